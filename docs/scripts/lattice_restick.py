"""Why the lattice starts new slips early after the first cycle of the loaded run
(docs/free_boundary_2d.md, "Against the lattice: a loaded run"; docs/lattice.md,
"Measured: stress left by an irregular healing").

Run: nice -n 5 python docs/scripts/lattice_restick.py [--dx 0.2 0.1] [--step 0.05 0.025]
[--json docs/lattice_restick.json]

The loaded square of docs/scripts/free_boundary_2d_loaded.py (side 12, gamma = 0.45,
v = 0.02, three bumps) is run in pieces of 0.05 time units and the modes, u, u_t and phi of
every block are kept. Measured, per block, from its first slip (the first cycle):

- the settled stress: phi at the first frame at which the block and its four neighbours
  are all stuck again;
- the tail's slip after the block stuck: the sum over its neighbours of their slip over
  the ground from the block's stick to the end of their own first slip. A stuck block's
  phi = u - Lap u gains that sum over dx^2 (plus v per unit time): the spring to a
  neighbour that slides on stretches by the neighbour's slip;
- the stress u_+ met by the front (the field plus v t at the first slip) and the planar
  pulse's re-sticking velocity v_c(u_+) there (bk.theory.restick_velocity, the chain's c
  at this dx);
- the blocks still sliding at the end, against the creep state of a lone sliding block
  whose four neighbours are stuck: s = v - u_t = v/(1 + 4/dx^2), phi = 2 gamma s.

Each dx is run at each step; the slip sequences at two steps are compared. The 1D
check: a ring of the same side, gamma, v and base with two of the bumps (those at 0.25
and 0.75 of the side), stress set by FFT the same way, run to t = 25: the settled
stress and the slips after the first cycle.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

import bkwaves as bk

sys.path.insert(0, str(Path(__file__).resolve().parent))
import free_boundary_2d_loaded as fbl  # noqa: E402

FRAME = 0.05  # time between recorded frames
NBRS = ((0, 1), (0, -1), (1, 0), (-1, 0))


def run(dx: float, step: float, t_end: float, v: float = fbl.V_LOAD) -> dict:
    n = int(round(fbl.L / dx))
    x = np.arange(n) * dx
    xx, yy = np.meshgrid(x, x)
    target = fbl.field(xx, yy)
    la = bk.Lattice(
        (n, n),
        bk.Params(gamma=fbl.GAMMA, v=v, dx=dx),
        u0=fbl.displacement(target, dx),
        boundary="periodic",
        step=step,
    )
    fr: dict[str, list] = {"t": [], "mode": [], "u": [], "phi": [], "u_t": []}
    t0 = time.process_time()
    for t in np.arange(FRAME, t_end + 1e-9, FRAME):
        res = la.run(t_end=float(t), progress=False)
        fr["t"].append(res.t)
        fr["mode"].append(np.array(la.modes, dtype=np.int8))
        fr["u"].append(np.array(la.u))
        fr["phi"].append(np.array(la.phi))
        fr["u_t"].append(np.array(la.u_t))
    out = {k: np.array(q) for k, q in fr.items()}
    out.update(target=target, slips=res.slips, energy=res.energy, n=n,
               cpu_s=time.process_time() - t0)  # fmt: skip
    return out


def shifted(a, di, dj, axes=(0, 1)):
    return np.roll(np.roll(a, di, axes[0]), dj, axes[1])


def analyse(r: dict, dx: float, v: float = fbl.V_LOAD) -> dict:
    g, n = fbl.GAMMA, r["n"]
    t, mode, phi, u, u_t = r["t"], r["mode"], r["phi"], r["u"], r["u_t"]
    s = r["slips"]
    first = s.sort_values("t_start").groupby("block").first()
    grid = np.full(n * n, np.nan)

    def per_block(col):
        a = grid.copy()
        a[first.index] = first[col]
        return a.reshape(n, n)

    t_slip, t_stick, u_stick = per_block("t_start"), per_block("t_end"), per_block("u_end")
    idx = np.arange(n)
    # settled stress: the block and its neighbours all stuck, after its first slip
    stuck5 = mode == 0
    for di, dj in NBRS:
        stuck5 &= shifted(mode, di, dj, (1, 2)) == 0
    ok = stuck5 & (t[:, None, None] > np.nan_to_num(t_slip, nan=np.inf)[None] + 0.5)
    k = np.argmax(ok, axis=0)
    settled = np.where(ok.any(axis=0), phi[k, idx[:, None], idx[None, :]], np.nan)
    # the tail's slip after the block stuck (neighbours' first slips)
    kst = np.clip(np.searchsorted(t, np.nan_to_num(t_stick, nan=np.inf)), 0, len(t) - 1)
    tk = t[kst]
    tail = np.zeros((n, n))
    for di, dj in NBRS:
        tn, un_end = shifted(t_stick, di, dj), shifted(u_stick, di, dj)
        un = shifted(u, di, dj, (1, 2))[kst, idx[:, None], idx[None, :]]
        rel = np.where(tn > tk, v * (tn - tk) - (un_end - un), 0.0)
        tail += np.clip(np.nan_to_num(rel), 0.0, None)
    good = np.isfinite(t_stick) & np.isfinite(settled)
    gain = tail[good] / dx**2
    # u_+ met by the front and the planar pulse's v_c there
    u_plus = (r["target"] + v * t_slip)[np.isfinite(t_slip)]
    lo = float(u_plus.min())
    vc_lo = float(bk.theory.restick_velocity(lo, g, c=bk.front_speed(lo, dx=dx, gamma=g)))
    # the creep boundary under load, u_c(v), with the chain's c: bisection in (0.5, 0.95)
    # (bk.theory.critical_stress_under_load's bracket starts at u_c(0), below the tip
    # solver's range at dx = 0.1)
    a, b = 0.5, 0.95
    for _ in range(40):
        mid = 0.5 * (a + b)
        vc = bk.theory.restick_velocity(mid, g, c=bk.front_speed(mid, dx=dx, gamma=g))
        a, b = (mid, b) if vc < v else (a, mid)
    u_c_v = 0.5 * (a + b)
    # blocks still sliding at the end
    last = mode[-1] == 1
    s_end = (v - u_t[-1])[last]
    late = s[s.t_start > float(np.nanmax(t_stick[np.isfinite(t_stick)]))]
    dur = (t_stick - t_slip)[np.isfinite(t_stick)]
    return {
        "dx": dx,
        "blocks": n * n,
        "slips": len(s),
        "cpu_s": r["cpu_s"],
        "energy_residual": float(r["energy"]["residual"]),
        "viscous_work": float(r["energy"]["viscous_work"]),
        "settled_phi": {
            "median": float(np.nanmedian(settled)),
            "frac_above_0.45": float(np.nanmean(settled > 0.45)),
            "max": float(np.nanmax(settled)),
        },
        "tail_slip_after_stick": {
            "p50": float(np.percentile(tail[good], 50)),
            "p99": float(np.percentile(tail[good], 99)),
            "gain_p90": float(np.percentile(gain, 90)),
            "gain_p99": float(np.percentile(gain, 99)),
            "gain_max": float(gain.max()),
            "frac_gain_above_0.5": float(np.mean(gain > 0.5)),
            "frac_gain_above_1": float(np.mean(gain > 1.0)),
        },
        "first_slip_duration": {"median": float(np.median(dur)), "max": float(dur.max())},
        "u_plus_min": lo,
        "restick_velocity_at_u_plus_min": vc_lo,
        "critical_stress_under_load": float(u_c_v),
        "still_sliding_at_end": int(last.sum()),
        "still_sliding_s": [float(q) for q in s_end],
        "creep_s_theory": v / (1 + 4 / dx**2),
        "slips_after_last_first_stick": len(late),
        "sliding_with_u_t_above_v": int(((mode == 1) & (u_t > v + 1e-9)).sum()),
        "_slips": s,
        "_modes": mode,
    }


def ring(dx: float, t_end: float = 25.0) -> dict:
    """The 1D check (module docstring)."""
    n = int(round(fbl.L / dx))
    x = np.arange(n) * dx
    f = np.zeros(n)
    for c, h in ((0.25, 1.0), (0.75, 0.985)):
        for sh in (-fbl.L, 0.0, fbl.L):
            f += h * np.exp(-((x - c * fbl.L - sh) ** 2) / (2 * fbl.SIGMA**2))
    target = fbl.BASE + fbl.HEIGHT * f / f.max()
    lap = -(4 / dx**2) * np.sin(np.pi * np.fft.fftfreq(n)) ** 2
    u0 = np.real(np.fft.ifft(np.fft.fft(target) / (1.0 - lap)))
    ch = bk.Chain(n, bk.Params(gamma=fbl.GAMMA, v=fbl.V_LOAD, dx=dx), u0=u0,
                  boundary="periodic")  # fmt: skip
    ts = np.arange(FRAME, t_end + 1e-9, FRAME)
    modes, phis = [], []
    for t in ts:
        res = ch.run(t_end=float(t), progress=False)
        modes.append(np.array(ch.modes))
        phis.append(np.array(ch.phi))
    mode, phi = np.array(modes), np.array(phis)
    s = res.slips
    first = s.sort_values("t_start").groupby("block").first()
    t_slip = np.full(n, np.inf)
    t_slip[first.index] = first.t_start
    ok = (mode == 0) & (np.roll(mode, 1, 1) == 0) & (np.roll(mode, -1, 1) == 0)
    ok &= ts[:, None] > t_slip[None] + 0.5
    k = np.argmax(ok, axis=0)
    settled = np.where(ok.any(axis=0), phi[k, np.arange(n)], np.nan)
    later = s[s.t_start > first.t_end.max()]
    return {
        "dx": dx,
        "blocks": n,
        "t_end": t_end,
        "settled_phi": {
            "median": float(np.nanmedian(settled)),
            "frac_above_0.45": float(np.nanmean(settled > 0.45)),
            "max": float(np.nanmax(settled)),
        },
        "first_slip_duration_max": float((first.t_end - first.t_start).max()),
        "slips_after_first_cycle": len(later),
        "still_sliding_at_end": int(s.t_end.isna().sum()),
        "energy_residual": float(res.energy["residual"]),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dx", type=float, nargs="+", default=[0.2, 0.1])
    ap.add_argument("--step", type=float, nargs="+", default=[0.05, 0.025])
    ap.add_argument("--t-end", type=float, default=13.0)
    ap.add_argument(
        "--v",
        type=float,
        default=fbl.V_LOAD,
        help="loading rate (the bumps reach the threshold at about 0.09/v; t_end is then "
        "0.09/v + t_end - 4.5)",
    )
    ap.add_argument("--no-ring", action="store_true", help="skip the 1D check")
    ap.add_argument("--json")
    a = ap.parse_args()
    t_end = a.t_end + 0.09 / a.v - 0.09 / fbl.V_LOAD
    out = {"L": fbl.L, "gamma": fbl.GAMMA, "v": a.v, "t_end": t_end, "runs": []}
    for dx in a.dx:
        base = None
        for step in a.step:
            res = analyse(run(dx, step, t_end, a.v), dx, a.v)
            sl, modes = res.pop("_slips"), res.pop("_modes")
            res["step"] = step
            if base is None:
                base = (sl, modes)
            else:
                key = ["block", "t_start"]
                p, q = (x.sort_values(key).reset_index(drop=True) for x in (base[0], sl))
                same = len(p) == len(q) and bool((p.block.values == q.block.values).all())
                res["against_first_step"] = {
                    "same_slip_sequence": same,
                    "max_dt_start": float((p.t_start - q.t_start).abs().max()) if same else None,
                    "max_dslip": float((p.slip - q.slip).abs().max()) if same else None,
                    "frames_with_other_modes": int((base[1] != modes).any(axis=(1, 2)).sum()),
                }
            print(json.dumps(res), flush=True)
            out["runs"].append(res)
    if not a.no_ring:
        out["ring"] = [ring(dx) for dx in a.dx]
        print(json.dumps(out["ring"]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
