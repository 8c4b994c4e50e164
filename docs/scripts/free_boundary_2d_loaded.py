"""FreeBoundary2D against the lattice (bk.Lattice) in a loaded run: births, collisions,
the sequence of ruptures.

Run: nice -n 5 python docs/scripts/free_boundary_2d_loaded.py [--dx 0.2 0.1] [--json FILE]

The problem: a periodic square of side L = 16 (the paper's units), gamma = 0.3, loading
v = 0.02, from a smooth stress field below the threshold everywhere: u = 0.74 + 0.18 f,
f a fixed random combination of the Fourier modes of wavenumbers 2 pi (m, n)/L, |m|, |n| <=
2, normalised to max |f| = 1 (so u in [0.56, 0.92], above u_c = gamma: every front is a
pulse, nothing creeps). Several maxima reach the threshold within a sweep time of each
other, so ruptures are born at several places, expand, collide and annihilate; the
loading then brings the field back to the threshold and the next cycle begins.

That field is the stress: the lattice (blocks at (i dx, j dx)) starts stuck at rest with
the displacement u whose phi = u - Lap u (the force on a stuck block, which decides slip)
equals it at the blocks (solved exactly by FFT), and FreeBoundary2D is given it on the
same nodes (h = dx), with the chain's finite-dx speed law (bk.tip_solve at this dx, as in
free_boundary_2d_lattice.py) or the exact law. (Given u = the field instead, phi = u -
Lap u would differ from it by up to 0.2 here and cross the threshold at t = 0.)

The lattice's slips are split into ruptures by who started them: slips are taken in the
order they start; a slip takes the rupture of a neighbouring block (or its own block's
previous slip) that slipped within the last `GAP` time units, the earliest-started
first, else it is a birth. The ruptures are matched one to one with FreeBoundary2D's in
order of start (the nearest in (time, place) not matched yet; a match needs |dt| <
T_MATCH and a distance < X_MATCH). Compared: start time, place, area, moment (lattice:
dx^2 times the sum of its slips; FreeBoundary2D: the integral of u_+ - u_- over its area).
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import bkwaves as bk

L, GAMMA, V_LOAD, T_END = 12.0, 0.45, 0.02, 25.0
BASE, HEIGHT, SIGMA = 0.6, 0.31, 1.5
CENTRES = ((0.25, 0.25), (0.75, 0.375), (0.42, 0.79))
HEIGHTS = (1.0, 0.985, 0.975)
GAP = 2.0  # a slip continues a neighbour's rupture if that neighbour slipped this recently
T_MATCH, X_MATCH = 5.0, 3.0


def field(x, y, size=L, base=BASE, centres=CENTRES, heights=HEIGHTS, sigma=SIGMA):
    """The initial stress: ``base`` plus Gaussian bumps of width ``sigma`` at
    ``centres`` (fractions of the side) with relative ``heights`` (periodic: images
    included), scaled so that the largest value is ``base`` + HEIGHT."""
    f = np.zeros_like(x)
    for (fx, fy), hgt in zip(centres, heights, strict=True):
        cx, cy = fx * size, fy * size
        for sx in (-size, 0.0, size):
            for sy in (-size, 0.0, size):
                r2 = (x - cx - sx) ** 2 + (y - cy - sy) ** 2
                f += hgt * np.exp(-r2 / (2 * sigma**2))
    return base + HEIGHT * f / f.max()


def displacement(phi, dx):
    """The lattice's u whose stress u - Lap u (the five-point Laplacian at spacing dx on
    the periodic square) is ``phi``: solved exactly by FFT (the Laplacian's eigenvalues
    -(4/dx^2) (sin^2(k_x dx/2) + sin^2(k_y dx/2)))."""
    ny, nx = phi.shape
    kx = 2 * np.pi * np.fft.fftfreq(nx)
    ky = 2 * np.pi * np.fft.fftfreq(ny)
    lap = -(4 / dx**2) * (np.sin(ky[:, None] / 2) ** 2 + np.sin(kx[None, :] / 2) ** 2)
    return np.real(np.fft.ifft2(np.fft.fft2(phi) / (1.0 - lap)))


def speed_at(dx, gamma=GAMMA):
    """The chain's planar speed c(u_+) at spacing dx (bk.tip_solve) as a speed table."""
    u = np.concatenate([np.arange(0.5, 0.9, 0.04), [0.92, 0.94, 0.96, 0.975, 0.985]])
    u = u[u > gamma + 0.04]  # (the tip solver's range: pulses re-sticking well behind)
    return {"u_plus": list(u), "c": [bk.tip_solve(float(q), dx=dx, gamma=gamma)["c"] for q in u]}


def lattice_ruptures(slips, nx, ny, dx, gap=GAP, first=None):
    """Split the lattice's slip records into ruptures (module docstring): a list of dicts
    (t_start, i, j, area, moment, blocks) in order of start. If ``first`` (an int array
    of nx ny) is given, it receives the rupture of each block's first slip (-1 if none):
    the lattice's partition of the square by first arrival."""
    s = slips.sort_values(["t_start", "block"], kind="stable")
    blocks = s["block"].to_numpy()
    t0, t1 = s["t_start"].to_numpy(), s["t_end"].to_numpy()
    slip = s["slip"].to_numpy()
    last_t = np.full(nx * ny, -np.inf)  # per block: end of its last slip
    last_s = np.full(nx * ny, -np.inf)  # per block: start of its last slip
    last_r = np.full(nx * ny, -1)
    out = []
    seen = []
    for b, ta, tb, sl in zip(blocks, t0, t1, slip, strict=True):
        i, j = b % nx, b // nx
        cand = [b, j * nx + (i + 1) % nx, j * nx + (i - 1) % nx]
        cand += [((j + 1) % ny) * nx + i, ((j - 1) % ny) * nx + i]
        best, best_s = -1, np.inf
        for q in cand:
            if last_r[q] >= 0 and last_t[q] >= ta - gap and last_s[q] < best_s:
                best, best_s = last_r[q], last_s[q]
        if best < 0:
            best = len(out)
            out.append({"t_start": float(ta), "i": int(i), "j": int(j), "moment": 0.0})
            seen.append(set())
        out[best]["moment"] += sl * dx * dx
        seen[best].add(int(b))
        if first is not None and first[b] < 0:
            first[b] = best
        last_t[b], last_s[b], last_r[b] = max(last_t[b], tb), ta, best
    for r, bl in zip(out, seen, strict=True):
        r["blocks"] = len(bl)
        r["area"] = len(bl) * dx * dx
    return out


def periodic_distance(a, b, size=L):
    d = np.abs(np.asarray(a) - np.asarray(b))
    d = np.minimum(d, size - d)
    return float(np.hypot(*d))


def match(fb_rows, la_rows, size=L, t_match=T_MATCH, x_match=X_MATCH):
    """Pairs (k_fb, k_la) matched in order of start (module docstring), and the rows of
    each side left without a partner."""
    pairs, used = [], set()
    for k, r in enumerate(fb_rows):
        best, score = None, np.inf
        for m, q in enumerate(la_rows):
            if m in used:
                continue
            dt = abs(q["t_start"] - r["t_start"])
            dxy = periodic_distance((q["x"], q["y"]), (r["x"], r["y"]), size)
            if dt < t_match and dxy < x_match and dt + dxy < score:
                best, score = m, dt + dxy
        if best is not None:
            used.add(best)
            pairs.append((k, best))
    fb_left = sorted(set(range(len(fb_rows))) - {p[0] for p in pairs})
    la_left = sorted(set(range(len(la_rows))) - used)
    return pairs, fb_left, la_left


def run_lattice(dx, size=L, t_end=T_END, v=V_LOAD, gamma=GAMMA, lattice_kw=None, **fkw):
    n = int(round(size / dx))
    x = np.arange(n) * dx
    xx, yy = np.meshgrid(x, x)
    target = field(xx, yy, size=size, **fkw)
    u0 = displacement(target, dx)
    la = bk.Lattice(
        (n, n), bk.Params(gamma=gamma, v=v, dx=dx), u0=u0, boundary="periodic", **(lattice_kw or {})
    )
    phi = np.array(la.phi)
    assert np.abs(phi - target).max() < 1e-12, "the lattice's stress is the field"
    t0 = time.process_time()
    res = la.run(t_end=t_end, progress=False)
    cpu = time.process_time() - t0
    slips = res.slips.copy()
    # slips still running at the end (blocks near a hypocentre creep on): their slip so
    # far, v (t - t_start) - (u(t) - u_start)
    live = slips["slip"].isna().to_numpy()
    u_now = np.asarray(res.u).ravel()[slips["block"].to_numpy()[live]]
    slips.loc[live, "slip"] = v * (res.t - slips["t_start"][live]) - (
        u_now - slips["u_start"][live]
    )
    slips.loc[live, "t_end"] = res.t
    label = np.full(n * n, -1)
    rows = lattice_ruptures(slips, n, n, dx, first=label)
    for r in rows:
        r["x"], r["y"] = r["i"] * dx, r["j"] * dx
    return {"n": n, "phi": phi, "u0": u0, "rows": rows, "cpu_s": cpu, "t": res.t,
            "still_sliding": int(live.sum()), "phi_end": np.array(la.phi),
            "t_first": res.first_slip_times(), "label": label.reshape(n, n)}  # fmt: skip


def run_fb2d(dx, phi, speed, size=L, t_end=T_END, v=V_LOAD, gamma=GAMMA, **options):
    """FreeBoundary2D on the lattice's nodes (h = dx) from the stress ``phi``; ``options``
    go to the engine (``curvature=``, ``speed_diagonal=``, ``record_arrivals=``)."""
    n = phi.shape[0]
    p = bk.Params(gamma=gamma, v=v, dx=dx)
    t0 = time.process_time()
    fb = bk.FreeBoundary2D(p, (n, n), dx, phi, "periodic", speed=speed, **options)
    ru = fb.run(t_end=t_end).ruptures
    cpu = time.process_time() - t0
    u_end = fb.u()
    rows = [
        {"id": int(r.id), "t_start": float(r.t_start), "x": float(r.x_start), "y": float(r.y_start),
         "area": float(r.area), "moment": float(r.moment), "blocks": int(r.n_nodes),
         "origin": str(r.origin), "contacts": int(r.contacts), "complete": bool(r.complete)}
        for r in ru.itertuples()
    ]  # fmt: skip
    return {"rows": rows, "cpu_s": cpu, "u_end": u_end, "engine": fb}


def compare(la, fb, size=L):
    """The matched sequence and its differences (lattice - FreeBoundary2D)."""
    pairs, fb_left, la_left = match(fb["rows"], la["rows"], size)
    out = []
    for k, m in pairs:
        a, b = fb["rows"][k], la["rows"][m]
        out.append(
            {
                "fb": k,
                "lattice": m,
                "t_fb": a["t_start"],
                "dt": b["t_start"] - a["t_start"],
                "dplace": periodic_distance((a["x"], a["y"]), (b["x"], b["y"]), size),
                "area_fb": a["area"],
                "darea_rel": (b["area"] - a["area"]) / a["area"],
                "moment_fb": a["moment"],
                "dmoment_rel": (b["moment"] - a["moment"]) / a["moment"],
            }
        )
    big = [q for q in out if q["area_fb"] >= 1.0]
    summary = {
        "matched": len(pairs),
        "fb_ruptures": len(fb["rows"]),
        "lattice_ruptures": len(la["rows"]),
        "fb_unmatched": [fb["rows"][k] for k in fb_left],
        "lattice_unmatched": [la["rows"][m] for m in la_left],
        "max_abs_dt": max((abs(q["dt"]) for q in out), default=np.nan),
        "max_dplace": max((q["dplace"] for q in out), default=np.nan),
        "max_abs_darea_rel": max((abs(q["darea_rel"]) for q in big), default=np.nan),
        "max_abs_dmoment_rel": max((abs(q["dmoment_rel"]) for q in big), default=np.nan),
        "total_moment_rel": sum(r["moment"] for r in la["rows"])
        / sum(r["moment"] for r in fb["rows"])
        - 1.0,
        # the stress left at the end: the lattice's phi against FreeBoundary2D's u
        "end_stress_diff": {
            "median": float(np.median(np.abs(la["phi_end"] - fb["u_end"]))),
            "p90": float(np.percentile(np.abs(la["phi_end"] - fb["u_end"]), 90)),
            "max": float(np.abs(la["phi_end"] - fb["u_end"]).max()),
            "lattice_max": float(la["phi_end"].max()),
            "fb_max": float(fb["u_end"].max()),
            "mean": float(np.mean(la["phi_end"] - fb["u_end"])),
        },
    }
    return out, summary


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dx", type=float, nargs="+", default=[0.2, 0.1])
    ap.add_argument("--t-end", type=float, default=T_END)
    ap.add_argument(
        "--scale",
        type=float,
        default=1.0,
        help="the same free boundary problem s times larger: L, the bumps' width and "
        "t_end times s, v over s (FreeBoundary2D's answer scales exactly; the lattice's "
        "pulse width does not)",
    )
    ap.add_argument("--json")
    a = ap.parse_args()
    sc = a.scale
    size, v, t_end = L * sc, V_LOAD / sc, a.t_end * sc
    result = {"L": size, "gamma": GAMMA, "v": v, "t_end": t_end, "scale": sc,
              "sigma": SIGMA * sc, "runs": []}  # fmt: skip
    for dx in a.dx:
        la = run_lattice(dx, size=size, t_end=t_end, v=v, sigma=SIGMA * sc)
        run = {"dx": dx, "blocks": la["n"] ** 2, "lattice_cpu_s": la["cpu_s"],
               "still_sliding": la["still_sliding"], "lattice": la["rows"],
               "variants": {}}  # fmt: skip
        for name, speed in (("exact", None), ("chain_speed", speed_at(dx))):
            fb = run_fb2d(dx, la["phi"], speed, size=size, t_end=t_end, v=v)
            pairs, summary = compare(la, fb, size=size)
            run["variants"][name] = {"cpu_s": fb["cpu_s"], "fb": fb["rows"], "pairs": pairs,
                                     **summary}  # fmt: skip
            print(f"dx {dx} {name}: lattice cpu {la['cpu_s']:.1f} s, fb cpu {fb['cpu_s']:.3f} s")
            print("  fb", len(fb["rows"]), "lattice", len(la["rows"]), "matched", len(pairs))
            for q in pairs:
                print(
                    f"  t {q['t_fb']:8.3f} dt {q['dt']:+.3f} dplace {q['dplace']:.3f} "
                    f"area {q['area_fb']:8.2f} darea {q['darea_rel']:+.4f} "
                    f"dmoment {q['dmoment_rel']:+.4f}",
                    flush=True,
                )
            for key in ("fb_unmatched", "lattice_unmatched"):
                left = summary[key]
                if left:
                    print(f"  {key}: {len(left)}, total area "
                          f"{sum(r['area'] for r in left):.3g}, first at t = "
                          f"{min(r['t_start'] for r in left):.3f}")  # fmt: skip
            print(
                "  total moment lattice/fb - 1:",
                round(summary["total_moment_rel"], 4),
                "end stress",
                {k: round(q, 4) for k, q in summary["end_stress_diff"].items()},
            )
        result["runs"].append(run)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(result, f, indent=1)


if __name__ == "__main__":
    main()
