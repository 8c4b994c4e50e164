"""The NetCDF blocks of a complete run merged into one file, without letting HDF5 meet a
full disk in the run's own process.

HDF5 does not survive a failed write: on ENOSPC (or EFBIG past ``ulimit -f``) h5py prints
"Can't decrement id ref count (file write failed ...)" and the process later dies by
SIGSEGV (seen in ``Group.__delitem__`` inside h5netcdf's ``create_variable``, and when
the half-written file is collected). So the merged file is

- sized first (:func:`merged_bytes`, an upper bound of the file HDF5 writes: whole
  chunks, their index, the metadata) and refused when the folder has less free space;
- built in memory and written by Python (a temporary name, renamed) when it is at most
  ``IN_MEMORY_BYTES``: a full disk is then an ``OSError`` like any other;
- otherwise written by a child process (``python -m bkwaves._nc_publish BLOCKS OUT``)
  whose death, by a signal or an error, is reported here as an ``OSError`` (ENOSPC when
  the disk has filled meanwhile). The parent asks ``check()`` while it waits, and kills
  the child when it says stop; the child dies with its parent (Linux
  ``PR_SET_PDEATHSIG``).

Either way only ``OUT.partial/final/`` is written: the blocks, the tables and the
checkpoint of the run stay as they were.
"""

from __future__ import annotations

import errno
import io as _pyio
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

#: Merged files up to this size are built in memory and written by Python
IN_MEMORY_BYTES = 32 << 20
#: What HDF5 adds to the data, bounded: a fixed part, and per chunk (its B-tree entry)
FIXED_OVERHEAD = 64 << 10
PER_CHUNK_OVERHEAD = 4 << 10
#: Seconds between two questions to ``check()`` while the child writes
POLL_S = 0.05


def _even(n: int, most: int) -> int:
    """The length of the pieces when ``n`` is cut into the fewest equal pieces of at most
    ``most``: no piece padded much (a chunk is stored whole, the last one too)."""
    most = max(1, min(n, most))
    return math.ceil(n / math.ceil(n / most))


def chunks(dims: tuple, sizes: dict, itemsize: int, total: int) -> tuple | None:
    """HDF5 chunk shape of a merged variable with dimensions ``dims`` (``sizes``: their
    lengths, ``t`` of length ``total``): at most NC_CHUNK_BYTES (and 4096 records) each,
    the dimensions cut into equal pieces, never longer in t than the run (a chunk is
    stored whole: 4 MiB chunks for 61 records of 200 blocks made a 9 MB file of 0.2 MB
    of data). None: not a variable along t."""
    from .io import NC_CHUNK_BYTES

    if dims[:1] != ("t",):
        return None
    total = max(1, int(total))
    cap = NC_CHUNK_BYTES
    if len(dims) == 1:
        return (_even(total, min(4096, cap // itemsize)),)
    if len(dims) == 2:  # (t, x)
        cx = _even(sizes[dims[1]], cap // itemsize)
        return (_even(total, min(4096, cap // (cx * itemsize))), cx)
    ny, nx = (sizes[d] for d in dims[1:])  # (t, y, x): whole records where they fit
    record = ny * nx * itemsize
    if record <= cap:
        return (_even(total, min(4096, cap // record)), ny, nx)
    cx = _even(nx, cap // itemsize)  # else rows of x (pieces of a row)
    return (1, _even(ny, cap // (cx * itemsize)), cx)


def _layout(blocks) -> tuple[dict, list, int, int]:
    """(sizes of the dimensions, [(name, dims, dtype, chunks)], total records, bytes of
    the first block's file beyond its data) of the blocks ``[(first, records, file)]``."""
    import h5netcdf

    total = sum(k for _, k, _ in blocks)
    with h5netcdf.File(blocks[0][2], "r") as s:
        sizes = {d: s.dimensions[d].size for d in s.dimensions if d != "t"}
        sizes["t"] = total
        variables = []
        data = 0
        for name, v in s.variables.items():
            dims = tuple(v.dimensions)
            variables.append((name, dims, v.dtype, chunks(dims, sizes, v.dtype.itemsize, total)))
            data += math.prod(v.shape) * v.dtype.itemsize
    head = max(0, blocks[0][2].stat().st_size - data)  # its metadata and attributes
    return sizes, variables, total, head


def merged_bytes(blocks) -> int:
    """An upper bound of the bytes of the merged file (HDF5 stores every chunk whole).

    Parameters
    ----------
    blocks : list of (int, int, pathlib.Path)
        The blocks (first record, records, file), as ``bkwaves.io._blocks`` lists them.

    Returns
    -------
    int
        Bytes: the chunks, a B-tree entry per chunk, the metadata of the first block's
        file (its attributes, counted once more) and FIXED_OVERHEAD.
    """
    sizes, variables, _, head = _layout(blocks)
    n = FIXED_OVERHEAD + head
    for _, dims, dtype, ch in variables:
        if ch is None:
            n += math.prod(sizes[d] for d in dims) * dtype.itemsize
            continue
        count = math.prod(math.ceil(sizes[d] / c) for d, c in zip(dims, ch, strict=True))
        n += count * (math.prod(ch) * dtype.itemsize + PER_CHUNK_OVERHEAD)
    return n


def merge_to(blocks, target) -> None:
    """Write the merged file of ``blocks`` to ``target`` (a path or a binary file
    object): t unlimited, its length the total; the variables along t chunked
    (:func:`chunks`), filled block by block (memory: one block)."""
    import h5netcdf

    sizes, variables, total, _ = _layout(blocks)
    with h5netcdf.File(target, "w") as f:
        with h5netcdf.File(blocks[0][2], "r") as s:
            f.attrs.update(dict(s.attrs))
            f.dimensions = {"t": None, **{d: n for d, n in sizes.items() if d != "t"}}
            f.resize_dimension("t", total)
            for name, dims, dtype, ch in variables:
                kw = {} if ch is None else {"chunks": ch}
                v = f.create_variable(name, dims, dtype, **kw)
                if ch is None:
                    v[...] = s.variables[name][...]
                v.attrs.update(dict(s.variables[name].attrs))
        n = 0
        for _, k, path in blocks:
            with h5netcdf.File(path, "r") as b:
                for name, _, _, ch in variables:
                    if ch is not None:
                        f.variables[name][n : n + k, ...] = b.variables[name][...]
            n += k


def _free(folder: Path) -> int:
    return shutil.disk_usage(folder).free


def merge(blocks, main: Path, check) -> None:
    """The merged file of ``blocks`` at ``main``, written where a failure of HDF5 cannot
    end this process (see the module's docstring); ``check()`` is asked before and
    while it is written (it raises to stop). A full disk, found before or while
    writing, is an ``OSError`` (ENOSPC) naming ``main`` with the bytes needed and free.
    """
    from .io import _write_bytes, human_bytes

    check()
    need = merged_bytes(blocks)
    free = _free(main.parent)
    if free < need:
        err = OSError(
            errno.ENOSPC,
            f"No space left on device: {main.name} needs up to {human_bytes(need)}, "
            f"{human_bytes(free)} free",
            str(main),
        )
        err.need, err.free = need, free
        raise err
    if need <= IN_MEMORY_BYTES:
        bio = _pyio.BytesIO()
        merge_to(blocks, bio)
        check()
        try:
            _write_bytes(main, bio.getbuffer())
        except OSError as e:
            e.need, e.free = need, _free(main.parent)
            raise
        return
    _merge_in_child(blocks[0][2].parent, main, check, need)


def _merge_in_child(blocks_dir: Path, main: Path, check, need: int) -> None:
    cmd = [sys.executable, "-m", "bkwaves._nc_publish", str(blocks_dir), str(main)]
    proc = subprocess.Popen(
        cmd,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,  # a Ctrl-C in the terminal is the parent's to answer
    )
    err = b""
    try:
        while True:
            check()
            try:
                _, more = proc.communicate(timeout=POLL_S)
                err += more or b""
                break
            except subprocess.TimeoutExpired:
                continue
    except BaseException:
        proc.kill()
        proc.wait()
        raise
    if proc.returncode == 0:
        return
    raise _child_error(proc.returncode, err.decode(errors="replace"), main, need)


def _child_error(rc: int, stderr: str, main: Path, need: int) -> OSError:
    """The OSError of a child that failed: the errno it reported (its last line), else
    the one in HDF5's message, else ENOSPC when the folder has less room than the file
    needs, else EIO; the reason in one line."""
    from .io import human_bytes

    report = {}
    for line in reversed(stderr.strip().splitlines()):
        if line.startswith("{"):
            try:
                report = json.loads(line)
            except ValueError:
                report = {}
            break
    code = report.get("errno")
    if code is None:
        found = re.findall(r"errno = (\d+)", stderr)
        code = int(found[-1]) if found else None
    free = _free(main.parent)
    if code is None and free < need:
        code = errno.ENOSPC
    how = f"died by {signal.Signals(-rc).name}" if rc < 0 else f"failed (exit {rc})"
    if code is not None:
        reason = os.strerror(code)
    else:
        code = errno.EIO
        reason = report.get("message") or "the NetCDF writer " + how
    err = OSError(
        code,
        f"{reason}: writing {main.name} (the NetCDF writer {how}; it needs up to "
        f"{human_bytes(need)}, {human_bytes(free)} free)",
        str(main),
    )
    err.need, err.free = need, free
    return err


def _die_with_parent() -> None:
    if sys.platform.startswith("linux"):
        import ctypes

        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, int(signal.SIGKILL), 0, 0, 0)  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # pragma: no cover - no prctl here
            pass


def main(argv=None) -> int:
    """The child: merge the blocks of ``argv[0]`` into ``argv[1]``; on an error, its
    errno and message as one JSON line on stderr, exit status 3."""
    _die_with_parent()
    blocks_dir, out = (Path(a) for a in (argv if argv is not None else sys.argv[1:]))
    from .io import _blocks

    try:
        merge_to(_blocks(blocks_dir), out)
    except Exception as e:  # noqa: BLE001 - every failure goes back to the parent
        code = getattr(e, "errno", None)
        if code is None:
            found = re.findall(r"errno = (\d+)", str(e))
            code = int(found[-1]) if found else None
        text = " ".join(str(e).split())[:300]
        sys.stderr.write(json.dumps({"errno": code, "message": text}) + "\n")
        sys.stderr.flush()
        os._exit(3)  # not through HDF5's clean-up of a file it failed to write
    return 0


if __name__ == "__main__":
    sys.exit(main())
