"""The chain run of noise_long_runs.py's "Ruptures of many sizes" (ring of length 1000,
20000 blocks, gamma = 0.85, v = 1e-4, exponential law, seed 1) on the installed build,
and the slip-by-slip comparison of two such runs (docs/noise.md, "Ruptures of many sizes").

    python docs/scripts/chain_divergence.py run T_END SEED OUT [SLIP_CAP]
    python docs/scripts/chain_divergence.py compare OUT_A OUT_B

``run`` writes OUT_catalog.csv (every digit), OUT_slips.parquet and OUT_info.json (CPU
time, open events, the energy books); a SLIP_CAP (e.g. 2e6) stops a run whose event
exceeds it. ``compare`` prints, event by event, the start times, nucleation blocks and
slip counts, then for each slip column how many slips differ and the first that does.
"""

import json
import math
import sys
import time

import numpy as np
import pandas as pd

import bkwaves as bk

DX, KICK = 0.05, 0.5


def run(t_end, seed, out, cap=10**9):
    length, gamma, v, phi0, u_star = 1000.0, 0.85, 1e-4, 0.01, 0.96
    n = round(length / DX)
    rate = DX * v / (length * phi0 * math.exp(-(1 - u_star) / phi0))
    noise = {"law": "exponential", "rate": rate, "phi0": phi0, "kick": KICK}
    p = bk.Params(gamma=gamma, v=v, dx=DX, beta=math.inf)
    ch = bk.Chain(n, p, "periodic", np.full(n, 0.9), noise=noise, seed=seed)
    c0 = time.process_time()
    res = ch.run(t_end=t_end, progress=False, max_event_duration=1e9, max_event_slips=cap)
    info = {
        "t": ch.t,
        "cpu_s": time.process_time() - c0,
        "events": len(res.catalog),
        "open": int(res.catalog.t_end.isna().sum()),
        "stop": str(res.stop),
        "energy": {k: float(x) for k, x in res.energy.items() if isinstance(x, float)},
    }
    res.catalog.to_csv(out + "_catalog.csv", index=False, float_format="%.17g")
    res.slips.to_parquet(out + "_slips.parquet")
    with open(out + "_info.json", "w") as f:
        json.dump(info, f, indent=1)
    print(json.dumps(info))


def compare(a, b):
    ca, cb = pd.read_csv(a + "_catalog.csv"), pd.read_csv(b + "_catalog.csv")
    for i in range(min(len(ca), len(cb))):
        ra, rb = ca.iloc[i], cb.iloc[i]
        print(
            f"event {i}: t_start {ra.t_start:.10g} / {rb.t_start:.10g} "
            f"(change {rb.t_start - ra.t_start:.3g}), nucleation block {ra.nucleation} / "
            f"{rb.nucleation}, slips {ra.n_slips} / {rb.n_slips}"
        )
    sa, sb = pd.read_parquet(a + "_slips.parquet"), pd.read_parquet(b + "_slips.parquet")
    m = min(len(sa), len(sb))
    for c in ("block", "t_start", "t_end", "u_end", "slip"):
        x, y = sa[c].to_numpy()[:m], sb[c].to_numpy()[:m]
        bad = np.flatnonzero(~((x == y) | (pd.isna(x) & pd.isna(y))))
        first = f"first at slip {bad[0]} (event {sa.event.iloc[bad[0]]})" if bad.size else "none"
        print(f"slips, {c}: {bad.size} of {m} differ, {first}")


if __name__ == "__main__":
    if sys.argv[1] == "run":
        cap = int(float(sys.argv[5])) if len(sys.argv) > 5 else 10**9
        run(float(sys.argv[2]), int(sys.argv[3]), sys.argv[4], cap)
    else:
        compare(sys.argv[2], sys.argv[3])
