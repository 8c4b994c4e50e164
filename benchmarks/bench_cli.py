"""Start-up time of the command line (issue 12: a command line that answers at once), and
what the first result of a call costs beyond its own work (issue 27: `bkwaves front` and
`Chain.run` must not pay for xarray/dask/pandas they do not use; `bkwaves run` writes
NetCDF and Zarr without xarray or dask).

Run: python benchmarks/bench_cli.py [--repeat N] [--before PYTHONPATH]
Every command is a fresh interpreter (subprocess); the rounds interleave the commands so
that a shared, busy machine slows them alike. Prints a markdown table of medians (wall and
CPU time) and each command's ratio to two baselines measured in the same run: an empty
interpreter (``python -c pass``) and ``python -c "import numpy"`` (which `bkwaves speed`
needs anyway). ``--before DIR`` also runs the bkwaves commands with ``PYTHONPATH=DIR`` (a
``python/`` directory of another version, e.g. from ``git archive``), interleaved with
the current ones. ``python -X importtime`` then shows where the remaining import time goes.
"""

import argparse
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PY = sys.executable
# a first result of the Python API: a short front in a small chain, reading its counters
CHAIN_RUN = (
    "import bkwaves as bk; ch = bk.Chain(200, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6); "
    "ch.kick(0, -2.0); r = ch.run(t_end=5.0, progress=False); r.counters"
)
# `bkwaves run` of the shipped front to NetCDF and to Zarr (written again each round)
FRONT = str(Path(__file__).resolve().parents[1] / "examples" / "chain_front.toml")
OUT = tempfile.mkdtemp(prefix="bench_cli_")
BASELINES = {
    "python -c pass": [PY, "-c", "pass"],
    'python -c "import numpy"': [PY, "-c", "import numpy"],
}
BKWAVES = {
    'python -c "import bkwaves"': [PY, "-c", "import bkwaves"],
    "bkwaves --help": [PY, "-m", "bkwaves", "--help"],
    "bkwaves speed 0.5 --json": [PY, "-m", "bkwaves", "speed", "0.5", "--json"],
    "bkwaves run --help": [PY, "-m", "bkwaves", "run", "--help"],
    "bkwaves front --u-plus 0.6 --gamma 0.3 --dx 0.05 --json": [
        PY,
        "-m",
        "bkwaves",
        "front",
        *("--u-plus", "0.6", "--gamma", "0.3", "--dx", "0.05", "--json"),
    ],
    "Chain.run (200 blocks, a kick, t_end = 5)": [PY, "-c", CHAIN_RUN],
    "bkwaves run examples/chain_front.toml -o OUT.nc": [
        *(PY, "-m", "bkwaves", "run", FRONT, "-o", f"{OUT}/x.nc", "--quiet", "--overwrite")
    ],
    "bkwaves run examples/chain_front.toml -o OUT.zarr": [
        *(PY, "-m", "bkwaves", "run", FRONT, "-o", f"{OUT}/x.zarr", "--quiet", "--overwrite")
    ],
}


def cpu_seconds() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def measure(cmd, env=None) -> tuple[float, float]:
    """Wall and CPU (user + system) seconds of one run of ``cmd``."""
    c0, t0 = cpu_seconds(), time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    return time.perf_counter() - t0, cpu_seconds() - c0


def top_imports(cmd, n=6):
    """The ``n`` top-level imports with the largest cumulative time (ms)."""
    r = subprocess.run([PY, "-X", "importtime", *cmd[1:]], capture_output=True, text=True)
    rows = []
    for line in r.stderr.splitlines():
        parts = line.split("|")
        if len(parts) == 3 and parts[1].strip().isdigit() and not parts[2].startswith("  "):
            rows.append((int(parts[1]) / 1000.0, parts[2].strip()))
    return sorted(rows, reverse=True)[:n]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--before", help="PYTHONPATH of the version to compare with")
    args = ap.parse_args()
    import bkwaves

    print(f"bkwaves {bkwaves.__version__} from {bkwaves.__file__}; {args.repeat} rounds\n")
    runs = {k: (cmd, None) for k, cmd in {**BASELINES, **BKWAVES}.items()}
    if args.before:
        env = {**os.environ, "PYTHONPATH": args.before}
        runs.update({f"{k} (before)": (cmd, env) for k, cmd in BKWAVES.items()})
    walls = {k: [] for k in runs}
    cpus = {k: [] for k in runs}
    for cmd, env in runs.values():  # warm the file cache
        measure(cmd, env)
    for _ in range(args.repeat):
        for k, (cmd, env) in runs.items():
            w, c = measure(cmd, env)
            walls[k].append(w)
            cpus[k].append(c)
    wall = {k: statistics.median(v) for k, v in walls.items()}
    cpu = {k: statistics.median(v) for k, v in cpus.items()}
    base, np_base = "python -c pass", 'python -c "import numpy"'
    print(
        "| command | wall (median) | wall (min) | CPU (median) "
        "| wall / `python -c pass` | wall / `import numpy` | CPU / `import numpy` |"
    )
    print("|---|---|---|---|---|---|---|")
    for k in runs:
        name = f"`{k.removesuffix(' (before)')}`" + (" before" if k.endswith("(before)") else "")
        print(
            f"| {name} | {wall[k] * 1e3:.0f} ms | {min(walls[k]) * 1e3:.0f} ms "
            f"| {cpu[k] * 1e3:.0f} ms | {wall[k] / wall[base]:.2f} "
            f"| {wall[k] / wall[np_base]:.2f} | {cpu[k] / cpu[np_base]:.2f} |"
        )
    for k in ("bkwaves --help", "bkwaves speed 0.5 --json", *list(BKWAVES)[-4:]):
        print(f"\nlargest top-level imports of `{k}` (python -X importtime, ms):")
        for ms, name in top_imports(BKWAVES[k]):
            print(f"  {ms:8.1f}  {name}")
    shutil.rmtree(OUT, ignore_errors=True)


if __name__ == "__main__":
    main()
