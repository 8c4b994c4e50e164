"""Adaptive sweeps: refine one or two continuous axes where a summary scalar changes
fastest (the ``adaptive`` package's Learner1D / Learner2D), the points computed on Dask.

The learner asks for points, the cluster computes them, every finished point is told to
the learner and appended to the store; the store is a Dataset with one dimension
``point`` (the axes are coordinates along it). Records are all-or-nothing: a point's
values are written first, then the store's committed count (attribute ``committed``) is
advanced, and readers see only committed points. A re-run tells the learner the points
already in the store and goes on from there.
"""

from __future__ import annotations

import json
import math
import time
from pathlib import Path

import numpy as np

from ._core import ParameterError
from .sweeps import (
    DONE,
    FAILED,
    STORE_MARKER,
    SweepResult,
    _client,
    _consolidate,
    _slots,
    _write_point_files,
    run_point,
    store_attrs,
)

ADAPTIVE_MARKER = STORE_MARKER + "-adaptive"


class _AdaptiveStore:
    def __init__(self, path: Path, spec, *, overwrite: bool):
        import zarr

        self.path, self.spec = Path(path), spec
        self.signature = json.dumps(
            {
                "task": spec.task,
                "base": spec.base,
                "axes": spec.to_dict()["axes"],
                "output": spec.adaptive["output"],
            },
            sort_keys=True,
            default=str,
        )
        if self.path.exists():
            try:
                g = zarr.open_group(str(self.path), mode="r", use_consolidated=False)
                ours = g.attrs.get("bkwaves_sweep") == ADAPTIVE_MARKER
            except Exception:  # noqa: BLE001 - anything unreadable is not ours
                ours = False
            if not ours:
                raise ParameterError(
                    f"-o {self.path}: exists and is not a bkwaves adaptive sweep store; "
                    "bkwaves will not touch it (choose another output)"
                )
            if g.attrs.get("signature") != self.signature and not overwrite:
                raise ParameterError(
                    f"-o {self.path}: holds a different sweep (other task, base, axes or "
                    "output); give another output, or --overwrite to replace it"
                )
            if overwrite:
                import shutil

                shutil.rmtree(self.path)
        if not self.path.exists():
            g = zarr.open_group(str(self.path), mode="w-")
            g.attrs.update({**store_attrs(spec, ADAPTIVE_MARKER, self.signature), "committed": 0})
            for a in spec.axes:
                self._create(a.name, 0.0)
            self._create("status", 0)
            self._create("error", "")
            self._create("key", "")
            self._create("wall_s", 0.0)
            _consolidate(self.path)
        self.g = zarr.open_group(str(self.path), mode="r+", use_consolidated=False)
        self.n = int(self.g.attrs["committed"])

    def _create(self, name, value, g=None):
        import zarr

        g = g or zarr.open_group(str(self.path), mode="r+", use_consolidated=False)
        if isinstance(value, str):
            kw = {"dtype": str, "fill_value": ""}
        elif isinstance(value, int):
            kw = {"dtype": "i1", "fill_value": 0}
        else:
            kw = {"dtype": "f8", "fill_value": float("nan")}
        cap = int(self.g["status"].shape[0]) if hasattr(self, "g") else 0
        return g.create_array(name, shape=(cap,), chunks=(256,), dimension_names=["point"], **kw)

    def points(self) -> list[tuple[tuple, dict]]:
        """The committed points: (axis values, summary) pairs."""
        out = []
        names = [a.name for a in self.spec.axes]
        skip = {*names, "status", "error", "key", "wall_s"}
        cols = {k: np.asarray(self.g[k][: self.n]) for k in self.g.array_keys()}
        for i in range(self.n):
            x = tuple(float(cols[k][i]) for k in names)
            s = {k: v[i] for k, v in cols.items() if k not in skip}
            out.append((x, int(cols["status"][i]), s))
        return out

    def append(self, x, key, summary, error):
        i = self.n
        if i >= self.g["status"].shape[0]:
            new = max(256, 2 * self.g["status"].shape[0])
            for k in self.g.array_keys():
                self.g[k].resize((new,))
        reserved = {a.name for a in self.spec.axes}
        for name, value in (summary or {}).items():
            if name.startswith("__") or name in reserved:
                continue
            if name not in self.g:
                self._create(name, value if isinstance(value, str) else 0.0, self.g)
                _consolidate(self.path)
            self.g[name][i] = value
        for a, v in zip(self.spec.axes, x, strict=True):
            self.g[a.name][i] = v
        self.g["key"][i] = key
        self.g["error"][i] = error or ""
        self.g["status"][i] = FAILED if error else DONE
        # commit: readers see the point only now
        self.n = i + 1
        self.g.attrs["committed"] = self.n


def load_adaptive_result(out):
    """Open an adaptive sweep store as a Dataset of its committed points."""
    import warnings

    import xarray as xr

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = xr.open_zarr(str(out), consolidated=False).load()
    n = int(ds.attrs.get("committed", ds.sizes.get("point", 0)))
    ds = ds.isel(point=slice(0, n))
    names = [k.split(".")[-1] for k in json.loads(ds.attrs["sweep"])["axes"]]
    ds = ds.set_coords(names)
    if len(names) == 1:  # one axis: in order along it
        ds = ds.sortby(names[0])
    return ds


def run_adaptive(spec, out, *, scheduler, workers, processes, overwrite, progress, client):
    import adaptive
    from distributed import wait

    t0 = time.perf_counter()
    store = _AdaptiveStore(out, spec, overwrite=overwrite)
    output = spec.adaptive["output"]
    npoints = spec.adaptive.get("npoints")
    loss_goal = spec.adaptive.get("loss_goal")
    bounds = [a.bounds for a in spec.axes]
    if len(bounds) == 1:
        learner = adaptive.Learner1D(None, bounds=bounds[0])
    else:
        learner = adaptive.Learner2D(None, bounds=bounds)

    def value(summary) -> float:
        v = summary.get(output, math.nan) if summary else math.nan
        return float(v) if isinstance(v, int | float | np.floating) else math.nan

    def point_of(x):
        return x if isinstance(x, tuple) else (x,)

    skipped = 0
    for x, _status, s in store.points():
        learner.tell(x[0] if len(x) == 1 else x, value(s))
        skipped += 1

    def done() -> bool:
        if npoints is not None and learner.npoints >= npoints:
            return True
        return bool(loss_goal is not None and learner.npoints >= 3 and learner.loss() <= loss_goal)

    computed = failed = 0
    interrupted = False
    own = None
    dashboard = None
    nworkers = 0
    if not done():
        if client is None:
            client, own = _client(scheduler, workers, processes)
        dashboard = getattr(client, "dashboard_link", None)
        nworkers = max(1, _slots(client))
        pending = {}
        try:
            while not done() or pending:
                want = 0 if done() else 2 * nworkers - len(pending)
                if npoints is not None:
                    want = min(want, npoints - learner.npoints - len(pending))
                if want > 0:
                    xs, _ = learner.ask(want)
                    for x in xs:
                        p = spec.point_at(list(point_of(x)))
                        k = spec.key(p)
                        fut = client.submit(
                            run_point, spec.task, p, spec.keep, key=f"bkwaves-point-{k}", pure=False
                        )
                        pending[fut] = (x, k)
                if not pending:
                    break
                finished = wait(list(pending), return_when="FIRST_COMPLETED").done
                for fut in finished:
                    x, k = pending.pop(fut)
                    try:
                        s = fut.result()
                    except Exception as exc:  # noqa: BLE001 - recorded as a failed point
                        store.append(point_of(x), k, None, f"{type(exc).__name__}: {exc}")
                        learner.tell(x, math.nan)
                        failed += 1
                    else:
                        _write_point_files(store.path, k, s)
                        store.append(point_of(x), k, s, None)
                        learner.tell(x, value(s))
                        computed += 1
                    fut.release()
        except KeyboardInterrupt:
            interrupted = True
            client.cancel(list(pending))
        finally:
            if own is not None:
                client.close()
                own.close()
    _consolidate(store.path)
    return SweepResult(
        dataset=load_adaptive_result(out),
        out=str(out),
        computed=computed,
        skipped=skipped,
        failed=failed,
        wall_s=time.perf_counter() - t0,
        dashboard=dashboard,
        interrupted=interrupted,
        workers=nworkers,
        extra={"loss": float(learner.loss()) if learner.npoints >= 2 else math.nan},
    )
