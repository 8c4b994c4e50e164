"""Long runs of the noisy chain against the calibrated free boundary (docs/noise.md,
"Long runs compared: a chain that cycles").

    python docs/scripts/noise_long_runs.py          # about five minutes on one core
    python docs/scripts/noise_long_runs.py --b OUT.json   # 5.: b from independent runs

1. The rupture map: the background u at which a ring is next fired by its own pattern,
   after a ring-wide rupture at u_+ (kick 0.5, as the noise), against gamma.
2. Re-sticking under load: one kicked pulse on the ring at gamma = 0.85, against v.
3. The comparison at gamma = 0.85, v = 1e-5 (t = 3e7): recurrences, moments, and the
   exact recurrence given the state a rupture leaves in each engine.
4. Ruptures of many sizes: rings of length 1000 (20000 blocks) at v = 1e-4 and 3000
   (60000 blocks) at v = 3e-5, where several ruptures share a loading: rate,
   size-frequency, b-value (about four minutes).
5. (--b OUT.json [--fb-only]) The b-values of 4. from independent runs (noise seeds): 8
   runs per engine at L = 1000 and 6 at L = 3000, each b with its bootstrap interval,
   and their mean with the standard error over runs (or why there is none); the rows
   are saved to OUT.json.
6. (--chain-b OUT.json [SEEDS] [--cpu S] [--length 3000]) The chain's column of 4. at
   L = 1000 (or 3000: v = 3e-5, to t = 1.926e6) as an ensemble over noise seeds (default
   1-8): each run to t = 1e6, until one event exceeds CHAIN_CAP slips per block (a ring
   that slides on) or past S s of CPU, its ruptures after the
   burn-in, their b (bk.stats.gutenberg_richter) and rate; rows saved to OUT.json after
   every segment of 2e4 time units.
7. (--step-check OUT.json SEED [CHAIN_B.json]) Whether a chain that slides on in 6. does so with the
   engine's step halved: the run to just before the event that ran away, then the same
   window from that state at step 0.05 dx and 0.025 dx (the engine's fingerprint
   patched, nothing else), the share of blocks sliding and their mean u against time.
"""

import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy import stats

import bkwaves as bk
from bkwaves import noise_stats as ns
from bkwaves import theory

N, DX, KICK = 400, 0.05, 0.5
L = N * DX


def ring_after_rupture(u_plus, gamma, v=0.0, t_end=60.0):
    p = bk.Params(gamma=gamma, v=v, dx=DX, beta=math.inf)
    ch = bk.Chain(N, p, "periodic", np.full(N, u_plus))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = ch.kick(0, -KICK, 0.0).run(t_end=t_end, max_events=1, progress=False)
    return ch, res.catalog


def rupture_map():
    print("background u_b at which the ring is next fired by its own pattern")
    for gamma in (0.3, 0.8, 0.85, 0.9):
        row = []
        for u_plus in (0.86, 0.9, 0.93, 0.95, 0.97, 0.99, 0.995, 0.999):
            ch, _ = ring_after_rupture(u_plus, gamma)
            u_b = np.median(ch.u) + 1 - ch.phi.max()
            row.append(f"{u_plus}: {u_b:.3f}{'*' if u_b > u_plus else ''}")
        print(f"  gamma = {gamma} (* cycle possible): " + ", ".join(row))


def resticking():
    print("one kicked pulse, gamma = 0.85: event duration (open: no re-sticking by t = 200)")
    for u_plus in (0.87, 0.9, 0.95):
        row = []
        for v in (1e-3, 1e-4, 1e-5, 0.0):
            _, cat = ring_after_rupture(u_plus, 0.85, v=v, t_end=200.0)
            ended = not math.isnan(cat.t_end.iloc[0])
            row.append(f"v = {v:g}: {cat.duration.iloc[0]:.1f}" if ended else f"v = {v:g}: open")
        print(f"  u_+ = {u_plus}: " + "; ".join(row))


def comparison(gamma=0.85, v=1e-5, t_end=3e7, phi0=0.01):
    chain_noise = {"law": "exponential", "rate": 1e-3, "phi0": phi0, "kick": KICK}
    p = bk.Params(gamma=gamma, v=v, dx=DX, beta=math.inf)
    ch = bk.Chain(N, p, "periodic", np.full(N, gamma + 0.01), noise=chain_noise, seed=1)
    chain_result = ch.run(t_end=t_end, progress=False, max_event_duration=1e9)
    cat = chain_result.catalog
    per = ns.chain_ruptures(chain_result)
    fb_noise = ns.calibrated_noise(chain_noise, DX, gamma)
    x = np.arange(200) * 0.1
    fb = bk.FreeBoundary(p, x, np.full(x.size, gamma + 0.01), "periodic", noise=fb_noise, seed=2)
    fb_result = fb.run(t_end=t_end)
    rup = ns.ruptures(fb_result)
    u_start = float(rup.u_start.mean())
    u_minus = float(theory.u_minus(u_start, theory.c_exact(u_start), gamma))
    after, _ = ring_after_rupture(u_start, gamma)
    u_eff = phi0 * math.log(np.mean(np.exp(after.phi / phi0)))

    def exact(phi, rate):
        return ns.first_slip(phi, {"law": "exponential", "rate": rate, "phi0": phi0}, v)

    print(f"gamma = {gamma}, v = {v}, t = {t_end:g}; free boundary noise {fb_noise}")
    print(
        f"  chain events: {len(cat)} ({cat.t_end.isna().sum()} open), sizes "
        f"{cat.n_blocks.min()}-{cat.n_blocks.max()}, durations {cat.duration.min():.1f}-"
        f"{cat.duration.max():.1f}; free boundary ruptures {len(rup)}, u_start "
        f"{u_start:.3f} +- {rup.u_start.std():.3f}"
    )
    print(
        f"  ruptures: chain {len(per)} ({per.spontaneous.mean():.2f} spontaneous, sizes "
        f"{per.n_blocks.min()}-{per.n_blocks.max()} blocks), free boundary {len(rup)} (sizes "
        f"{rup.swept.min():.2f}-{rup.swept.max():.2f}); free boundary events "
        f"{len(fb_result.events)}"
    )
    print(
        f"  after a rupture at {u_start:.3f}: u_- = {u_minus:.5f} (free boundary), chain median"
        f" u {np.median(after.u):.5f}, mean {after.u.mean():.5f}, min {after.u.min():.5f},"
        f" hazard-weighted phi {u_eff:.5f}"
    )
    rows = (
        ("chain", cat.t_start.to_numpy(), per.moment, exact(after.phi, chain_noise["rate"])),
        (
            "free boundary",
            fb_result.events.t_start.to_numpy(),
            rup.moment,
            exact(np.full(N, u_minus), fb_noise["rate"] * DX),
        ),
    )
    for name, t, moment, (mean, survival) in rows:
        d = np.diff(t)
        ks = stats.kstest(d, lambda s, f=survival: 1 - f(s)).pvalue
        print(
            f"  {name}: event recurrence {d.mean():.0f} +- {d.std(ddof=1) / math.sqrt(d.size):.0f} "
            f"(sd {d.std(ddof=1):.0f}), exact {mean:.0f}, KS p {ks:.2f}; moment "
            f"{moment.mean():.1f} (sd {moment.std():.1f}) per rupture"
        )
    print(
        f"  KS two-sample p = {stats.ks_2samp(np.diff(rows[0][1]), np.diff(rows[1][1])).pvalue:.2f}"
    )


def _many_sizes(length, t_end, gamma, v, phi0, u_star, seeds=(1, 2), chain=True):
    """The runs of sizes(): the chain's ruptures (noise seed seeds[0]; None unless
    ``chain``) and the free boundary's (seeds[1]) after two loadings of burn-in, the
    chain's result, the burn-in."""
    n = round(length / DX)
    rate = DX * v / (length * phi0 * math.exp(-(1 - u_star) / phi0))
    chain_noise = {"law": "exponential", "rate": rate, "phi0": phi0, "kick": KICK}
    p = bk.Params(gamma=gamma, v=v, dx=DX, beta=math.inf)
    burn = 2 * (u_star + 0.1) / v  # two loadings
    per = chain_result = None
    if chain:
        ch = bk.Chain(n, p, "periodic", np.full(n, 0.9), noise=chain_noise, seed=seeds[0])
        chain_result = ch.run(
            t_end=t_end, progress=False, max_event_duration=1e9, max_event_slips=10**9
        )
        per = ns.chain_ruptures(chain_result)
        per = per[per.t_start > burn]
    fb_noise = ns.calibrated_noise(chain_noise, DX, gamma)
    x = np.arange(round(length / 0.1)) * 0.1
    fb = bk.FreeBoundary(p, x, np.full(x.size, 0.9), "periodic", noise=fb_noise, seed=seeds[1])
    rup = ns.ruptures(fb.run(t_end=t_end))
    return per, rup[rup.t_start > burn], chain_result, burn


def sizes(length=1000.0, t_end=1e6, gamma=0.85, v=1e-4, phi0=0.01, u_star=0.96):
    """Several ruptures per loading: L >> c phi0 / v. Rate per block at phi = 1 set so
    that one nucleation is expected by the time a uniform ring reaches u_star."""
    n = round(length / DX)
    per, rup, chain_result, burn = _many_sizes(length, t_end, gamma, v, phi0, u_star)
    print(f"ring of length {length} ({n} blocks), gamma = {gamma}, v = {v}, t = {burn:g}-{t_end:g}")
    print(f"  open chain events: {chain_result.catalog.t_end.isna().sum()}")
    for name, r in (("chain", per), ("free boundary", rup)):
        # the estimator of every bkwaves b (docs/usage.md "Event statistics")
        b = bk.stats.gutenberg_richter(r.moment.to_numpy())
        q = np.percentile(r.swept, [10, 50, 90])
        print(
            f"  {name}: {len(r)} ruptures ({r.spontaneous.mean():.2f} spontaneous), rate "
            f"{len(r) / (t_end - burn):.3e} +- {math.sqrt(len(r)) / (t_end - burn):.1e}; u_start "
            f"{r.u_start.mean():.4f} (sd {r.u_start.std():.4f}); swept 10/50/90 % "
            f"{q[0]:.0f}/{q[1]:.0f}/{q[2]:.0f}, mean {r.swept.mean():.1f}; mean slip "
            f"{(r.moment / r.swept).mean():.4f}; {b.text()}"
        )
        # the k-th rupture of its loading (a new loading after a gap of over 0.3 u_star / v)
        t = r.t_start.to_numpy()
        group = np.cumsum(np.r_[True, np.diff(t) > 0.3 * u_star / v])
        k = np.arange(len(t)) - np.searchsorted(group, group)
        by_order = ", ".join(
            f"{r.u_start[k == j].mean():.4f} (n = {np.sum(k == j)})"
            for j in range(3)
            if np.any(k == j)
        )
        print(f"    u_start of the 1st, 2nd, 3rd rupture of a loading: {by_order}")
    for col in ("swept", "moment"):
        print(f"  KS two-sample, {col}: p = {stats.ks_2samp(per[col], rup[col]).pvalue:.2f}")
    print(f"  KS two-sample, u_start: p = {stats.ks_2samp(per.u_start, rup.u_start).pvalue:.2g}")


def b_values(length, t_end, v, seeds, chain=True, gamma=0.85, phi0=0.01, u_star=0.96):
    """The b-value of the ruptures of sizes() (bk.stats.gutenberg_richter: moment
    magnitudes M = (2/3) log10(int slip dx), Mc by maximum curvature + 0.2, Aki-Utsu, 95 %
    bootstrap interval) in independent runs: one noise seed per run and engine (the chain
    seed k, the free boundary seed k + 1: run 1 is the table's; the chain only if
    ``chain``). Returns one row per run and engine, with the largest magnitude and the
    fraction of ruptures that sweep the whole ring."""
    rows = []
    for k in seeds:
        per, rup, _, _ = _many_sizes(length, t_end, gamma, v, phi0, u_star, (k, k + 1), chain)
        for name, r in (("chain", per), ("free boundary", rup)):
            if r is None:
                continue
            b = bk.stats.gutenberg_richter(r.moment.to_numpy())
            rows.append(
                dict(
                    length=length, v=v, t_end=t_end, seed=k, engine=name,
                    ruptures=len(r), b=b.b, lo=b.lo, hi=b.hi, m_c=b.m_c, n=b.n,
                    fit_p=b.fit_p, reason=b.reason, text=b.text(),
                    m_max=float((2 / 3) * np.log10(r.moment.max())),
                    ring_wide=float(np.mean(r.swept >= (1 - 1e-9) * length)),
                )
            )  # fmt: skip
            print(f"L = {length:g}, seed {k}, {name}: {len(r)} ruptures, {b.text()}", flush=True)
    return rows


def _b_summary(rows):
    """Per ring and engine: the b of each run and their mean with its standard error
    over the independent runs (the spread of b between runs, not a bootstrap)."""
    import pandas as pd

    df = pd.DataFrame(rows)
    for (length, engine), g in df.groupby(["length", "engine"], sort=False):
        b = g.b.astype(float).to_numpy()
        ok = b[np.isfinite(b)]
        rw = g.ring_wide.to_numpy()
        print(
            f"L = {length:g}, {engine}: ring-wide ruptures {rw.mean():.2f} +- "
            f"{rw.std(ddof=1) / math.sqrt(rw.size):.2f} of all, largest M "
            f"{g.m_max.min():.3f}-{g.m_max.max():.3f}, Mc {g.m_c.min():.2f}-{g.m_c.max():.2f}"
        )
        if not ok.size:
            print(f"  no b in any of {b.size} runs: {g.reason.iloc[0]}")
            continue
        err = ok.std(ddof=1) / math.sqrt(ok.size) if ok.size > 1 else math.nan
        print(
            f"L = {length:g}, {engine}: b = {ok.mean():.2f} +- {err:.2f} over {ok.size} runs "
            f"(each: {', '.join(f'{x:.2f}' for x in b)}; Mc {g.m_c.min():.2f}-"
            f"{g.m_c.max():.2f}, {g.n.min()}-{g.n.max()} of {g.ruptures.min()}-"
            f"{g.ruptures.max()} ruptures above Mc)"
        )


#: Slips per block after which a chain event of "Ruptures of many sizes" counts as a ring
#: that slides on (a ring-wide rupture takes about 1 per block; 2e5 slips at L = 1000).
CHAIN_CAP = 10


def _sizes_chain(seed, length=1000.0, gamma=0.85, v=1e-4, phi0=0.01, u_star=0.96, step=None):
    """The chain of sizes() at ``length`` with noise ``seed`` (and ``step``, a fraction
    of dx; default the engine's), not run."""
    n = round(length / DX)
    rate = DX * v / (length * phi0 * math.exp(-(1 - u_star) / phi0))
    noise = {"law": "exponential", "rate": rate, "phi0": phi0, "kick": KICK}
    p = bk.Params(gamma=gamma, v=v, dx=DX, beta=math.inf)
    kw = {} if step is None else {"step": step}
    return bk.Chain(n, p, "periodic", np.full(n, 0.9), noise=noise, seed=seed, **kw)


def chain_b(seeds, out, length=1000.0, t_end=1e6, v=1e-4, u_star=0.96, seg=2e4, cpu=None):
    """6.: one run per noise seed, in segments of ``seg`` time units (a quiet segment end
    changes nothing; one inside an event cuts a step short: still a sample of the same
    ensemble); a row per run, rewritten to ``out`` after every segment, so an interrupted
    ensemble keeps what it computed. ``cpu``: a CPU budget per run in seconds (the row then
    says where it stopped)."""
    import time

    burn = 2 * (u_star + 0.1) / v
    rows = []
    for k in seeds:
        ch = _sizes_chain(k, length, v=v, u_star=u_star)
        c0 = time.process_time()
        while True:
            t_next = min(ch.t + seg, t_end)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", bk.chain.RunawayEventWarning)
                res = ch.run(t_end=t_next, progress=False, max_event_duration=1e9,
                             max_event_slips=CHAIN_CAP * ch.n)  # fmt: skip
            cpu_s = time.process_time() - c0
            over = cpu is not None and cpu_s > cpu and res.stop == "time" and ch.t < t_end
            done = res.stop != "time" or ch.t >= t_end or over
            row = _chain_row(res, ch, k, length, v, t_end, burn, cpu_s, over)
            rows = [r for r in rows if r["seed"] != k] + [row]
            clean = [{a: None if x != x else x for a, x in q.items()} for q in rows]
            Path(out).write_text(json.dumps(clean, indent=1) + "\n")
            print(f"seed {k}: t = {row['t']:.4g}, {row['events']} events ({row['open']} open, "
                  f"{row['sliding']:.3f} of the blocks sliding), {row['ruptures']} ruptures, "
                  f"{cpu_s:.0f} s CPU", flush=True)  # fmt: skip
            if done:
                break
        print(f"seed {k}: stop {row['stop']}, runaway from {row['runaway_t']}, {row['text']}")
    return rows


def _chain_row(res, ch, k, length, v, t_end, burn, cpu_s, over):
    """A row of chain_b: where the run is, the runaway (an open event at a long_event
    stop), its closed ruptures after the burn-in and their b."""
    cat = res.catalog
    open_ = cat[cat.t_end.isna()]
    runaway = open_ if res.stop == "long_event" else open_.iloc[:0]
    per = ns.chain_ruptures(res)
    per = per[(per.t_start > burn) & per.t_end.notna()]
    end = runaway.t_start.iloc[0] if len(runaway) else ch.t
    span = end - burn
    b = bk.stats.gutenberg_richter(per.moment.to_numpy())
    return dict(
        length=length, v=v, t_end=t_end, seed=k, engine="chain",
        stop="cpu budget" if over else res.stop, t=float(ch.t), cpu_s=cpu_s,
        events=len(cat), open=len(open_), sliding=float(np.mean(ch.modes != 0)),
        runaway_t=float(runaway.t_start.iloc[0]) if len(runaway) else None,
        runaway_block=int(runaway.nucleation.iloc[0]) if len(runaway) else None,
        window=float(span), ruptures=len(per),
        rate=len(per) / span if span > 0 else None,
        b=b.b, lo=b.lo, hi=b.hi, m_c=b.m_c, n=b.n, fit_p=b.fit_p,
        reason=b.reason, text=b.text(),
        m_max=float((2 / 3) * np.log10(per.moment.max())) if len(per) else None,
        ring_wide=float(np.mean(per.swept >= (1 - 1e-9) * length)) if len(per) else None,
        u_start=float(per.u_start.mean()) if len(per) else None,
        energy_residual=float(res.energy["residual"]),
    )  # fmt: skip


def _chain_summary(rows, loading=9620.0):
    """6.'s ensemble: how many runs slid on and when (the hazard per loading, Poisson),
    the pooled rupture rate with its Poisson error and the spread of the runs' rates,
    the ring-wide share and u_start with their standard errors over the runs."""
    runs = [r for r in rows if r["ruptures"]]
    slid = [r for r in rows if r["runaway_t"] is not None]
    span = sum(r["window"] for r in rows)
    n_rup = sum(r["ruptures"] for r in rows)
    rates = np.array([r["rate"] for r in runs])
    rw = np.array([r["ring_wide"] for r in runs])
    us = np.array([r["u_start"] for r in runs])

    def se(x):
        return x.std(ddof=1) / math.sqrt(x.size) if x.size > 1 else math.nan

    when = ", ".join(f"{r['runaway_t']:.3g}" for r in slid)
    print(
        f"{len(rows)} runs: {len(slid)} slid on (at t = {when}); {span / loading:.0f} loadings "
        f"after burn-in in all: slide-on hazard {len(slid) / (span / loading):.3g} +- "
        f"{math.sqrt(len(slid)) / (span / loading):.2g} per loading"
    )
    print(
        f"ruptures: {n_rup}, pooled rate {n_rup / span:.3e} +- {math.sqrt(n_rup) / span:.1e} "
        f"per unit time; runs' rates {rates.mean():.3e} +- {se(rates):.1e} (sd "
        f"{rates.std(ddof=1):.1e}); ring-wide {rw.mean():.2f} +- {se(rw):.2f}; u_start "
        f"{us.mean():.4f} +- {se(us):.4f}"
    )


def _with_step(chain, step):
    """``chain``'s state in a chain that steps at ``step`` dx: the checkpoint's engine
    bytes with the step in the fingerprint replaced (bytes 32-40: magic, n, dx, v, step)."""
    import struct

    meta, arrays = chain.__getstate__()
    raw = bytearray(arrays["engine"].tobytes())
    assert struct.unpack("<d", raw[32:40])[0] == chain.step, "fingerprint layout changed"
    raw[32:40] = struct.pack("<d", step)
    meta = dict(meta, step=step)
    arrays = dict(arrays, engine=np.frombuffer(bytes(raw), dtype=np.uint8))
    return bk.Chain._from_record(meta, arrays)


def step_check(seed, out, t0=None, window=2000.0, probe=100.0):
    """7.: the start t0 of the event of ``seed`` that runs away (found by a run unless
    given, e.g. from 6.'s rows), a rerun to just before it (checked below: the same event
    then starts at the same float), then the window from there at the default step and
    at half of it."""
    import time

    if t0 is None:
        ch = _sizes_chain(seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", bk.chain.RunawayEventWarning)
            res = ch.run(t_end=1e6, progress=False, max_event_duration=1e9,
                         max_event_slips=CHAIN_CAP * ch.n)  # fmt: skip
        open_ = res.catalog[res.catalog.t_end.isna()]
        if not len(open_):
            print(f"seed {seed}: no event ran away to t = {res.t:.4g}")
            return
        t0 = float(open_.t_start.iloc[0])
    t_quiet = t0 - 1e-3  # events do not overlap: every block is stuck here
    ch = _sizes_chain(seed)
    ch.run(t_end=t_quiet, progress=False, max_event_duration=1e9, max_event_slips=CHAIN_CAP * ch.n)
    record = {"seed": seed, "t_runaway": t0, "t_quiet": t_quiet, "window": window, "runs": []}
    for step in (ch.step, ch.step / 2):
        run = _with_step(ch, step)
        times, share, mean_u = [], [], []
        c0 = time.process_time()
        t = t_quiet
        first = None
        while t < t_quiet + window:
            t = min(t + probe, t_quiet + window)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", bk.chain.RunawayEventWarning)
                r = run.run(t_end=t, progress=False, max_event_duration=1e9,
                            max_event_slips=10**9)  # fmt: skip
            new = r.catalog[r.catalog.t_start >= t_quiet]  # (the catalog keeps the past)
            if first is None and len(new):
                first = float(new.t_start.iloc[0])
            sliding = run.modes != 0
            times.append(t)
            share.append(float(sliding.mean()))
            mean_u.append(float(run.u.mean()))
        record["runs"].append(dict(step=step, first_event=first, t=times, sliding=share,
                                   mean_u=mean_u, cpu_s=time.process_time() - c0,
                                   energy_residual=float(r.energy["residual"])))  # fmt: skip
        print(
            f"step {step}: first event at {first!r} (the full run's {t0!r}); sliding share "
            + ", ".join(f"{x:.2f}" for x in share[:: max(1, len(share) // 8)]),
            flush=True,
        )
        Path(out).write_text(json.dumps(record, indent=1) + "\n")


if __name__ == "__main__" and "--chain-b" in sys.argv:
    # python docs/scripts/noise_long_runs.py --chain-b OUT.json [SEED ...] [--cpu S]  (S: a
    # CPU budget per run in seconds; SEED 0: the
    # summary of OUT.json as written, no runs)
    i = sys.argv.index("--chain-b")
    args = sys.argv[i + 2 :]
    cpu = float(args.pop(args.index("--cpu") + 1)) if "--cpu" in args else None
    length = float(args.pop(args.index("--length") + 1)) if "--length" in args else 1000.0
    args = [a for a in args if a not in ("--cpu", "--length")]
    # the rows of sizes(): L = 1000 at v = 1e-4 to 1e6, L = 3000 at v = 3e-5 to 1.926e6
    t_end, v = (1e6, 1e-4) if length == 1000.0 else (1.926e6, 3e-5)
    seeds = [int(a) for a in args] or list(range(1, 9))
    if seeds == [0]:  # --chain-b OUT.json 0: the summary of OUT.json's rows, no runs
        rows = json.loads(Path(sys.argv[i + 1]).read_text())
    else:
        rows = chain_b(seeds, sys.argv[i + 1], length=length, t_end=t_end, v=v, cpu=cpu)
    _b_summary(rows)
    _chain_summary(rows, loading=0.962 / rows[0]["v"])
elif __name__ == "__main__" and "--step-check" in sys.argv:
    # python docs/scripts/noise_long_runs.py --step-check OUT.json SEED [CHAIN_B.json]
    i = sys.argv.index("--step-check")
    seed, t0 = int(sys.argv[i + 2]), None
    if len(sys.argv) > i + 3:  # the rows of --chain-b: the runaway's start for this seed
        rows = json.loads(Path(sys.argv[i + 3]).read_text())
        t0 = next(r["runaway_t"] for r in rows if r["seed"] == seed)
    step_check(seed, sys.argv[i + 1], t0)
elif __name__ == "__main__" and "--b" in sys.argv:
    # the b-values of "Ruptures of many sizes" from independent runs (docs/noise.md):
    # python docs/scripts/noise_long_runs.py --b OUT.json [--fb-only]
    chain = "--fb-only" not in sys.argv
    rows = b_values(1000.0, 1e6, 1e-4, seeds=range(1, 9), chain=chain)
    rows += b_values(3000.0, 1.926e6, 3e-5, seeds=range(1, 7), chain=chain)
    _b_summary(rows)
    # (no b: null, not NaN, so that the file is JSON)
    rows = [{k: None if v != v else v for k, v in r.items()} for r in rows]
    Path(sys.argv[sys.argv.index("--b") + 1]).write_text(json.dumps(rows, indent=1) + "\n")
elif __name__ == "__main__":
    rupture_map()
    resticking()
    comparison()
    sizes()
    sizes(length=3000.0, t_end=1.926e6, v=3e-5)
