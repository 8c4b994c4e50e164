"""Where the first healing front stalls, and what sets it (docs/lattice.md, "Derived and
measured: where the first healing stalls").

The claim: a healing front (the edge of the re-stuck region behind a rupture) stops where it
meets the sound cone of the collision of two rupture fronts. The two fronts meet at (x_m,
t_m); nothing that happens there reaches x before t_m + |x - x_m| (the sliding equation's
characteristics have speed 1, the fronts are supersonic and the stuck ground ahead of them
carries no signal), so up to that cone each front's healing is its own, and inside it the
other pulse's slip keeps the blocks sliding past their first backswing. The stall is at
distance d from the collision point where the front's own healing line t_h(x) crosses
t_m + |x - x_m|:

    d = T c / (1 + c)                 (exact, T the local slip duration, c the front speed)
    d ~ w(u_+) / (1 + c(u_+))         (the steady pulse: T = w/c; u_+ the stress met there)

Measured on the loaded ring of docs/scripts/lattice_later_ruptures.py (side 24, two bumps of
width 3, gamma = 0.45, v = 0.01) and on variations, one thing at a time. Per run:

- t_r, t_h: every block's first slip and first stick times (located events of bk.Chain);
- hypocentres (minima of t_r) and collisions (maxima of t_r; (x_m, t_m) from straight lines
  fitted to t_r over 0.2-1 on each side, c_m the fronts' speeds there);
- the stall on each side of a collision: going out from the hypocentre, the first pair of
  neighbours whose first sticks are more than THRESHOLD apart, for each THRESHOLD of
  --thresholds (its position must not depend on it);
- the cone's prediction: the healing line fitted to t_h over 0.6 before the stall, met with
  t_m + |x - x_m| (parameter-free given the front's own healing);
- the pulse's prediction: w/(1 + c) of bk.traveling_wave at u_+ = phi_0(x_m) + v t_m (the
  stress ahead of the fronts where they meet; phi of a stuck block grows at v exactly).

- the kick: the jump of s_t (s = v - u_t) where the cone passes a block 1 from the
  collision, measured (quadratics fitted on each side) and predicted (cone_jump), and,
  where the healing line meets the cone, that jump against a, the rate at which s falls to
  zero there: a stall needs the jump to win (s turns up before it reaches zero).

Run: nice -n 5 python docs/scripts/healing_stall.py --dx 0.025 0.0125 0.00625 --json
docs/healing_stall.json (about 40 s of CPU); --table --json FILE prints the table;
--figure PNG --json FILE draws docs/figures/beyond_healing_stall.png.
A run with --json keeps the (case, dx) already in FILE (an interrupted run resumes).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import bkwaves as bk

BASE = {"side": 24.0, "bumps": [[0.25, 1.0], [0.75, 0.985]], "sigma": 3.0, "base": 0.6,
        "height": 0.31, "gamma": 0.45, "v": 0.01}  # fmt: skip
CASES = {
    "base": {},
    "width 2": {"sigma": 2.0},
    "width 4.5": {"sigma": 4.5},
    "peak 0.85": {"height": 0.25},
    "peak 0.95": {"height": 0.35},
    "gamma 0.3": {"gamma": 0.3},
    "gamma 0.6": {"gamma": 0.6},
    "v 0.005": {"v": 0.005},
    "v 0.02": {"v": 0.02},
    "single bump": {"bumps": [[0.25, 1.0]]},
    "side 36": {"side": 36.0},
}
CROSSOVER = {  # fronts that meet near K = a (kick_over_rate = 1)
    "width 3.75": {"sigma": 3.75},
    "width 4": {"sigma": 4.0},
    "gamma 0.3, width 3.25": {"gamma": 0.3, "sigma": 3.25},
    "gamma 0.3, width 3.5": {"gamma": 0.3, "sigma": 3.5},
    "gamma 0.3, width 3.75": {"gamma": 0.3, "sigma": 3.75},
    "gamma 0.6, width 4": {"gamma": 0.6, "sigma": 4.0},
    "gamma 0.6, width 4.25": {"gamma": 0.6, "sigma": 4.25},
}
ALL_CASES = {**CASES, **CROSSOVER}
THRESHOLDS = (0.25, 0.5, 0.75)
FIT_HEAL = 0.6  # the healing line is fitted over this length before the stall


def ring(dx, side, bumps, sigma, base, height, gamma, v):
    """A periodic chain at the stress phi_0 = base + height * (sum of Gaussian bumps of
    width sigma at the fractions `bumps` of the side, normalised to a peak of 1), set
    exactly as phi = u - Lap u by FFT. Returns (chain, x, phi_0)."""
    n = int(round(side / dx))
    x = np.arange(n) * dx
    f = np.zeros(n)
    for c, h in bumps:
        for sh in (-side, 0.0, side):
            f += h * np.exp(-((x - c * side - sh) ** 2) / (2 * sigma**2))
    target = base + height * f / f.max()
    lap = -(4 / dx**2) * np.sin(np.pi * np.fft.fftfreq(n)) ** 2
    u0 = np.real(np.fft.ifft(np.fft.fft(target) / (1.0 - lap)))
    ch = bk.Chain(n, bk.Params(gamma=gamma, v=v, dx=dx), u0=u0, boundary="periodic")
    return ch, x, target


def first_times(slips, n):
    """Each block's first slip start and first stick (NaN for a block that never slipped
    or is still in its first slip)."""
    first = slips.sort_values("t_start").groupby("block").first()
    tr, th = np.full(n, np.nan), np.full(n, np.nan)
    tr[first.index] = first["t_start"].to_numpy(dtype=float)
    th[first.index] = first["t_end"].to_numpy(dtype=float)
    return tr, th


def kick_over_rate(c, gamma):
    """K/a where a steady pulse's healing line meets the collision's cone: K = c u_+/(c^2 -
    1) exp(-gamma d) with d = w/(1 + c), a = c^2 |u_-|/(c^2 - 1) (the pulse's healing rate),
    u_- and w of eqs. (um), (w): u_+ cancels and K/a = exp(pi gamma / S)/c, S = sqrt(c^2 (1 -
    gamma^2) - 1). Above 1 the kick turns the slip speed up before it reaches zero."""
    s2 = c * c * (1 - gamma * gamma) - 1
    return float("inf") if s2 <= 0 else float(np.exp(np.pi * gamma / np.sqrt(s2)) / c)


def _line(xs, ts):
    return np.polyfit(xs, ts, 1)


def collisions(x, tr, side):
    """The meetings of two rupture fronts: blocks whose first slip is later than both
    neighbours'; (x_m, t_m) from lines fitted over 0.2-1 on each side (the ring unrolled
    about x_m), and the two fronts' speeds there."""
    out = []
    n = len(x)
    for k in np.where((tr > np.roll(tr, 1)) & (tr >= np.roll(tr, -1)))[0]:
        rel = (x - x[k] + side / 2) % side - side / 2
        left, right = (rel > -1.0) & (rel < -0.2), (rel > 0.2) & (rel < 1.0)
        pl, pr = _line(rel[left], tr[left]), _line(rel[right], tr[right])
        xr = (pr[1] - pl[1]) / (pl[0] - pr[0])
        out.append({"k": int(k), "x": float((x[k] + xr) % side), "rel": float(xr),
                    "t": float(np.polyval(pl, xr)), "c_left": float(1 / pl[0]),
                    "c_right": float(-1 / pr[0])})  # fmt: skip
    assert all(0 <= c["k"] < n for c in out)
    return out


def stall_toward(x, tr, th, col, side, direction, dx, thresholds=THRESHOLDS):
    """The stall of the healing front that runs toward the collision ``col`` from the side
    ``direction`` (-1: from smaller x): scanning from the hypocentre (the nearest minimum of
    t_r on that side) toward the collision, the first neighbours whose first sticks differ
    by more than each threshold. Distances are from the collision point."""
    n = len(x)
    k = col["k"]
    # walk from the collision toward the hypocentre while t_r falls
    path = [k]
    while True:
        q = (path[-1] + direction) % n
        if not tr[q] < tr[path[-1]] or len(path) > n // 2:
            break
        path.append(q)
    path = path[::-1]  # hypocentre ... collision
    d_of = np.array([abs(((x[q] - col["x"]) + side / 2) % side - side / 2) for q in path])
    ths = th[path]
    out = {"hypocentre_distance": float(d_of[0]), "t_hypocentre": float(tr[path[0]])}
    steps = np.abs(np.diff(ths))
    kmax = int(np.nanargmax(steps))  # the largest step, stall or not
    out.update(max_jump=float(steps[kmax]), d_max_jump=float(d_of[kmax] - dx / 2))
    found = {}
    for thr in thresholds:
        jumps = np.where(np.abs(np.diff(ths)) > thr)[0]
        found[thr] = None if len(jumps) == 0 else int(jumps[0])
    out["d_by_threshold"] = {str(t): (None if j is None else float(d_of[j] - dx / 2))
                             for t, j in found.items()}  # fmt: skip
    j = found[0.5]
    if j is None:
        return out
    i = path[j]
    out.update(d=float(d_of[j] - dx / 2), jump=float(ths[j + 1] - ths[j]),
               t_stick=float(th[i]), t_slip=float(tr[i]), duration=float(th[i] - tr[i]),
               cone_time=float(col["t"] + d_of[j]))  # fmt: skip
    fit = (d_of[: j + 1] < d_of[j] + FIT_HEAL) & np.isfinite(ths[: j + 1])
    p = _line(d_of[: j + 1][fit], ths[: j + 1][fit])  # t_h = p0 d + p1
    out["c_heal"] = float(-1 / p[0])
    out["d_cone"] = float((p[1] - col["t"]) / (1 - p[0]))  # p0 d + p1 = t_m + d
    c_m = col["c_left"] if direction < 0 else col["c_right"]
    out["d_duration"] = float(out["duration"] * c_m / (1 + c_m))
    return out


def cone_jump(c_left, c_right, u_plus):
    """The jump of s_t = -u_tt (s = v - u_t, the speed over the ground) across the sound
    cone, at the collision of two fronts of speeds c_left, c_right (the one from the left
    moving right) into the stress u_plus, on the side of the front from the left: each
    front makes u_tt jump by J = -c^2 u_+/(c^2 - 1) (continuity of u, u_t across it), and
    the local solution about the corner gives (1/2)|J_L| (1/c_L + 1/c_R)(1 - 1/c_L)/(1 -
    1/c_R) on the left-going characteristic (|J|/c for equal speeds). Along it the jump
    decays as exp(-gamma t)."""
    j = c_left**2 * u_plus / (c_left**2 - 1)
    return 0.5 * j * (1 / c_left + 1 / c_right) * (1 - 1 / c_left) / (1 - 1 / c_right)


def measure_kick(p, dx, col, stall, x, tr, th, d_probe=1.0, frame=0.0025, win=(0.05, 0.2)):
    """On the front from the left of ``col``: the jump of s_t where the cone passes the
    block d_probe from the collision (quadratics fitted to s on each side, over ``win``
    from the cone, their slopes at it), and a, the rate at which s falls to zero where the
    healing line meets the cone (a line fitted to s over 0.02-0.12 before the first stick
    of the last block that sticks before the cone reaches it)."""
    n = len(x)
    i_probe = int(round((col["x"] - d_probe) / dx)) % n
    # the healing line meets the cone: the block nearest the collision, on the
    # hypocentre's side, that sticks before the cone reaches it
    dist = np.abs(((x - col["x"]) + p["side"] / 2) % p["side"] - p["side"] / 2)
    left = (((x - col["x"]) + p["side"] / 2) % p["side"] - p["side"] / 2) < 0
    before = left & (dist < stall["hypocentre_distance"]) & (th < col["t"] + dist)
    i_star = int(np.where(before)[0][np.argmin(dist[before])])
    d_star = float(dist[i_star])
    t_probe = col["t"] + d_probe
    t_star = th[i_star]
    ch, _, _ = ring(dx, **p)
    t0 = min(t_probe - win[1], t_star - 0.12) - 0.01
    t1 = max(t_probe + win[1], t_star) + 0.01
    ch.run(t_end=t0, progress=False)
    ts = np.arange(t0, t1, frame)
    s = []
    for t in ts:
        ch.run(t_end=float(t), progress=False)
        u_t = np.asarray(ch.u_t)
        s.append((p["v"] - u_t[i_probe], p["v"] - u_t[i_star]))
    s = np.array(s)

    def slope(k, lo, hi, deg, at):
        sel = (ts > lo) & (ts < hi)
        q = np.polyfit(ts[sel] - at, s[sel, k], deg)
        return float(np.polyval(np.polyder(q), 0.0))

    jump = (slope(0, t_probe + win[0], t_probe + win[1], 2, t_probe)
            - slope(0, t_probe - win[1], t_probe - win[0], 2, t_probe))  # fmt: skip
    a = -slope(1, t_star - 0.12, t_star - 0.02, 1, t_star)
    k0 = cone_jump(col["c_left"], col["c_right"], col["u_plus"])
    return {"d_probe": d_probe, "jump_measured": jump,
            "jump_predicted": k0 * np.exp(-p["gamma"] * d_probe), "k0": k0, "d_star": d_star,
            "a": a, "jump_at_star": k0 * np.exp(-p["gamma"] * d_star)}  # fmt: skip


def run_case(name, dx, over, kick=False):
    p = {**BASE, **over}
    ch, x, phi0 = ring(dx, **p)
    t_nuc = (1 - phi0.max()) / p["v"]
    t_end = t_nuc + 14.0
    c0 = time.process_time()
    slips = ch.run(t_end=t_end, progress=False).slips
    cpu = time.process_time() - c0
    tr, th = first_times(slips, len(x))
    out = {"case": name, "dx": dx, "params": p, "t_nucleation": float(np.nanmin(tr)),
           "cpu_s": cpu, "t_end": t_end, "never_slipped": int(np.isnan(tr).sum()),
           "collisions": []}  # fmt: skip
    for col in collisions(x, tr, p["side"]):
        u_plus = float(np.interp(col["x"], x, phi0, period=p["side"]) + p["v"] * col["t"])
        wave = bk.traveling_wave(u_plus, p["gamma"])
        entry = {**col, "u_plus": u_plus, "c": wave.c, "regime": wave.regime,
                 "w": wave.w, "d_pulse": (wave.w / (1 + wave.c) if wave.w else None),
                 "kick_over_rate_pulse": kick_over_rate(wave.c, p["gamma"]),
                 "sides": {}}  # fmt: skip
        for direction in (-1, 1):
            entry["sides"][str(direction)] = stall_toward(x, tr, th, col, p["side"],
                                                          direction, dx)  # fmt: skip
        out["collisions"].append(entry)
    if kick:
        col = out["collisions"][0]
        out["kick"] = measure_kick(p, dx, col, col["sides"]["-1"], x, tr, th)
    return out


def rows(out):
    """One row per (case, dx, collision side)."""
    for r in out["runs"]:
        for col in r["collisions"]:
            for side, s in col["sides"].items():
                yield r, col, side, s


def fmt(q):
    return "-" if q is None else f"{q:.3f}"


def table(out):
    """One row per case and stalled front (the fronts from the bump at 0.25 of the side,
    then from the other): the stall's distance d from the collision at every dx, and the
    predictions (the cone's and T c/(1 + c) at the finest dx)."""
    by = {}
    for r, col, side, s in rows(out):
        by.setdefault((r["case"], round(col["x"]), side), []).append((r, col, s))
    dxs = sorted({r["dx"] for r in out["runs"]}, reverse=True)
    head = ", ".join(str(d) for d in dxs)
    lines = [f"| case | u_+, c where the fronts meet | hypocentre to collision D | stall d at dx = "
             f"{head} (thresholds 0.25-0.75 agree) | D - d | cone: d | T c/(1+c) | "
             f"pulse: w/(1+c) | jump of s_t at the cone, d = 1: measured, predicted | at the "
             f"meeting: the jump K, the healing rate a |",
             "|---|---|---|---|---|---|---|---|---|---|"]  # fmt: skip
    seen = set()
    for (case, _xk, side), items in by.items():
        items.sort(key=lambda q: -q[0]["dx"])
        r, col, s = items[-1]
        key = (case, round(s["hypocentre_distance"], 1))
        if key in seen:  # the mirror image of a front already listed
            continue
        seen.add(key)
        kk = "- | -"
        if "kick" in r and r["collisions"][0] is col and side == "-1":
            k = r["kick"]
            kk = (f"{k['jump_measured']:.3f}, {k['jump_predicted']:.3f} | "
                  f"{k['jump_at_star']:.3f}, {k['a']:.3f}")  # fmt: skip
        ds = []
        for _r, _c, q in items:
            dt = set(q["d_by_threshold"].values())
            ds.append(fmt(q.get("d")) if len(dt) == 1 else "thresholds differ")
        if s.get("d") is None:
            ds = [f"none (largest first-stick step {s['max_jump']:.2f}, at {s['d_max_jump']:.2f})"]
        lines.append(f"| {case} | {col['u_plus']:.3f}, {col['c']:.2f} | "
                     f"{s['hypocentre_distance']:.2f} | {', '.join(ds)} | "
                     f"{fmt(s.get('d') and s['hypocentre_distance'] - s['d'])} | "
                     f"{fmt(s.get('d_cone'))} | {fmt(s.get('d_duration'))} | "
                     f"{fmt(col['d_pulse'])} | {kk} |")  # fmt: skip
    return lines


def figure(out, path, dx=0.0125):
    """docs/figures/beyond_healing_stall.png. Left: the base ring between the higher bump's
    hypocentre and the collision of its front with the other bump's: first slip and first
    stick times against x, the collision's sound cone, the stall. Right: every stall's
    distance from its collision at the finest dx of ``out`` against the cone's prediction
    and the steady pulse's w/(1 + c)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = dict(BASE)
    ch, x, _ = ring(dx, **p)
    tr, th = first_times(ch.run(t_end=16.0, progress=False).slips, len(x))
    col = min(collisions(x, tr, p["side"]), key=lambda c: abs(c["x"] - 12.0))
    st = stall_toward(x, tr, th, col, p["side"], -1, dx)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    sel = (x > 4.0) & (x < 14.0)
    ax[0].plot(x[sel], tr[sel], "-", lw=1.2, label="first slip $t_r(x)$")
    ax[0].plot(x[sel], th[sel], ".", ms=1.5, label="first stick $t_h(x)$")
    xs = np.linspace(col["x"] - 3.0, col["x"] + 1.5, 50)
    ax[0].plot(xs, col["t"] + np.abs(xs - col["x"]), "k--", lw=0.8,
               label="sound cone $t_m + |x - x_m|$")  # fmt: skip
    x_stall = col["x"] - st["d"]
    ax[0].axvline(x_stall, color="0.5", lw=0.8, ls=":")
    ax[0].annotate("stall", (x_stall, st["t_stick"]), (x_stall - 2.2, st["t_stick"] + 1.0),
                   arrowprops={"arrowstyle": "->", "lw": 0.7})  # fmt: skip
    ax[0].set_xlabel("$x$")
    ax[0].set_ylabel("$t$")
    ax[0].set_ylim(8.5, 16.0)
    ax[0].legend(fontsize=8, loc="lower right")
    finest = min(r["dx"] for r in out["runs"])
    d, cone, pulse = [], [], []
    for r, c, _side, s in rows(out):
        if r["dx"] == finest and s.get("d") is not None:
            d.append(s["d"])
            cone.append(s["d_cone"])
            pulse.append(c["d_pulse"])
    lo, hi = 1.6, 2.9
    ax[1].plot([lo, hi], [lo, hi], "k-", lw=0.6)
    ax[1].plot(cone, d, "o", ms=4, label="sound cone (the healing line met with it)")
    ax[1].plot(pulse, d, "s", ms=4, mfc="none", label="steady pulse $w/(1+c)$")
    ax[1].set_xlim(lo, hi)
    ax[1].set_ylim(lo, hi)
    ax[1].set_xlabel("predicted $d$")
    ax[1].set_ylabel(f"measured $d$ ($\\Delta x = {finest}$)")
    ax[1].legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return st, col


def crossover_table(out):
    """The front from the bump at 0.25 of the side in each case: K/a, closed form and
    measured, and the largest step of first-stick times at each dx."""
    dxs = sorted({r["dx"] for r in out["runs"]}, reverse=True)
    lines = ["| case | u_+, c where the fronts meet | K/a: steady pulse, measured (dx = "
             f"{dxs[-1]}) | largest step of first sticks at dx = "
             f"{', '.join(str(d) for d in dxs)} | its distance from the collision |",
             "|---|---|---|---|---|"]  # fmt: skip
    cases = list(dict.fromkeys(r["case"] for r in out["runs"]))
    for case in cases:
        rs = sorted((r for r in out["runs"] if r["case"] == case), key=lambda r: -r["dx"])
        col = rs[-1]["collisions"][0]
        k = rs[-1].get("kick")
        meas = fmt(k["jump_at_star"] / k["a"]) if k else "-"
        steps = ", ".join(f"{r['collisions'][0]['sides']['-1']['max_jump']:.2f}" for r in rs)
        lines.append(f"| {case} | {col['u_plus']:.3f}, {col['c']:.2f} | "
                     f"{col['kick_over_rate_pulse']:.2f}, {meas} | {steps} | "
                     f"{rs[-1]['collisions'][0]['sides']['-1']['d_max_jump']:.2f} |")  # fmt: skip
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dx", type=float, nargs="+", default=[0.025, 0.0125])
    ap.add_argument("--cases", nargs="+", default=list(CASES), choices=list(ALL_CASES))
    ap.add_argument("--crossover", action="store_true", help="the CROSSOVER cases")
    ap.add_argument("--json")
    ap.add_argument("--table", action="store_true", help="print the table of --json, run nothing")
    ap.add_argument("--figure", help="with --json: draw the figure of docs/lattice.md to FILE")
    a = ap.parse_args()
    if a.figure:
        figure(json.loads(Path(a.json).read_text()), a.figure)
        return
    if a.table:
        out = json.loads(Path(a.json).read_text())
        print("\n".join(crossover_table(out) if out.get("crossover") else table(out)))
        return
    if a.crossover:
        a.cases = list(CROSSOVER)
    out = {"base": BASE, "thresholds": THRESHOLDS, "crossover": a.crossover, "runs": []}
    if a.json and Path(a.json).exists():
        out["runs"] = json.loads(Path(a.json).read_text())["runs"]
    done = {(r["case"], r["dx"]) for r in out["runs"]}
    for name in a.cases:
        for dx in a.dx:
            if (name, dx) in done:
                continue
            r = run_case(name, dx, ALL_CASES[name], kick=True)
            out["runs"].append(r)
            print(f"{name} dx {dx}: cpu {r['cpu_s']:.1f} s, collisions "
                  f"{[round(c['x'], 3) for c in r['collisions']]}", flush=True)  # fmt: skip
            if a.json:
                Path(a.json).write_text(json.dumps(out, indent=1))
    print("\n".join(crossover_table(out) if a.crossover else table(out)))


if __name__ == "__main__":
    main()
