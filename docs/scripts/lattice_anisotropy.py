"""The anisotropy check of docs/lattice.md: ruptures with dx/dy = 1.5 as dx -> 0.

A rupture from a point (bk.lattice.rupture, u_+ = 0.6, gamma = 0.45, v = 0) on a quadrant
4 units of x wide at dx = 0.2, 0.1, 0.05 (dy = dx/1.5): its aspect (extent along x over
extent along y, in blocks) at t = 1, 1.5, 2, 2.5 against dy/dx (a circle in the plane).
Writes docs/lattice_anisotropy.json.

    python docs/scripts/lattice_anisotropy.py
"""

import json
import time
from pathlib import Path

import bkwaves as bk

out = []
for dx in (0.2, 0.1, 0.05):
    dy = dx / 1.5
    size = int(round(4.0 / dx))
    t0 = time.process_time()
    r = bk.lattice.rupture(0.6, 0.45, dx, size=size, dy=dy, check=False)
    row = {"dx": dx, "dy": dy, "size": list(r.size), "cpu": time.process_time() - t0}
    for t in (1.0, 1.5, 2.0, 2.5):
        a = r.aspect(t)
        row[f"aspect_{t}"] = a
        row[f"dev_{t}"] = a * dx / dy - 1.0
    out.append(row)
    print(row, flush=True)
path = Path(__file__).resolve().parents[1] / "lattice_anisotropy.json"
path.write_text(json.dumps(out, indent=1) + "\n")
