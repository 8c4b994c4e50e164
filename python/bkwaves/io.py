"""Self-describing run outputs: snapshots to NetCDF (h5netcdf) or Zarr, tables to Parquet
and CSV, written incrementally so that an interrupted run keeps every completed record.

Layout for an output ``OUT.nc`` (or ``OUT.zarr``):

- ``OUT.nc``: snapshots, dimensions ``t`` and ``x``; variables as given
  (e.g. ``u``, ``u_t``, ``state``) with CF attributes; global attributes ``title``,
  ``Conventions``, ``bkwaves_version``, ``model``, ``seed``, ``config`` (the TOML text or
  JSON of the run), ``units_system`` and the parameters;
- ``OUT.events.parquet`` / ``OUT.events.csv``: the event catalog, and any other table
  (``OUT.<name>.parquet``), each with its column units in the Parquet metadata.

Crash safety: HDF5 (hence NetCDF-4) files are not safe against a crash while they are
open for writing. So during a run each NetCDF snapshot goes to its own small, complete
file in ``OUT.nc.parts/`` (written to a temporary name, then renamed); closing the writer,
normally or on Ctrl-C/SIGTERM, merges the parts into ``OUT.nc``. After a hard crash the
parts remain valid and :func:`load` reads them (or merges them: :func:`finalize`). Zarr
appends are safe by construction (the array metadata is updated after the chunks).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from . import __version__
from ._core import ParameterError

__all__ = ["RunWriter", "load", "load_tables", "finalize", "table_path"]

SUFFIXES = (".nc", ".zarr")


def table_path(out, name: str, suffix: str = ".parquet") -> Path:
    """Path of the table ``name`` beside the main output ``out``."""
    out = Path(out)
    return out.with_name(f"{out.name}.{name}{suffix}")


def _check_path(path) -> Path:
    p = Path(path)
    if p.suffix not in SUFFIXES:
        raise ParameterError(
            f"invalid output path = {str(p)!r}: allowed suffixes .nc (NetCDF) or .zarr (Zarr)"
        )
    return p


def _attr(v):
    if isinstance(v, bool):
        return int(v)
    if v is None:
        return ""
    if isinstance(v, dict | list | tuple):
        return json.dumps(v)
    return v


class RunWriter:
    """Append snapshots of fields on a fixed grid ``x`` and write tables beside them.

    ``variables`` maps names to ``(units, long_name, dtype)``; ``coord_units`` gives the
    units of ``x`` and ``t``; ``attrs`` are global attributes (config, params, seed, ...).
    Every :meth:`append` is complete on disk when it returns, so a crash loses at most the
    record being written. Use as a context manager (closing merges NetCDF parts).
    """

    def __init__(
        self,
        path,
        x,
        variables: dict,
        *,
        attrs: dict | None = None,
        coord_units: tuple[str, str] = ("1", "1"),
        overwrite: bool = True,
        resume_count: int | None = None,
    ):
        self.path = _check_path(path)
        self.x = np.asarray(x, dtype=float)
        self.variables = dict(variables)
        self.count = 0
        attrs = {
            "Conventions": "CF-1.10",
            "bkwaves_version": __version__,
            "source": "bkwaves (Burridge-Knopoff chain with Coulomb friction)",
            **(attrs or {}),
        }
        self.attrs = {k: _attr(v) for k, v in attrs.items()}
        self.x_units, self.t_units = coord_units
        self.path.parent.mkdir(parents=True, exist_ok=True)
        if resume_count is not None:
            self._resume(int(resume_count))
            return
        if self.path.exists() and not overwrite:
            raise ParameterError(f"output {self.path} exists (pass overwrite=True)")
        import shutil

        for stale in (self.path, self.parts_dir):
            if stale.is_dir():
                shutil.rmtree(stale)
            elif stale.exists():
                stale.unlink()

    @property
    def parts_dir(self) -> Path:
        return _parts_dir(self.path)

    def _resume(self, count: int):
        """Continue an existing output after its first ``count`` records (later records,
        written after the checkpoint by a run that then crashed, are dropped)."""
        import shutil

        self.count = count
        if self.path.suffix == ".nc":
            parts = self.parts_dir
            parts.mkdir(exist_ok=True)
            if self.path.exists():
                # the merged file becomes the base of the parts
                self.path.replace(parts / "base.nc")
            base = parts / "base.nc"
            n_base = 0
            if base.exists():
                import xarray as xr

                with xr.open_dataset(base, engine="h5netcdf") as ds:
                    n_base = ds.sizes["t"]
                    if n_base > count:
                        kept = ds.isel(t=slice(0, count)).load()
                if n_base > count:
                    tmp = parts / "base.tmp"
                    kept.to_netcdf(tmp, engine="h5netcdf")
                    tmp.replace(base)
                    n_base = count
            for f in parts.glob("part-*.nc"):
                if int(f.stem.split("-")[1]) >= count:
                    f.unlink()
            have = n_base + len(list(parts.glob("part-*.nc")))
        else:
            import zarr

            if not self.path.exists():
                raise ParameterError(f"cannot resume: output {self.path} not found")
            g = zarr.open_group(str(self.path), mode="r+")
            have = None
            for name in list(g.array_keys()):
                a = g[name]
                dims = getattr(a.metadata, "dimension_names", None) or a.attrs.get(
                    "_ARRAY_DIMENSIONS", ()
                )
                if dims and dims[0] == "t":
                    have = a.shape[0] if have is None else min(have, a.shape[0])
                    if a.shape[0] > count:
                        a.resize((count, *a.shape[1:]))
            have = count if have is None else min(have, count)
            del shutil
        if have < count:
            raise ParameterError(
                f"cannot resume: {self.path} holds {have} records, the checkpoint expects {count}"
            )

    def _dataset(self, t, fields):
        import xarray as xr

        return xr.Dataset(
            {
                name: (
                    ("t", "x"),
                    np.asarray(fields[name], dtype=dt)[None, :],
                    {"units": u, "long_name": ln},
                )
                for name, (u, ln, dt) in self.variables.items()
            },
            coords={
                "t": ("t", [t], {"units": self.t_units, "long_name": "time"}),
                "x": (
                    "x",
                    self.x,
                    {"units": self.x_units, "long_name": "position along the chain"},
                ),
            },
            attrs=self.attrs,
        )

    def append(self, t: float, **fields):
        """Append one snapshot at time ``t``; every declared variable must be given."""
        missing = set(self.variables) - set(fields)
        if missing:
            raise ParameterError(f"snapshot misses variables {sorted(missing)}")
        ds = self._dataset(float(t), fields)
        if self.path.suffix == ".nc":
            self.parts_dir.mkdir(exist_ok=True)
            part = self.parts_dir / f"part-{self.count:08d}.nc"
            tmp = part.with_suffix(".tmp")
            ds.to_netcdf(tmp, engine="h5netcdf")
            tmp.replace(part)
        elif self.count == 0:
            ds.to_zarr(self.path, mode="w", consolidated=False)
        else:
            ds.to_zarr(self.path, append_dim="t", consolidated=False)
        self.count += 1

    def write_table(self, name: str, df, units: dict | None = None, csv: bool = True):
        """Write a pandas table beside the output as Parquet (and CSV), atomically."""
        import pyarrow as pa
        import pyarrow.parquet as pq

        table = pa.Table.from_pandas(df, preserve_index=False)
        meta = dict(table.schema.metadata or {})
        meta[b"bkwaves_units"] = json.dumps(units or {}).encode()
        meta[b"bkwaves_version"] = __version__.encode()
        table = table.replace_schema_metadata(meta)
        target = table_path(self.path, name)
        tmp = target.with_name(target.name + ".tmp")
        pq.write_table(table, tmp)
        tmp.replace(target)
        if csv:
            c = table_path(self.path, name, ".csv")
            tmp = c.with_name(c.name + ".tmp")
            df.to_csv(tmp, index=False)
            tmp.replace(c)

    def close(self):
        """Finish the output (for NetCDF: merge the parts into one file)."""
        if self.path.suffix == ".nc" and self.parts_dir.exists():
            finalize(self.path)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def _parts_dir(path: Path) -> Path:
    return path.with_name(path.name + ".parts")


def _open_parts(parts: Path):
    import xarray as xr

    files = sorted(parts.glob("part-*.nc"))
    base = parts / "base.nc"
    if base.exists():
        files = [base, *files]
    if not files:
        raise ParameterError(f"no completed records in {parts}")
    dss = [xr.open_dataset(f, engine="h5netcdf") for f in files]
    ds = xr.concat(dss, dim="t", combine_attrs="override").load()
    for d in dss:
        d.close()
    return ds


def finalize(path) -> Path:
    """Merge the NetCDF parts of an output (left by a run that did not close) into ``path``."""
    import shutil

    p = _check_path(path)
    parts = _parts_dir(p)
    if not parts.exists():
        return p
    ds = _open_parts(parts)
    tmp = p.with_name(p.name + ".tmp")
    enc = {v: {"chunksizes": (1, ds.sizes["x"])} for v in ds.data_vars}
    ds.to_netcdf(tmp, engine="h5netcdf", unlimited_dims=["t"], encoding=enc)
    tmp.replace(p)
    shutil.rmtree(parts)
    return p


def load(path):
    """Open a run output: returns ``(dataset, catalog)``: the snapshots as an xarray
    Dataset and the event catalog as a pandas DataFrame (None if the run wrote none),
    with its column units in ``catalog.attrs["units"]``. An output whose run crashed
    before closing is read from its completed parts. Other tables: :func:`load_tables`."""
    ds, tables = load_tables(path)
    return ds, tables.get("events")


def load_tables(path):
    """Like :func:`load`, with every table: returns ``(dataset, {name: DataFrame})``."""
    import pyarrow.parquet as pq
    import xarray as xr

    p = _check_path(path)
    parts = _parts_dir(p)
    if p.suffix == ".nc" and parts.exists():
        ds = _open_parts(parts)
    elif not p.exists():
        raise ParameterError(f"output not found: {p}")
    elif p.suffix == ".nc":
        ds = xr.open_dataset(p, engine="h5netcdf")
    else:
        ds = xr.open_zarr(p, consolidated=False)
    tables = {}
    for f in sorted(p.parent.glob(f"{p.name}.*.parquet")):
        name = f.name[len(p.name) + 1 : -len(".parquet")]
        t = pq.read_table(f)
        df = t.to_pandas()
        meta = t.schema.metadata or {}
        df.attrs["units"] = json.loads(meta.get(b"bkwaves_units", b"{}"))
        tables[name] = df
    return ds, tables
