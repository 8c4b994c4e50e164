"""Files a command writes: checked before any work, written whole, and never a user's.

- :func:`check_writable` refuses, before any computation, an output that cannot be
  created (a read-only file system, a missing permission, a parent that is a file, a
  path under /proc): a :class:`bkwaves.ParameterError` naming the option and the path,
  which the command line prints as one ``Error:`` line (exit status 2).
- :func:`write_atomic` writes a file under a temporary name beside it and renames it
  into place, so a reader, or a failure half-way, never leaves a truncated file.
- :class:`OwnedFiles` is the policy of ``bkwaves run`` for a set of plain files in a
  folder (``bkwaves paper``): existing outputs are refused unless ``overwrite``, and even
  then only files bkwaves wrote and nobody changed since (their SHA-256 is recorded in a
  manifest in the folder) are replaced; every other file in the folder is left alone.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import json
import os
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path

from . import __version__
from ._core import ParameterError


def _reason(e: OSError) -> str:
    return e.strerror or type(e).__name__


def _named(name: str, path: Path) -> str:
    """``-o DIR`` for a command-line option, ``outdir = 'DIR'`` for an argument."""
    return f"{name} {path}" if name.startswith("-") else f"{name} = {str(path)!r}"


def check_writable(path, name: str, *, directory: bool = False) -> Path:
    """``path`` as a Path if bkwaves can write it: the file ``path`` (or, with
    ``directory``, files inside the folder ``path``), creating missing parent folders.
    Nothing is created: the nearest existing folder is probed with a temporary file that
    is removed at once. Else a ParameterError naming ``name`` and the path."""
    path = Path(path)
    where = path if directory else path.parent
    if not directory and path.is_dir():
        raise ParameterError(f"{_named(name, path)}: is a folder; give a file name")
    if directory and path.exists() and not path.is_dir():
        raise ParameterError(f"{_named(name, path)}: is a file; give a folder")
    probe = Path(os.path.abspath(where))
    while not probe.exists():
        if probe.is_symlink():  # a dangling link: mkdir would fail on it
            raise ParameterError(f"{_named(name, path)}: {probe} is a broken symbolic link")
        probe = probe.parent
    if not probe.is_dir():
        raise ParameterError(f"{_named(name, path)}: cannot write there ({probe} is a file)")
    try:
        fd, tmp = tempfile.mkstemp(prefix=".bkwaves-probe-", dir=probe)
    except OSError as e:
        raise ParameterError(
            f"{_named(name, path)}: cannot write there ({_reason(e)}: {probe})"
        ) from None
    os.close(fd)
    os.unlink(tmp)
    return path


def write_atomic(path, write: Callable[[Path], object]) -> Path:
    """Call ``write(tmp)`` to write a temporary file beside ``path`` (same suffix, so a
    writer that picks its format from the name picks the right one), then rename it onto
    ``path``: ``path`` is either the old file or the complete new one."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(
        prefix=f".{path.stem}.", suffix=f".tmp{path.suffix}", dir=path.parent
    )
    os.close(fd)
    tmp = Path(tmp)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    return path


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


class OwnedFiles:
    """The files a command writes into ``folder`` (names relative to it), with a manifest
    ``folder/manifest`` recording the SHA-256 of each file as written.

    :meth:`claim` (before any work) refuses when a file to be written exists, unless
    ``overwrite``; with ``overwrite`` it still refuses any such file that is not in the
    manifest or whose content changed since bkwaves wrote it (a user's file, or one the
    user edited). :meth:`write` writes one file atomically and records it."""

    FORMAT = "bkwaves-files-1"

    def __init__(self, folder, manifest: str, *, command: str, name: str = "outdir"):
        self.folder = Path(folder)
        self.manifest = self.folder / manifest
        self.command = command
        self.name = name
        self.files: dict[str, str] = {}

    def _read_manifest(self) -> dict[str, str] | None:
        """The recorded files, or None when the manifest is missing or not bkwaves'."""
        try:
            doc = json.loads(self.manifest.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if not isinstance(doc, dict) or doc.get("format") != self.FORMAT:
            return None
        files = doc.get("files")
        if not isinstance(files, dict):
            return None
        return {str(k): str(v) for k, v in files.items()}

    def claim(self, names: Iterable[str], overwrite: bool) -> None:
        check_writable(self.folder, self.name, directory=True)
        names = list(names)
        present = [n for n in [*names, self.manifest.name] if (self.folder / n).exists()]
        if not present:
            return
        shown = ", ".join(present[:4]) + (
            f" and {len(present) - 4} more" if len(present) > 4 else ""
        )
        if not overwrite:
            raise ParameterError(
                f"output {self.folder} holds {shown}: pass --overwrite (overwrite=True) to "
                f"replace what an earlier `{self.command}` wrote, or choose another folder"
            )
        recorded = self._read_manifest()
        if recorded is None and self.manifest.exists():
            foreign = [self.manifest.name]
        else:
            recorded = recorded or {}
            foreign = [
                n
                for n in present
                if n != self.manifest.name
                and (
                    n not in recorded
                    or not (self.folder / n).is_file()
                    or _sha256(self.folder / n) != recorded[n]
                )
            ]
        if foreign:
            raise ParameterError(
                f"not replacing {', '.join(str(self.folder / n) for n in foreign)}: not written "
                f"by bkwaves, or changed since (no matching record in {self.manifest.name}); "
                "move it away or choose another folder"
            )
        self.files = {n: h for n, h in (recorded or {}).items() if n not in names}

    def write(self, name: str, write: Callable[[Path], object]) -> Path:
        """Write ``folder/name`` with ``write(tmp)`` atomically and record it."""
        path = write_atomic(self.folder / name, write)
        self.files[name] = _sha256(path)
        doc = {"format": self.FORMAT, "bkwaves_version": __version__, "files": self.files}
        write_atomic(
            self.manifest, lambda p: p.write_text(json.dumps(doc, indent=1), encoding="utf-8")
        )
        return path


def os_error_line(e: OSError) -> str:
    """One line for an OSError the command line did not foresee: what, and which file."""
    what = e.strerror or str(e) or type(e).__name__
    files = [f for f in (e.filename, e.filename2) if f is not None]
    if files:
        return f"{what}: {' -> '.join(os.fsdecode(f) for f in files)}"
    if e.errno == errno.ENOSPC:
        return "no space left on the output's device"
    return what
