"""Print the tables of docs/theory.md (tip solver convergence, fits, finite dx).

Run: python docs/scripts/tip_tables.py
"""

import numpy as np

import bkwaves as bk
from bkwaves import theory as th


def closed(u):
    return 1.0 / np.sqrt(1.0 - u * u)


def convergence():
    print(
        "| u_+ | c (closed form) | degree 8 | degree 12 | degree 16 | degree 24"
        " | decay 20 | decay 60 |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for u in [0.02, 0.05, 0.2, 0.5, 0.8, 0.95, 0.999]:
        c0 = closed(u)
        row = [f"{u}", f"{c0:.15g}"]
        for kw in [
            dict(degree=8),
            dict(degree=12),
            dict(degree=16),
            dict(degree=24),
            dict(decay=20.0),
            dict(decay=60.0),
        ]:
            c = bk.tip_solve(u, **kw)["c"]
            row.append(f"{abs(c / c0 - 1):.1e}")
        print("| " + " | ".join(row) + " |")


def fits():
    c = np.linspace(2.5, 40.0, 80)
    theta = np.array([bk.tip_solve(c=x)["theta"] for x in c])
    x = 1.0 / c**2
    A = np.vstack([x**k for k in range(1, 9)]).T
    a = np.linalg.lstsq(A, theta, rcond=None)[0]
    exact = [1 / 2, 3 / 8, 5 / 16, 35 / 128, 63 / 256]
    print(
        "| coefficient of 1/c^(2k) | fitted from the tip solver | paper"
        " | binomial of 1/sqrt(1-x) - 1 |"
    )
    print("|---|---|---|---|")
    paper = ["1/2", "3/8", "5/16", "0.2719", "-"]
    for k in range(5):
        print(f"| k = {k + 1} | {a[k]:.6f} | {paper[k]} | {exact[k]:.6f} |")
    u = np.linspace(0.02, 0.08, 7)
    cc = np.array([bk.tip_solve(v)["c"] for v in u])
    coef = np.polyfit(u**2, (cc - 1) / u**2, 2)
    print(f"\nsmall u_+: (c - 1)/u_+^2 -> {coef[-1]:.8f} (eq. c1: 1/2; closed form: 1/2)")


def interpolation():
    u = np.linspace(0.01, 0.99, 981)
    d = th.c_interpolation(u) / closed(u) - 1
    i = np.argmax(np.abs(d))
    print(f"\ninterpolation eq. (c): max |rel. error| = {abs(d[i]):.4f} at u_+ = {u[i]:.3f}")


def _outside_chain_domain(u, dx, gamma):
    try:
        bk.tip_solve(u, dx=dx, gamma=gamma)
    except bk.ParameterError:
        return True
    return False


def finite_dx():
    print(
        "| gamma | u_+ | dx = 0.1 | 0.05 | 0.025 | 0.0125 | order"
        " | Richardson dx->0 | c continuum |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for g in [0.0, 0.3, 0.45]:
        for u in [0.3, 0.5, 0.7, 0.9]:
            if u <= g:
                continue
            dxs = [0.1, 0.05, 0.025, 0.0125]
            # the tip problem itself (chain_domain=False): an asterisk marks a speed that is
            # not the chain's (narrow pulse, docs/theory.md "Narrow pulses")
            cs = [bk.tip_solve(u, dx=h, gamma=g, chain_domain=False)["c"] for h in dxs]
            mark = [_outside_chain_domain(u, h, g) for h in dxs]
            p = np.log2((cs[1] - cs[2]) / (cs[2] - cs[3]))
            # two levels of Richardson: remove the dx^p and the next dx^(p+1) terms
            # (gamma > 0: c = c0 + a dx + b dx^2; gamma = 0: only even powers)
            p1 = round(p)
            p2 = p1 + (2 if g == 0.0 else 1)
            r1 = [cs[i + 1] + (cs[i + 1] - cs[i]) / (2**p1 - 1) for i in range(3)]
            rich = r1[2] + (r1[2] - r1[1]) / (2**p2 - 1)
            row = [f"{g}", f"{u}"] + [
                f"{c:.8f}" + ("*" if m else "") for c, m in zip(cs, mark, strict=True)
            ]
            row += [f"{p:.3f}", f"{rich:.9f}", f"{closed(u):.9f}"]
            print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    convergence()
    print()
    fits()
    interpolation()
    print()
    finite_dx()
