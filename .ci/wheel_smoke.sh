#!/usr/bin/env bash
# Smoke test of an installed bkwaves wheel, run by .ci/run in a fresh virtual environment
# whose PATH has no cargo: a front, a run written to NetCDF and to Zarr, bkwaves paper
# --quick. Usage: wheel_smoke.sh VENV REPO (runs in a temporary directory).
set -euo pipefail
venv=$1 repo=$2
export PATH="$venv/bin:/usr/bin:/bin"
if command -v cargo >/dev/null; then echo "cargo is on PATH: not a Rust-free test" >&2; exit 1; fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
python - "$repo" <<'PY'
import json
import subprocess
import sys
from pathlib import Path

import bkwaves as bk

repo = Path(sys.argv[1])
where = Path(bk.__file__).resolve()
assert (repo / "python").resolve() not in where.parents, f"bkwaves from the source tree: {where}"
# a front: the chain against the finite-dx tip problem, and the command line
c = bk.front_speed(0.6, dx=0.1, gamma=0.3)
out = subprocess.run(["bkwaves", "front", "--u-plus", "0.6", "--gamma", "0.3", "--dx", "0.1",
                      "--json"], check=True, capture_output=True, text=True).stdout
front = json.loads(out)
assert abs(front["c"] - c) < 1e-6, (front["c"], c)
# one run to NetCDF and to Zarr: same catalog
config = repo / "examples" / "chain_front.toml"
for out in ("front.nc", "front.zarr"):
    subprocess.run(["bkwaves", "run", str(config), "-o", out, "--quiet"], check=True)
(ds_nc, ev_nc), (ds_z, ev_z) = bk.load("front.nc"), bk.load("front.zarr")
assert ds_nc["u"].shape == ds_z["u"].shape and (ds_nc["u"].values == ds_z["u"].values).all()
assert ev_nc.equals(ev_z) and len(ev_nc) == 1
print(f"wheel smoke: bkwaves {bk.__version__} from {where.parent}; front c = {front['c']:.6f}"
      f" (tip problem {c:.6f}); run to NetCDF and Zarr: {ds_nc['u'].shape} snapshots equal")
PY
bkwaves paper --quick -o paper --quiet --json > paper.json
python - <<'PY'
import json
from pathlib import Path

r = json.load(open("paper.json"))
figures = r["figures"] + r["beyond_figures"]
missing = [f for f in figures if not (Path("paper") / f"{f}.png").is_file()]
assert figures and not missing and Path("paper/report.md").is_file(), missing
print(f"wheel smoke: bkwaves paper --quick: {len(figures)} figures, report.md,"
      f" {r['claims']} claims {r['verdicts']}")
PY
