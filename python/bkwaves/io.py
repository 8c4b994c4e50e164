"""Self-describing run outputs: snapshots to NetCDF (h5netcdf) or Zarr, tables to Parquet
and CSV, written in blocks so that an interrupted run keeps every committed record.

Layout of a published output ``OUT.nc`` (or ``OUT.zarr``):

- ``OUT.nc``: snapshots, dimensions ``t`` and ``x``; variables as given
  (e.g. ``u``, ``u_t``, ``sliding``) with CF attributes; global attributes ``title``,
  ``Conventions``, ``bkwaves_version``, ``bkwaves_run_id``, ``model``, ``seed``,
  ``config`` (the TOML text or JSON of the run), ``units_system`` and the parameters;
- ``OUT.events.parquet`` / ``OUT.events.csv``: the event catalog, and any other table
  (``OUT.<name>.parquet``), each with its column units and the run id in the Parquet
  metadata (the CSV's SHA-256 too: that is how bkwaves recognises its own CSV).

Never destroy data. A writer refuses an existing output unless ``overwrite=True``, and
even then removes only files that carry bkwaves' marker (the ``bkwaves_version`` attribute
or Parquet metadata, the CSV checksum, the marker file of an unfinished run). It holds a
lock ``OUT.lock`` while it writes: a second writer on the same output fails at once.

Never lose what was computed. While a run goes on everything goes to ``OUT.partial/``
beside the output: NetCDF snapshots as complete block files (built in memory, written
to a temporary name and renamed), a Zarr store whose records are all-or-nothing (the
variables of a block are written first, then the group attribute ``bkwaves_records``,
the committed length, advances), and each table as Parquet parts holding the rows
appended since the previous commit (rows are appended, never rewritten). A commit writes
the tables first, then the snapshots, so committed snapshots always have their
catalog. Closing the writer after a complete run merges the parts and renames the
results onto ``OUT`` and its tables (an earlier output is replaced only then), with
the same run id in every file: :func:`load` never pairs snapshots with the catalog of
another run. An interrupted or failed run leaves ``OUT.partial/``: :func:`load` reads
it (up to its last committed record, saying what it dropped), ``bkwaves run --resume``
continues it and :func:`finalize` publishes it as it is.

HDF5 never writes to disk in the run's process (a write it fails ends the process by
SIGSEGV): NetCDF blocks are built in memory and written by Python, and the merged file
is sized first and written by Python or by a child process (``bkwaves._nc_publish``).
"""

from __future__ import annotations

import errno
import hashlib
import json
import os
import shutil
import time
import uuid
import warnings
from pathlib import Path

import numpy as np

from . import __version__
from ._core import ParameterError

__all__ = [
    "RunWriter",
    "load",
    "load_tables",
    "finalize",
    "table_path",
    "partial_path",
    "NO_SPACE",
    "OutputError",
]

SUFFIXES = (".nc", ".zarr")
PARTIAL_FORMAT = "bkwaves-partial-1"
MARKER = "bkwaves-run.json"
RECORDS_ATTR = "bkwaves_records"
RUN_ID_ATTR = "bkwaves_run_id"
#: errno values of a write that failed for lack of space
NO_SPACE = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG})
#: How xarray declares a NaN fill value of a float64 Zarr (v3) array: its bytes, base64
_NAN_FILL = "AAAAAAAA+H8="
#: Bytes of one chunk of a published NetCDF variable (and of the pieces merged at once)
NC_CHUNK_BYTES = 4 << 20


class OutputError(OSError):
    """Writing a run's output failed (a full disk, a folder removed or made read-only):
    ``strerror`` is one line saying what failed, what was kept and how to continue."""


class PublishStopped(Exception):
    """A signal arrived while a complete run was being published: nothing was renamed,
    ``OUT.partial/`` is kept as it was."""


def table_path(out, name: str, suffix: str = ".parquet") -> Path:
    """Path of the table ``name`` beside the main output ``out``.

    Parameters
    ----------
    out : str or pathlib.Path
        The main output.
    name : str
        The table's name (``events``, ``slips``, ...).
    suffix : str, default ".parquet"
        The file type.

    Returns
    -------
    pathlib.Path
        ``OUT.NAME.parquet`` (or the suffix given).

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.io.table_path("run.nc", "events").name
    'run.nc.events.parquet'
    """
    out = Path(out)
    return out.with_name(f"{out.name}.{name}{suffix}")


def partial_path(out) -> Path:
    """Where the unfinished run writing ``out`` keeps its records: ``OUT.partial/``.

    Parameters
    ----------
    out : str or pathlib.Path
        The main output.

    Returns
    -------
    pathlib.Path
        ``OUT.partial``.

    Examples
    --------
    >>> import bkwaves as bk
    >>> bk.io.partial_path("run.zarr").name
    'run.zarr.partial'
    """
    out = Path(out)
    return out.with_name(out.name + ".partial")


def _lock_path(out: Path) -> Path:
    return out.with_name(out.name + ".lock")


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


def human_bytes(n: float) -> str:
    for unit in ("B", "kB", "MB", "GB", "TB"):
        if abs(n) < 1000 or unit == "TB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000
    return f"{n} B"  # pragma: no cover


def _write_bytes(path: Path, data) -> None:
    """Write ``data`` to ``path`` completely or not at all (temporary name, rename)."""
    tmp = path.with_name(path.name + ".tmp")
    try:
        with open(tmp, "wb") as f:
            f.write(data)
    except OSError as e:
        tmp.unlink(missing_ok=True)
        if e.filename is None:  # (a failed write names no file: the one meant is named)
            raise OSError(e.errno, e.strerror, str(path)) from None
        raise
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    tmp.replace(path)


LOCK_TAG = "bkwaves lock"


def _lock_text_is_ours(text: str) -> bool:
    """Is this the text of a lock bkwaves wrote (now, or a PID alone as before)?"""
    if text.startswith(LOCK_TAG + " "):
        return True
    return text.strip().isdigit() and text.endswith("\n") and text.count("\n") == 1


class _Lock:
    """An exclusive ``flock`` on ``OUT.lock``, taken without waiting. The file is created
    with its text at once (a temporary file linked to the name), so a file of that name
    without bkwaves' text is someone else's: it is refused, never overwritten nor
    removed. A lock left by a killed run is taken over. The file is removed on release
    (if it is still the one locked)."""

    def __init__(self, path: Path, out: Path):
        import fcntl

        self.path = path
        self.fd = None
        text = f"{LOCK_TAG} pid {os.getpid()}\n".encode()
        while True:
            tmp = path.with_name(f".{path.name}.{os.getpid()}.{uuid.uuid4().hex[:8]}.tmp")
            try:
                with open(tmp, "xb") as f:
                    f.write(text)
                try:
                    os.link(tmp, path)
                except OSError as e:
                    if e.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP):
                        raise
                    # no hard links here: create it exclusively, then write
                    fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_EXCL, 0o644)
                    try:
                        os.write(fd, text)
                    finally:
                        os.close(fd)
                created = True
            except FileExistsError:
                created = False
            finally:
                tmp.unlink(missing_ok=True)
            try:
                fd = os.open(path, os.O_RDWR)
            except FileNotFoundError:  # removed meanwhile by its holder: try again
                continue
            if not created:
                held = os.read(fd, 256).decode(errors="replace")
                if not _lock_text_is_ours(held):
                    os.close(fd)
                    raise ParameterError(
                        f"{path} exists and was not written by bkwaves (not a bkwaves "
                        "lock): bkwaves will not overwrite or remove it; move it away or "
                        "choose another output"
                    )
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.lseek(fd, 0, os.SEEK_SET)
                held = os.read(fd, 256).decode(errors="replace").strip()
                os.close(fd)
                holder = held.removeprefix(LOCK_TAG).strip()
                who = f" (process {holder.removeprefix('pid ')})" if holder else ""
                raise ParameterError(
                    f"output {out} is being written by another bkwaves run{who}: wait for "
                    f"it to end or choose another output (lock {path})"
                ) from None
            try:
                same = os.path.samestat(os.fstat(fd), os.stat(path))
            except FileNotFoundError:
                same = False
            if same:
                break
            os.close(fd)  # the holder removed it meanwhile: lock the new one
        if not created:  # a lock left by a run that was killed: ours now
            os.ftruncate(fd, 0)
            os.pwrite(fd, text, 0)
        self.fd = fd

    def release(self):
        if self.fd is None:
            return
        try:
            if os.path.samestat(os.fstat(self.fd), os.stat(self.path)):
                self.path.unlink(missing_ok=True)
        except FileNotFoundError:
            pass
        os.close(self.fd)
        self.fd = None


def _start_error(out: Path, e: OSError, doing: str) -> OutputError:
    """The one-line error of an output that cannot be started (nothing was computed)."""
    where = f" ({e.filename})" if getattr(e, "filename", None) else ""
    return OutputError(
        e.errno,
        f"cannot write {out}: {e.strerror or e}{where} while {doing}; nothing was "
        "computed or kept; free space or fix the folder, then run again",
    )


# --- what bkwaves wrote ---------------------------------------------------------------


def _parquet_meta(path: Path) -> dict:
    import pyarrow.parquet as pq

    try:
        return dict(pq.read_schema(path).metadata or {})
    except Exception:  # noqa: BLE001 - not Parquet: not ours
        return {}


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _main_attrs(path: Path) -> dict:
    """Global attributes of a NetCDF file or Zarr group ({} if it is neither)."""
    try:
        if path.suffix == ".zarr":
            doc = json.loads((path / "zarr.json").read_text())
            return dict(doc.get("attributes", {}))
        import h5py

        with h5py.File(path, "r") as f:
            return {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
    except Exception:  # noqa: BLE001 - unreadable: not ours
        return {}


def _is_ours(path: Path, out: Path) -> bool:
    """Did bkwaves write ``path`` (an item of the output ``out``)? Checked before removing."""
    if path == partial_path(out):
        return _read_marker(path) is not None
    if path == out:
        if "bkwaves_version" not in _main_attrs(path):
            return False
        if path.is_dir():  # a Zarr group: its zarr.json and arrays, nothing else
            return _zarr_group_is_ours(path)
        return True
    if path.suffix == ".parquet":
        return b"bkwaves_version" in _parquet_meta(path)
    if path.suffix == ".csv":
        meta = _parquet_meta(path.with_suffix(".parquet"))
        sha = meta.get(b"bkwaves_csv_sha256")
        return sha is not None and sha.decode() == _sha256(path)
    if path.name == out.name + ".checkpoint":
        from . import _checkpoint

        try:  # data only (no pickle): safe to read whatever the file is
            _checkpoint.read(path, "run", "bkwaves run")
        except Exception:  # noqa: BLE001 - not a bkwaves run checkpoint
            return False
        return True
    return False


def _zarr_group_is_ours(root: Path) -> bool:
    """Does the Zarr group at ``root`` hold nothing but what bkwaves writes, at every
    depth: its ``zarr.json`` and arrays, each an array's ``zarr.json`` and its chunks
    (``c/`` and below: numbered files and folders only), no links?"""

    def chunks_only(d: Path) -> bool:
        for e in d.iterdir():
            if e.is_symlink() or not e.name.isdigit():
                return False
            if e.is_dir() and not chunks_only(e):
                return False
        return True

    def array_only(d: Path) -> bool:
        for e in d.iterdir():
            if e.is_symlink():
                return False
            if e.name == "zarr.json" and e.is_file():
                continue
            if e.name == "c" and e.is_dir() and chunks_only(e):
                continue
            return False
        return True

    for e in root.iterdir():
        if e.is_symlink():
            return False
        if e.name == "zarr.json" and e.is_file():
            continue
        if e.is_dir() and (e / "zarr.json").is_file() and array_only(e):
            continue
        return False
    return True


def _published_items(out: Path) -> list[Path]:
    """The files of a published output: the main output and its tables."""
    items = [out] if out.exists() or out.is_symlink() else []
    for p in sorted(out.parent.glob(f"{out.name}.*")):
        rest = p.name[len(out.name) + 1 :]
        stem, _, suffix = rest.partition(".")
        if suffix in ("parquet", "csv") and stem:
            items.append(p)
    return items


def _read_marker(partial: Path) -> dict | None:
    try:
        m = json.loads((partial / MARKER).read_text())
    except (OSError, ValueError):
        return None
    return m if isinstance(m, dict) and m.get("format") == PARTIAL_FORMAT else None


# --- the writer ----------------------------------------------------------------------


class RunWriter:
    """Append snapshots of fields on a fixed grid ``x`` (and ``y``: a planar grid, the
    fields' dims then (t, y, x)) and tables of rows, in blocks.

    ``variables`` maps names to ``(units, long_name, dtype)`` or ``(units, long_name,
    dtype, {more attributes})``; ``coord_units`` gives the units of ``x`` and ``t`` and
    ``coord_attrs`` more attributes of each (e.g. how they are scaled). ``attrs`` are
    global attributes (config, params, seed, ...).

    Records are buffered and committed in blocks: when the buffer holds ``block_bytes``,
    when its oldest record is ``flush_every`` seconds old, on :meth:`commit` and on
    closing. A crash loses at most the uncommitted buffer. Use as a context manager:
    leaving the block normally publishes the output (see the module's docstring), an
    exception leaves the committed records in ``OUT.partial/``.

    An existing output is refused unless ``overwrite`` (then only files bkwaves wrote are
    replaced, when the new output is published). ``resume_count`` continues the unfinished
    run of ``OUT.partial/`` after its first ``resume_count`` records (and ``resume_rows``:
    the first rows of each table), dropping those written later.

    Parameters
    ----------
    path : str or pathlib.Path
        The output, ``OUT.nc`` or ``OUT.zarr``.
    x : array_like
        The grid (in the unit ``coord_units`` gives; the paper's dimensionless x by
        default).
    variables : dict
        Name -> ``(units, long_name, dtype[, attrs])``.
    y : array_like, optional
        Positions across of a planar grid (dimensionless or m): the fields' dims are then
        (t, y, x).
    attrs : dict, optional
        Global attributes.
    coord_units : tuple of str, default ("1", "1")
        Units of x and t ("1": dimensionless).
    coord_attrs : tuple of dict, default ({}, {})
        More attributes of x and t, and optionally of y (default: x's).
    overwrite : bool, default False
        Replace an existing output (only files bkwaves wrote).
    resume_count : int, optional
        Continue after this many records of ``OUT.partial/``.
    resume_rows : dict, optional
        Table name -> rows to keep when resuming.
    block_bytes : int, default 8 MiB
        Commit when the buffer holds this many bytes.
    flush_every : float, default 5
        Commit when the oldest buffered record is this old [s].

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
    >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
    >>> with w:
    ...     w.append(0.0, u=[0.1, 0.2, 0.3])
    ...     w.append_block([1.0, 2.0], u=[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]])
    >>> ds, catalog = bk.io.load(out)
    >>> ds.u.shape, ds.t.values.tolist()
    ((3, 3), [0.0, 1.0, 2.0])
    """

    def __init__(
        self,
        path,
        x,
        variables: dict,
        *,
        y=None,
        attrs: dict | None = None,
        coord_units: tuple[str, str] = ("1", "1"),
        coord_attrs: tuple[dict, dict] = ({}, {}),
        overwrite: bool = False,
        resume_count: int | None = None,
        resume_rows: dict | None = None,
        block_bytes: int = 8 << 20,
        flush_every: float = 5.0,
    ):
        self.path = _check_path(path)
        self.partial = partial_path(self.path)
        self.x = np.asarray(x, dtype=float)
        self.y = None if y is None else np.asarray(y, dtype=float)
        # the dims of a snapshot field and the shape of one record
        self.space = ("x",) if self.y is None else ("y", "x")
        self.record_shape = (len(self.x),) if self.y is None else (len(self.y), len(self.x))
        self.variables = {}
        for name, spec in variables.items():
            units, long_name, dtype, *more = spec
            self.variables[name] = (units, long_name, np.dtype(dtype), dict(*more))
        self.x_units, self.t_units = coord_units
        self.x_attrs, self.t_attrs = (dict(a) for a in coord_attrs[:2])
        self.y_attrs = dict(coord_attrs[2]) if len(coord_attrs) > 2 else self.x_attrs
        self.block_bytes = int(block_bytes)
        self.flush_every = float(flush_every)
        self.count = 0  # committed records
        self.closed = False
        self._buf_t: list[float] = []
        self._buf: dict[str, list] = {name: [] for name in self.variables}
        self._buf_bytes = 0
        self._buf_since = None
        self._tables: dict[str, dict] = {}
        self._replaces: list[Path] = []
        self._created = False
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._lock = _Lock(_lock_path(self.path), self.path)
        except OSError as e:
            raise _start_error(self.path, e, "taking its lock") from None
        try:
            if resume_count is not None:
                self._resume(int(resume_count), dict(resume_rows or {}), attrs)
            else:
                self._start(overwrite, attrs)
        except BaseException as e:
            if self._created:  # made by this call, holding nothing yet: not left behind
                shutil.rmtree(self.partial, ignore_errors=True)
            self._lock.release()
            if isinstance(e, OSError) and not isinstance(e, OutputError):
                raise _start_error(self.path, e, "creating its records") from None
            raise

    # --- opening -----------------------------------------------------------------------

    def _global_attrs(self, attrs, run_id):
        attrs = {
            "Conventions": "CF-1.10",
            "bkwaves_version": __version__,
            "source": "bkwaves (Burridge-Knopoff chain with Coulomb friction)",
            **(attrs or {}),
            RUN_ID_ATTR: run_id,
        }
        return {k: _attr(v) for k, v in attrs.items()}

    def _start(self, overwrite: bool, attrs):
        from .runner import checkpoint_path

        existing = _published_items(self.path)
        leftovers = [p for p in (self.partial, checkpoint_path(self.path)) if p.exists()]
        if existing or leftovers:
            names = ", ".join(p.name for p in existing + leftovers)
            if not overwrite:
                # --resume only where it can work: an unfinished run that left a checkpoint
                resumable = self.partial.exists() and checkpoint_path(self.path).exists()
                if resumable:
                    hint = "; or continue its unfinished run with --resume"
                elif self.partial.exists():
                    hint = (
                        " (its unfinished run left no checkpoint to resume from; "
                        "bkwaves.io.finalize publishes what it wrote)"
                    )
                else:
                    hint = ""
                raise ParameterError(
                    f"output {self.path} exists ({names}): pass --overwrite (overwrite=True) "
                    f"to replace it{hint}"
                )
            foreign = [p for p in existing + leftovers if not _is_ours(p, self.path)]
            if foreign:
                raise ParameterError(
                    f"not replacing {', '.join(str(p) for p in foreign)}: not written by "
                    "bkwaves (no bkwaves marker); move it away or choose another output"
                )
            # an unfinished earlier run is discarded now; a published output is replaced
            # only when the new one is complete
            if self.partial.exists():
                shutil.rmtree(self.partial)
            checkpoint_path(self.path).unlink(missing_ok=True)
            self._replaces = existing
        self.run_id = uuid.uuid4().hex
        self.attrs = self._global_attrs(attrs, self.run_id)
        self.partial.mkdir()
        self._created = True
        (self.partial / "tables").mkdir()
        marker = {
            "format": PARTIAL_FORMAT,
            "run_id": self.run_id,
            "output": self.path.name,
            "bkwaves_version": __version__,
            "replaces": [p.name for p in self._replaces],
        }
        _write_bytes(self.partial / MARKER, json.dumps(marker).encode())
        # what a commit needs, imported now: a commit, and so the answer to a signal,
        # never waits for imports
        import pandas  # noqa: F401
        import pyarrow.parquet  # noqa: F401

        if self.path.suffix == ".nc":
            self._blocks_dir.mkdir()
            import h5netcdf  # noqa: F401
        else:
            self._create_zarr()

    def _resume(self, count: int, rows: dict, attrs):
        marker = _read_marker(self.partial)
        if marker is None:
            state = "was published" if self.path.exists() else "has no records"
            raise ParameterError(
                f"cannot resume {self.path}: no unfinished run in {self.partial} (the run {state})"
            )
        self.run_id = marker["run_id"]
        self._replaces = [self.path.with_name(n) for n in marker.get("replaces", [])]
        self.attrs = self._global_attrs(attrs, self.run_id)
        if self.path.suffix == ".nc":
            have = 0
            for start, n, f in _blocks(self._blocks_dir):
                if start >= count:
                    f.unlink()
                elif start + n > count:
                    _write_bytes(f, _copy_nc(f, count - start))
                    have += count - start
                else:
                    have += n
        else:
            import zarr

            g = zarr.open_group(str(self._zarr_store), mode="r+")
            have = min(_zarr_committed(g), count)
            g.attrs[RECORDS_ATTR] = have
            for _, a in _zarr_t_arrays(g):
                if a.shape[0] > have:
                    a.resize((have, *a.shape[1:]))
        if have < count:
            raise ParameterError(
                f"cannot resume: {self.partial} holds {have} records, the checkpoint "
                f"expects {count}"
            )
        self.count = count
        for d in sorted((self.partial / "tables").iterdir()):
            keep = rows.get(d.name)
            kept = 0
            for start, n, f in _table_parts(d):
                if keep is not None and start >= keep:
                    f.unlink()
                elif keep is not None and start + n > keep:
                    _write_parquet_part(f, _read_parquet(f).slice(0, keep - start))
                    kept += keep - start
                else:
                    kept += n
            meta = _parquet_meta(next(iter(_table_parts(d)))[2]) if kept else {}
            self._tables[d.name] = {
                "rows": kept,
                "buf": [],
                "units": json.loads(meta.get(b"bkwaves_units", b"{}")),
                "scales": json.loads(meta.get(b"bkwaves_scales", b"{}")),
                "descriptions": json.loads(meta.get(b"bkwaves_descriptions", b"{}")),
                "csv": meta.get(b"bkwaves_csv", b"1") == b"1",
            }

    @property
    def _blocks_dir(self) -> Path:
        return self.partial / "snapshots"

    @property
    def _zarr_store(self) -> Path:
        return self.partial / self.path.name

    def _dataset(self, t, fields):
        import xarray as xr

        coords = {"t": ("t", np.asarray(t, dtype=float), self._coord_attrs("t"))}
        for name in self.space:
            coords[name] = (name, getattr(self, name), self._coord_attrs(name))
        return xr.Dataset(
            {
                name: (
                    ("t", *self.space),
                    np.asarray(fields[name], dtype=dt),
                    {"units": u, "long_name": ln, **more},
                )
                for name, (u, ln, dt, more) in self.variables.items()
            },
            coords=coords,
            attrs=self.attrs,
        )

    def _nc_block(self, t, fields) -> bytes:
        """A NetCDF-4 file of the records ``t`` built in memory by h5netcdf (HDF5 crashes
        the process when a write fails for lack of space, so the file is written by
        Python). Variables contiguous: one write each. The same file as xarray writes
        for :meth:`_dataset`, without its start-up cost (its first ``to_netcdf`` imports
        dask and distributed: a second and more, where a commit must be prompt)."""
        import io

        import h5netcdf

        bio = io.BytesIO()
        with h5netcdf.File(bio, "w") as f:
            f.attrs.update(self.attrs)
            f.dimensions = {"t": len(t), **{k: len(getattr(self, k)) for k in self.space}}
            coords = [("t", np.asarray(t, dtype=float))] + [
                (k, getattr(self, k)) for k in self.space
            ]
            for name, data in coords:
                v = f.create_variable(name, (name,), "f8", data=data)
                v.attrs.update(self._coord_attrs(name))
            for name, (u, ln, dt, more) in self.variables.items():
                data = np.asarray(fields[name], dtype=dt)
                v = f.create_variable(name, ("t", *self.space), dt, data=data)
                v.attrs.update({"units": u, "long_name": ln, **more})
        return bio.getvalue()

    def _create_zarr(self):
        """The empty store, made by zarr directly (as xarray's ``to_zarr`` makes it: CF
        attributes, dimension names, NaN fill values declared in ``_FillValue``), in a
        few milliseconds: xarray's first ``to_zarr`` imports dask (a second and more),
        and a signal must not wait for it."""
        import zarr

        nx = int(np.prod(self.record_shape))
        row = max(1, nx * max(dt.itemsize for _, _, dt, _ in self.variables.values()))
        chunk_t = int(min(max(1, (1 << 20) // row), 4096))
        g = zarr.open_group(str(self._zarr_store), mode="w", zarr_format=3)
        g.attrs.update({**self.attrs, RECORDS_ATTR: 0})

        def array(name, dims, shape, chunks, dtype, attrs, data=None):
            dtype = np.dtype(dtype)
            attrs = dict(attrs)
            if dtype.kind == "f":
                attrs["_FillValue"] = _NAN_FILL
            a = g.create_array(
                name,
                shape=shape,
                chunks=chunks,
                dtype=dtype,
                fill_value=np.nan if dtype.kind == "f" else 0,
                dimension_names=dims,
                attributes=attrs,
            )
            if data is not None:
                a[...] = data

        array("t", ("t",), (0,), (4096,), "f8", self._coord_attrs("t"))
        for k in self.space:
            c = getattr(self, k)
            array(k, (k,), (len(c),), (max(len(c), 1),), "f8", self._coord_attrs(k), c)
        shape = self.record_shape
        for name, (u, ln, dt, more) in self.variables.items():
            attrs = {"units": u, "long_name": ln, **more}
            array(name, ("t", *self.space), (0, *shape), (chunk_t, *shape), dt, attrs)

    def _coord_attrs(self, name: str) -> dict:
        if name == "t":
            return {"units": self.t_units, "long_name": "time", **self.t_attrs}
        if name == "y":
            return {"units": self.x_units, "long_name": "position across", **self.y_attrs}
        along = "position along the chain" if self.y is None else "position along the slip"
        return {"units": self.x_units, "long_name": along, **self.x_attrs}

    # --- appending ---------------------------------------------------------------------

    def append(self, t: float, **fields):
        """Append one snapshot at time ``t``; every declared variable must be given.

        Parameters
        ----------
        t : float
            Its time (the unit of ``coord_units``; dimensionless by default).
        **fields : array_like
            One array on the grid per declared variable.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> w.append(0.0, u=[0.1, 0.2, 0.3])
        >>> w.records
        1
        >>> w.abandon()
        """
        self.append_block([t], **{k: np.asarray(v)[None, ...] for k, v in fields.items()})

    def append_block(self, t, **fields):
        """Append snapshots at the times ``t`` (fields: one row per time).

        Parameters
        ----------
        t : array_like
            Their times (the unit of ``coord_units``; dimensionless by default).
        **fields : array_like
            Per declared variable, an array of shape (len(t), len(x)).

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> w.append_block([1.0, 2.0], u=[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]])
        >>> w.records
        2
        >>> w.abandon()
        """
        missing = set(self.variables) - set(fields)
        if missing:
            raise ParameterError(f"snapshot misses variables {sorted(missing)}")
        t = np.atleast_1d(np.asarray(t, dtype=float))
        for name, (_, _, dt, _) in self.variables.items():
            a = np.asarray(fields[name], dtype=dt).reshape(len(t), *self.record_shape)
            self._buf[name].append(a)
            self._buf_bytes += a.nbytes
        self._buf_t.extend(t.tolist())
        self._note_buffered()

    def append_rows(
        self,
        name: str,
        df,
        units: dict | None = None,
        csv: bool | None = None,
        scales: dict | None = None,
        descriptions: dict | None = None,
    ):
        """Append the rows of the pandas table ``df`` to the table ``name`` (created on
        first use, with CSV beside the Parquet unless ``csv=False``). ``units`` gives the
        units of columns, ``scales`` how dimensionless columns are scaled,
        ``descriptions`` what columns are (read back into ``df.attrs``).

        Parameters
        ----------
        name : str
            The table.
        df : pandas.DataFrame
            Its new rows.
        units : dict, optional
            Column -> unit ("1": dimensionless).
        csv : bool, optional
            Also write CSV (default True for a new table).
        scales : dict, optional
            Column -> factor to physical units.
        descriptions : dict, optional
            Column -> what it is.

        Examples
        --------
        >>> import pandas as pd
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> with w:
        ...     w.append(0.0, u=[0.1, 0.2, 0.3])
        ...     w.append_rows("events", pd.DataFrame({"t_start": [0.5]}), units={"t_start": "1"})
        >>> bk.io.load_tables(out)[1]["events"].t_start.tolist()
        [0.5]
        """
        tb = self._tables.setdefault(
            name, {"rows": 0, "buf": [], "units": {}, "scales": {}, "descriptions": {}, "csv": True}
        )
        if units:
            tb["units"] = dict(units)
        if scales:
            tb["scales"] = dict(scales)
        if descriptions:
            tb["descriptions"] = dict(descriptions)
        if csv is not None:
            tb["csv"] = bool(csv)
        if len(df) or (tb["rows"] == 0 and not tb["buf"]):  # (an empty table: its schema)
            tb["buf"].append(df)
            self._buf_bytes += int(df.memory_usage(index=False).sum())
        self._note_buffered()

    def write_table(self, name: str, df, units: dict | None = None, csv: bool = True, scales=None):
        """Set the whole table ``name`` (replacing rows written before).

        Parameters
        ----------
        name : str
            The table.
        df : pandas.DataFrame
            All its rows.
        units : dict, optional
            Column -> unit ("1": dimensionless).
        csv : bool, default True
            Also write CSV.
        scales : dict, optional
            Column -> factor to physical units.

        Examples
        --------
        >>> import pandas as pd
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> w.write_table("events", pd.DataFrame({"a": [1, 2]}))
        >>> w.write_table("events", pd.DataFrame({"a": [3]}))
        >>> w.table_rows("events")
        1
        >>> w.abandon()
        """
        d = self.partial / "tables" / name
        if d.exists():
            shutil.rmtree(d)
        self._tables.pop(name, None)
        self.append_rows(name, df, units, csv, scales)

    def table_rows(self, name: str) -> int:
        """Rows of the table ``name`` written or buffered so far.

        Parameters
        ----------
        name : str
            The table.

        Returns
        -------
        int
            Its rows (0 for a table never written).

        Examples
        --------
        >>> import pandas as pd
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> w.append_rows("events", pd.DataFrame({"t_start": [0.5, 1.5]}))
        >>> w.table_rows("events"), w.table_rows("slips")
        (2, 0)
        >>> w.abandon()
        """
        tb = self._tables.get(name)
        return 0 if tb is None else tb["rows"] + sum(len(d) for d in tb["buf"])

    @property
    def record_bytes(self) -> int:
        """Bytes of one snapshot in memory (the fields and its time)."""
        nodes = int(np.prod(self.record_shape))
        return 8 + nodes * sum(dt.itemsize for _, _, dt, _ in self.variables.values())

    @property
    def records(self) -> int:
        """Snapshots appended so far (committed or buffered)."""
        return self.count + len(self._buf_t)

    def _note_buffered(self):
        now = time.monotonic()
        if self._buf_since is None:
            self._buf_since = now
        if self._buf_bytes >= self.block_bytes or now - self._buf_since >= self.flush_every:
            self.commit()

    def commit(self):
        """Write the buffered rows of every table, then the buffered snapshots.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> w.append(0.0, u=[0.1, 0.2, 0.3])
        >>> w.commit()
        >>> w.count                                   # committed records
        1
        >>> w.abandon()
        """
        for name, tb in self._tables.items():
            if tb["buf"]:
                import pandas as pd

                df = pd.concat(tb["buf"], ignore_index=True)
                d = self.partial / "tables" / name
                d.mkdir(exist_ok=True)
                _write_parquet_part(d / f"part-{tb['rows']:012d}.parquet", self._arrow(df, tb))
                tb["rows"] += len(df)
                tb["buf"] = []
        if self._buf_t:
            t = np.asarray(self._buf_t)
            fields = {name: np.concatenate(rows) for name, rows in self._buf.items()}
            self._buf_t = []
            self._buf = {name: [] for name in self.variables}
            self._buf_bytes = 0
            self._write_records(t, fields)
        self._buf_bytes = 0
        self._buf_since = None

    def _write_records(self, t, fields):
        """Commit the records ``t`` (fields: one row each); on a full disk, as many of
        them as fit (halves, quarters, ... down to single records), then raise."""
        try:
            if self.path.suffix == ".nc":
                _write_bytes(
                    self._blocks_dir / f"block-{self.count:010d}.nc", self._nc_block(t, fields)
                )
            else:
                self._append_zarr(t, fields)
        except OSError as e:
            if e.errno not in NO_SPACE or len(t) == 1:
                raise
            h = len(t) // 2
            self._write_records(t[:h], {k: v[:h] for k, v in fields.items()})
            self._write_records(t[h:], {k: v[h:] for k, v in fields.items()})
            return
        self.count += len(t)

    def _append_zarr(self, t, fields):
        """Write the variables of the block, then advance the committed length."""
        import zarr

        g = zarr.open_group(str(self._zarr_store), mode="r+")
        n, k = self.count, len(t)
        for name, data in [*fields.items(), ("t", t)]:
            a = g[name]
            a.resize((n + k, *a.shape[1:]))
            a[n : n + k] = data
        g.attrs[RECORDS_ATTR] = n + k

    def _arrow(self, df, tb):
        import pyarrow as pa

        table = pa.Table.from_pandas(df, preserve_index=False)
        meta = dict(table.schema.metadata or {})
        meta[b"bkwaves_units"] = json.dumps(tb["units"]).encode()
        meta[b"bkwaves_scales"] = json.dumps(tb["scales"]).encode()
        meta[b"bkwaves_descriptions"] = json.dumps(tb.get("descriptions", {})).encode()
        meta[b"bkwaves_version"] = __version__.encode()
        meta[b"bkwaves_run_id"] = self.run_id.encode()
        meta[b"bkwaves_csv"] = b"1" if tb["csv"] else b"0"
        return table.replace_schema_metadata(meta)

    # --- closing -----------------------------------------------------------------------

    def close(self, publish: bool = True, remove=(), stop=None, on_stop=None, spare=()) -> bool:
        """Commit the buffer; with ``publish`` (a complete run) merge the parts and rename
        the output and its tables onto ``OUT``, replacing an earlier output, then remove
        ``OUT.partial/`` and the files in ``remove``. Without: keep ``OUT.partial/``.
        When the publication fails for lack of space, the files in ``spare`` (the
        checkpoint of the run's end) are removed and it is tried once more, unless the
        space the output needs is known and their room would not make it fit.

        ``stop``: a function asked between the pieces of the merge; when it returns true
        the publication is abandoned before anything is renamed (``OUT.partial/`` kept),
        ``on_stop()`` is called while the lock is still held, and close returns False.

        Parameters
        ----------
        publish : bool, default True
            Publish the output (a complete run).
        remove : iterable of path, default ()
            Files to remove once published (e.g. the checkpoint).
        stop : callable, optional
            Asked between the pieces of the merge.
        on_stop : callable, optional
            Called when ``stop`` abandons the publication.
        spare : iterable of path, default ()
            Files to give up for room when the publication fails for lack of space.

        Returns
        -------
        bool
            True when the output was published.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> w.append(0.0, u=[0.1, 0.2, 0.3])
        >>> w.close(publish=False), os.path.exists(out + ".partial")
        (False, True)
        """
        if self.closed:
            return False
        try:
            self.commit()
            if publish:
                try:
                    try:
                        _publish(self.path, self.partial, self._replaces, remove, stop)
                    except OSError as e:
                        spared = [Path(f) for f in spare if Path(f).exists()]
                        # (past a file-size limit, EFBIG, other files' room is no help)
                        if e.errno not in NO_SPACE or e.errno == errno.EFBIG or not spared:
                            raise
                        room = sum(f.stat().st_size for f in spared)
                        need = getattr(e, "need", None)  # (the NetCDF's, when known)
                        if need is not None and getattr(e, "free", 0) + room < need:
                            raise  # not enough either way: the spared files are kept
                        for f in spared:  # their room may be what the output lacks
                            f.unlink()
                        _publish(self.path, self.partial, self._replaces, remove, stop)
                except OSError as e:
                    e.publishing = True  # (every record is kept: the run can publish again)
                    raise
                except PublishStopped:
                    if on_stop is not None:
                        on_stop()
                    return False
                return True
            return False
        finally:
            self.closed = True
            self._lock.release()

    def abandon(self):
        """Stop after a failed write: drop the buffer, keep what was committed, unlock.

        Examples
        --------
        >>> import os, tempfile
        >>> import bkwaves as bk
        >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
        >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
        >>> w.append(0.0, u=[0.1, 0.2, 0.3])
        >>> w.abandon()
        >>> os.path.exists(out)
        False
        """
        self._buf_t, self._buf_bytes = [], 0
        self._buf = {name: [] for name in self.variables}
        for tb in self._tables.values():
            tb["buf"] = []
        for tmp in self.partial.rglob("*.tmp"):
            tmp.unlink(missing_ok=True)
        if (self.partial / "final").exists():  # a publication cut short
            shutil.rmtree(self.partial / "final")
        self.closed = True
        self._lock.release()

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            self.close()
        elif isinstance(exc, OSError) and exc.errno in NO_SPACE:
            self.abandon()
        else:
            self.close(publish=False)
        return False


# --- parts -----------------------------------------------------------------------------


def _blocks(d: Path):
    """(first record, records, file) of the NetCDF blocks in ``d``, in order."""
    import h5netcdf

    out = []
    for f in sorted(d.glob("block-*.nc")):
        with h5netcdf.File(f, "r") as nc:
            out.append((int(f.stem.split("-")[1]), nc.dimensions["t"].size, f))
    return out


def _table_parts(d: Path):
    """(first row, rows, file) of the Parquet parts in ``d``, in order."""
    import pyarrow.parquet as pq

    return [
        (int(f.stem.split("-")[1]), pq.read_metadata(f).num_rows, f)
        for f in sorted(d.glob("part-*.parquet"))
    ]


def _read_parquet(f: Path):
    import pyarrow.parquet as pq

    return pq.read_table(f)


def _write_parquet_part(path: Path, table):
    import pyarrow.parquet as pq

    tmp = path.with_name(path.name + ".tmp")
    try:
        pq.write_table(table, tmp)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    tmp.replace(path)


def _open_nc(f: Path):
    import h5py
    import xarray as xr

    # every object opened once by h5py first: a damaged file fails here, cleanly (an
    # h5netcdf File whose opening fails half-way raises again when it is collected,
    # under "Exception ignored in", after the one-line error)
    with h5py.File(f, "r") as h:
        h.visititems(lambda name, obj: None)
    return xr.open_dataset(f, engine="h5netcdf")


def _zarr_t_arrays(g):
    for name, a in g.arrays():
        dims = getattr(a.metadata, "dimension_names", None) or a.attrs.get("_ARRAY_DIMENSIONS", ())
        if dims and dims[0] == "t":
            yield name, a


def _zarr_committed(g) -> int:
    """Complete records of a Zarr group: its committed length (stores written before
    bkwaves committed lengths: the shortest time axis)."""
    lengths = [a.shape[0] for _, a in _zarr_t_arrays(g)]
    shortest = min(lengths) if lengths else 0
    committed = g.attrs.get(RECORDS_ATTR)
    return shortest if committed is None else min(int(committed), shortest)


def _merged_nc(blocks_dir: Path):
    import xarray as xr

    files = [f for _, _, f in _blocks(blocks_dir)]
    if not files:
        return None
    dss = [_open_nc(f) for f in files]
    ds = xr.concat(dss, dim="t", combine_attrs="override").load()
    for d in dss:
        d.close()
    return ds


def _copy_nc(src: Path, k: int | None = None) -> bytes:
    """The NetCDF file ``src`` (its first ``k`` records) copied by h5netcdf, in memory
    (its bytes: HDF5 never writes to a disk that may be full)."""
    import io

    import h5netcdf

    target = io.BytesIO()
    with h5netcdf.File(src, "r") as s, h5netcdf.File(target, "w") as f:
        f.attrs.update(dict(s.attrs))
        nt = s.dimensions["t"].size
        k = nt if k is None else min(k, nt)
        space = {d: s.dimensions[d].size for d in s.dimensions if d != "t"}
        f.dimensions = {"t": k, **space}
        for name, var in s.variables.items():
            in_t = var.dimensions[:1] == ("t",)
            v = f.create_variable(name, var.dimensions, var.dtype)
            v[...] = var[:k] if in_t else var[...]
            v.attrs.update(dict(var.attrs))
    return target.getvalue()


def _merge_nc(blocks_dir: Path, main: Path, check) -> None:
    """The NetCDF blocks of an unfinished run merged into one file ``main`` (memory: the
    file up to 32 MiB, else one block), sized first and written where a failure of HDF5
    cannot end this process (``bkwaves._nc_publish``); ``check()`` is asked before
    and while it is written."""
    from . import _nc_publish

    blocks = _blocks(blocks_dir)
    if not blocks:
        return
    _nc_publish.merge(blocks, main, check)
    check()


def _merged_table(d: Path):
    import pyarrow as pa

    parts = _table_parts(d)
    if not parts:
        return None
    tables = [_read_parquet(f) for _, _, f in parts]
    meta = tables[0].schema.metadata
    return pa.concat_tables(tables).replace_schema_metadata(meta)


def _publish(out: Path, partial: Path, replaces, remove=(), stop=None):
    """Build the final files in ``partial/final`` and rename them onto ``out``. ``stop``
    (a function) is asked between pieces of the merge: when it returns true, ``final``
    is removed and :class:`PublishStopped` raised, before anything is renamed."""
    final = partial / "final"
    if final.exists():
        shutil.rmtree(final)
    final.mkdir()

    def check():
        if stop is not None and stop():
            raise PublishStopped

    try:
        _build_final(out, partial, final, check)
    except PublishStopped:
        shutil.rmtree(final, ignore_errors=True)
        raise
    _install(out, partial, final, replaces, remove)


def _build_final(out: Path, partial: Path, final: Path, check) -> None:
    """The merged tables and the main output, in ``final`` (memory: one part or one
    block at a time)."""
    import pyarrow.parquet as pq

    marker = _read_marker(partial) or {}
    run_id = marker.get("run_id", "")
    produced = []
    for d in sorted((partial / "tables").iterdir()):
        check()
        parts = _table_parts(d)
        if not parts:
            continue
        target = final / table_path(out, d.name).name
        meta = _parquet_meta(parts[0][2])
        meta[b"bkwaves_run_id"] = run_id.encode()
        if meta.get(b"bkwaves_csv", b"1") == b"1":
            csv = target.with_suffix(".csv")
            for k, (_, _, f) in enumerate(parts):
                check()
                _read_parquet(f).to_pandas().to_csv(
                    csv, index=False, mode="w" if k == 0 else "a", header=k == 0
                )
            meta[b"bkwaves_csv_sha256"] = _sha256(csv).encode()
            produced.append(csv)
        schema = pq.read_schema(parts[0][2]).with_metadata(meta)
        with pq.ParquetWriter(target, schema) as w:
            for _, _, f in parts:  # one row group per part: appended, never rewritten
                check()
                w.write_table(_read_parquet(f).replace_schema_metadata(meta))
        produced.append(target)
    main = final / out.name
    if out.suffix == ".nc":
        blocks_dir = partial / "snapshots"
        _merge_nc(blocks_dir, main, check)
    else:
        import zarr

        check()
        store = partial / out.name
        with warnings.catch_warnings():  # "consolidated metadata is not in the v3 spec"
            warnings.simplefilter("ignore")
            zarr.consolidate_metadata(str(store))
        store.replace(main)
    (final / "produced.json").write_text(json.dumps([p.name for p in produced]))


def _install(out: Path, partial: Path, final: Path, replaces, remove=()):
    """Rename the files built in ``final`` onto ``out`` and its tables."""
    produced = [final / n for n in json.loads((final / "produced.json").read_text())]
    main = final / out.name
    if main.exists() and out.is_dir() and not _is_ours(out, out):
        # changed since the run began: not replaced
        raise ParameterError(
            f"not replacing {out}: it now holds files bkwaves did not write; the new "
            f"output is in {final}"
        )
    # install: tables first, the main output last; then drop what the old output had
    # and the new one has not
    old = partial / "replaced"
    old.mkdir(exist_ok=True)
    names = {p.name for p in produced} | {out.name}
    for p in replaces:
        if p.name not in names and p.exists() and _is_ours(p, out):
            p.replace(old / p.name)
    for p in produced:
        p.replace(out.with_name(p.name))
    if main.exists():
        if out.is_dir():
            out.replace(old / out.name)
        main.replace(out)
    for p in remove:
        Path(p).unlink(missing_ok=True)
    shutil.rmtree(partial)


def finalize(path) -> Path:
    """Publish the records an unfinished run left in ``OUT.partial/`` as ``OUT`` (after a
    crash, an interruption or a full disk), replacing an earlier output: the run can then
    no longer be resumed (its checkpoint is removed).

    Parameters
    ----------
    path : str or pathlib.Path
        The output ``OUT``.

    Returns
    -------
    pathlib.Path
        ``OUT`` (unchanged when there is nothing to publish).

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
    >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
    >>> w.append(0.0, u=[0.1, 0.2, 0.3])
    >>> w.close(publish=False)                     # as a run cut short leaves it
    False
    >>> ds, _ = bk.io.load(bk.io.finalize(out))
    >>> ds.u.values.tolist()
    [[0.1, 0.2, 0.3]]
    """
    from .runner import checkpoint_path

    p = _check_path(path)
    partial = partial_path(p)
    marker = _read_marker(partial)
    if marker is None:
        return p
    lock = _Lock(_lock_path(p), p)
    try:
        replaces = [p.with_name(n) for n in marker.get("replaces", [])]
        _publish(p, partial, replaces, remove=[checkpoint_path(p)])
    finally:
        lock.release()
    return p


# --- reading -----------------------------------------------------------------------------


def load(path):
    """Open a run output (what ``bkwaves run`` or ``bk.run(cfg, out)`` wrote).

    Without a published output the records of an unfinished run (``OUT.partial/``) are
    read, up to the last committed one, with a warning. Other tables:
    :func:`~bkwaves.io.load_tables`.

    Parameters
    ----------
    path : str or pathlib.Path
        The output, ``OUT.nc`` or ``OUT.zarr``.

    Returns
    -------
    dataset : xarray.Dataset
        The snapshots, with the config, version, seed and units in its attributes.
    catalog : pandas.DataFrame or None
        The event catalog (None if the run wrote none; the ruptures of a
        ``free_boundary_2d`` run, whose events are its ruptures), its column units in
        ``catalog.attrs["units"]``.

    Examples
    --------
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> cfg = {"model": "free_boundary", "params": {"gamma": 0.3, "v": 0.01, "dx": 0.001},
    ...        "domain": {"length": 90.0, "grid": 451},
    ...        "initial": {"kind": "bumps", "base": 0.499,
    ...                    "bumps": [{"center": 45.0, "width": 50.0, "height": 0.5}]},
    ...        "run": {"max_events": 2}}
    >>> out = os.path.join(tempfile.mkdtemp(), "source.nc")
    >>> _ = bk.run(cfg, out)
    >>> ds, catalog = bk.load(out)
    >>> ds["u"].dims, len(catalog)
    (('t', 'x'), 2)
    """
    ds, tables = load_tables(path)
    # (a planar free boundary run's events are its ruptures: it writes those only)
    return ds, tables.get("events", tables.get("ruptures"))


def load_tables(path):
    """Like :func:`load`, with every table: returns ``(dataset, {name: DataFrame})``.
    A table written by another run than the snapshots (another run id) is left out,
    with a warning.

    Parameters
    ----------
    path : str or pathlib.Path
        The output, ``OUT.nc`` or ``OUT.zarr``.

    Returns
    -------
    dataset : xarray.Dataset
        The snapshots (units in the attributes).
    tables : dict
        Table name -> pandas.DataFrame (column units in ``attrs["units"]``).

    Examples
    --------
    >>> import pandas as pd
    >>> import os, tempfile
    >>> import bkwaves as bk
    >>> out = os.path.join(tempfile.mkdtemp(), "run.nc")
    >>> w = bk.io.RunWriter(out, [0.0, 0.5, 1.0], {"u": ("1", "stress", "f8")})
    >>> with w:
    ...     w.append(0.0, u=[0.1, 0.2, 0.3])
    ...     w.append_rows("events", pd.DataFrame({"t_start": [0.5]}), units={"t_start": "1"})
    >>> ds, tables = bk.io.load_tables(out)
    >>> ds.u.shape, list(tables), tables["events"].attrs["units"]
    ((1, 3), ['events'], {'t_start': '1'})
    """
    p = _check_path(path)
    partial = partial_path(p)
    marker = _read_marker(partial)
    if p.exists():
        if marker is not None:
            warnings.warn(
                f"{partial} holds an unfinished newer run (not read): continue it with "
                f"`bkwaves run --resume {p}`",
                stacklevel=2,
            )
        ds = _readable(p, lambda: _open_zarr(p, p) if p.suffix == ".zarr" else _open_nc(p))
        raw = {}
        for f in sorted(p.parent.glob(f"{p.name}.*.parquet")):
            raw[f.name[len(p.name) + 1 : -len(".parquet")]] = _read_parquet(f)
    elif marker is not None:
        store = partial / p.name
        if p.suffix == ".zarr" and not (store / "zarr.json").is_file():
            raise ParameterError(
                f"{p} has no records: its run stopped before its store {store} was "
                "written (run it again with --overwrite)"
            )
        if p.suffix == ".zarr":
            ds = _readable(store, lambda: _open_zarr(store, p))
        else:
            ds = _readable(partial, lambda: _merged_nc(partial / "snapshots"))
            if ds is None:
                raise ParameterError(f"no completed records in {partial}")
        raw = {}
        for d in sorted((partial / "tables").iterdir()):
            t = _merged_table(d)
            if t is not None:
                raw[d.name] = t
        warnings.warn(
            f"{p} is unfinished: read {ds.sizes['t']} committed records from {partial} "
            f"(continue the run with `bkwaves run --resume {p}` if it left a checkpoint, "
            "or publish it as it is with bkwaves.io.finalize)",
            stacklevel=2,
        )
    else:
        raise ParameterError(f"output not found: {p}")
    run_id = ds.attrs.get(RUN_ID_ATTR)
    tables = {}
    for name, t in raw.items():
        meta = t.schema.metadata or {}
        tid = meta.get(b"bkwaves_run_id", b"").decode() or None
        if run_id is not None and tid != run_id:
            warnings.warn(
                f"table {name!r} of {p} belongs to another run ({tid or 'no run id'}, the "
                f"snapshots are run {run_id}): left out",
                stacklevel=2,
            )
            continue
        df = t.to_pandas()
        df.attrs["units"] = json.loads(meta.get(b"bkwaves_units", b"{}"))
        df.attrs["scales"] = json.loads(meta.get(b"bkwaves_scales", b"{}"))
        df.attrs["descriptions"] = json.loads(meta.get(b"bkwaves_descriptions", b"{}"))
        tables[name] = df
    return ds, tables


def _readable(path: Path, read):
    """``read()``, with a damaged or unreadable file reported in one line."""
    try:
        return read()
    except ParameterError:
        raise
    except Exception as e:  # noqa: BLE001 - h5py, zarr, codecs, JSON: all one message
        what = "NetCDF (HDF5)" if path.suffix == ".nc" else "bkwaves"
        text = " ".join(str(e).split())[:200] or type(e).__name__
        raise ParameterError(
            f"cannot read {path}: not a readable {what} output ({type(e).__name__}: {text})"
        ) from None


def _open_zarr(store: Path, out: Path):
    """A Zarr store read up to its last committed record (a warning says what a torn
    store had beyond it)."""
    import xarray as xr
    import zarr

    g = zarr.open_group(str(store), mode="r")
    n = _zarr_committed(g)
    lengths = {name: a.shape[0] for name, a in _zarr_t_arrays(g)}
    consolidated = "consolidated_metadata" in json.loads((store / "zarr.json").read_text())
    if lengths and max(lengths.values()) > n:
        warnings.warn(
            f"{out}: dropped the uncommitted records beyond record {n} "
            f"({', '.join(f'{k}: {v}' for k, v in sorted(lengths.items()))} rows written)",
            stacklevel=3,
        )
    if all(v == n for v in lengths.values()):
        ds = xr.open_zarr(store, consolidated=consolidated)
        return ds
    # a torn store: arrays of different lengths, built here from the committed rows
    data, coords = {}, {}
    for name, a in g.arrays():
        dims = tuple(
            getattr(a.metadata, "dimension_names", None) or a.attrs.get("_ARRAY_DIMENSIONS", ())
        )
        values = a[:n] if dims and dims[0] == "t" else a[:]
        attrs = {k: v for k, v in a.attrs.items() if k != "_ARRAY_DIMENSIONS"}
        (coords if name in ("t", "x", "y") else data)[name] = (dims, values, attrs)
    return xr.Dataset(data, coords=coords, attrs=dict(g.attrs))
