"""How soon after it starts does ``bkwaves`` answer SIGINT and SIGTERM in one line?

Starts ``bkwaves run CONFIG -o OUT --quiet`` (the console script, as a user types it) over
and over, sends SIGINT or SIGTERM ``DELAY`` ms after the process was started, and sorts
what happened:

- ``answered``: exit 130/143 with one line on stderr, no traceback (bkwaves noted the
  signal: ``bkwaves._signals.install_early``, the first thing ``import bkwaves`` does in the
  command line);
- ``traceback``: a Python traceback (SIGINT after the interpreter installed its own
  handler, before bkwaves installed its: KeyboardInterrupt in the start-up imports);
- ``silent``: killed by the signal with nothing on stderr (before any handler: the
  interpreter itself still starting, or SIGTERM before bkwaves's handler);
- ``other``: anything else (printed).

Also measured, in the same run: the wall time of ``python -c pass`` and of
``bkwaves --version`` (the interpreter's start, and the command line up).

Run: python benchmarks/signal_window.py [--trials 20] [--delays 5 10 20 50 100]
     [--json out.json]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "examples" / "chain_front.toml"


def bkwaves_script() -> str:
    found = shutil.which("bkwaves", path=os.path.dirname(sys.executable))
    return found or shutil.which("bkwaves") or sys.exit("no bkwaves console script found")


def classify(rc: int, stderr: str, sig: int) -> str:
    lines = [ln for ln in stderr.splitlines() if ln.strip()]
    if "Traceback" in stderr or "KeyboardInterrupt" in stderr:
        return "traceback"
    if rc == -sig and not lines:
        return "silent"
    if rc == 128 + sig and len(lines) == 1:
        return "answered"
    return "other"


def trial(script: str, sig: int, delay_ms: float, tmp: Path, k: int) -> tuple[str, str]:
    out = tmp / f"o{k}.nc"
    p = subprocess.Popen(
        [script, "run", str(CONFIG), "-o", str(out), "--quiet"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    time.sleep(delay_ms / 1000.0)
    p.send_signal(sig)
    _, err = p.communicate(timeout=300)
    return classify(p.returncode, err, sig), f"rc={p.returncode} {err.strip()[-300:]}"


def wall(cmd) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=20)
    ap.add_argument("--delays", type=float, nargs="*", default=[5, 10, 20, 50, 100])
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    script = bkwaves_script()
    rows = []
    others = []
    starts = {"python -c pass": [], "bkwaves --version": []}
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        k = 0
        for _ in range(a.trials):  # rounds interleave delays and signals (a load slows all)
            starts["python -c pass"].append(wall([sys.executable, "-c", "pass"]))
            starts["bkwaves --version"].append(wall([script, "--version"]))
            for delay in a.delays:
                for sig in (signal.SIGINT, signal.SIGTERM):
                    k += 1
                    kind, what = trial(script, sig, delay, tmp, k)
                    rows.append({"signal": signal.Signals(sig).name, "delay_ms": delay,
                                 "outcome": kind})  # fmt: skip
                    if kind == "other":
                        others.append((signal.Signals(sig).name, delay, what))
            for f in tmp.iterdir():  # (a run that finished: not the point here)
                shutil.rmtree(f) if f.is_dir() else f.unlink()
    load = os.getloadavg()[0]
    table = {}
    for r in rows:
        key = (r["signal"], r["delay_ms"])
        table.setdefault(key, {"answered": 0, "traceback": 0, "silent": 0, "other": 0})
        table[key][r["outcome"]] += 1
    print(f"load average {load:.1f}; {a.trials} trials per row")
    for name, ts in starts.items():
        print(f"{name}: median {1e3 * statistics.median(ts):.0f} ms, "
              f"min {1e3 * min(ts):.0f} ms")  # fmt: skip
    print("| signal | delay (ms) | answered | traceback | silent | other |")
    print("|---|---|---|---|---|---|")
    for (name, delay), c in table.items():
        print(f"| {name} | {delay:g} | {c['answered']} | {c['traceback']} | {c['silent']} | "
              f"{c['other']} |")  # fmt: skip
    for o in others:
        print("other:", *o)
    if a.json:
        Path(a.json).write_text(
            json.dumps(
                {
                    "load_average": load,
                    "trials": a.trials,
                    "start_ms": {n: [1e3 * t for t in ts] for n, ts in starts.items()},
                    "rows": [{"signal": s, "delay_ms": dl, **c} for (s, dl), c in table.items()],
                    "other": others,
                },
                indent=1,
            )
        )


if __name__ == "__main__":
    main()
