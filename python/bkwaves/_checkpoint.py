"""Checkpoint files: data only, never pickles.

A checkpoint is a NumPy ``.npz`` archive (a zip of ``.npy`` arrays) read with
``allow_pickle=False``, so loading one can never run code. The array ``header`` holds UTF-8
JSON: ``{"format": "bkwaves-checkpoint", "version": 1, "kind": ..., "bkwaves": ...,
"meta": {...}}``; the other arrays are plain numbers, among them ``engine``: the Rust
engine's own checkpoint bytes (which carry their own magic and configuration checks).
A file of another format, of another version, or of another kind is refused with a
:class:`bkwaves.ParameterError` naming the file and what was expected. Writing replaces
only a bkwaves checkpoint: anything else at the path (a user's file, a folder) is refused
with a ParameterError and left as it was.
"""

from __future__ import annotations

import dataclasses
import json
import zipfile
from pathlib import Path

import numpy as np

from ._core import ParameterError

FORMAT = "bkwaves-checkpoint"
VERSION = 1
"""The checkpoint layout this bkwaves writes and reads; bumped when the layout changes."""

_PICKLE_START = (b"\x80", b"(", b"]", b"}")  # protocols 2-5, and protocol 0/1 containers


def write(path, kind: str, meta: dict, arrays: dict[str, np.ndarray]) -> Path:
    """Write a checkpoint of ``kind`` atomically (a temporary file renamed into place)."""
    from . import __version__

    path = Path(path)
    _check_replaceable(path)
    header = {"format": FORMAT, "version": VERSION, "kind": kind, "bkwaves": __version__}
    header["meta"] = meta
    text = json.dumps(header, allow_nan=True, default=_json_scalar)
    payload = {"header": np.frombuffer(text.encode("utf-8"), dtype=np.uint8)}
    for name, a in arrays.items():
        a = np.asarray(a)
        if a.dtype.hasobject:
            raise TypeError(f"checkpoint array {name!r} is not plain data ({a.dtype})")
        payload[name] = a
    tmp = path.with_name(path.name + ".tmp")
    try:
        f = open(tmp, "wb")
    except OSError as e:  # (a missing folder, a read-only one): named by the user's path
        raise type(e)(e.errno, e.strerror, str(path)) from None
    try:
        with f:
            np.savez(f, **payload)
        tmp.replace(path)
    except BaseException:  # (a full disk, a signal): the earlier checkpoint stays
        tmp.unlink(missing_ok=True)
        raise
    return path


def _check_replaceable(path: Path) -> None:
    """Refuse to write over anything at ``path`` but a bkwaves checkpoint (of any kind or
    version): a user's file of the same name is never replaced."""
    if not (path.exists() or path.is_symlink()):
        return
    header = None
    if path.is_file():
        try:
            with np.load(path, allow_pickle=False) as z:
                header = json.loads(z["header"].tobytes().decode("utf-8"))
        except (ValueError, KeyError, OSError, EOFError, zipfile.BadZipFile, UnicodeDecodeError):
            header = None
    if not (isinstance(header, dict) and header.get("format") == FORMAT):
        raise ParameterError(
            f"not replacing {path}: it is not a bkwaves checkpoint; move it away or choose "
            "another path"
        )


def read(path, kind: str, writer: str) -> tuple[dict, dict[str, np.ndarray]]:
    """``(meta, arrays)`` of the checkpoint of ``kind`` at ``path``; ``writer`` names
    what writes such files (for the error messages)."""
    path = Path(path)
    what = f"a bkwaves {kind} checkpoint (written by {writer})"
    try:
        with open(path, "rb") as f:
            start = f.read(4)
    except OSError as e:
        raise ParameterError(f"cannot read checkpoint {path}: {e.strerror or e}") from None
    if start[:1] in _PICKLE_START:
        raise ParameterError(
            f"{path} is a Python pickle, not {what}: bkwaves never loads pickles (loading "
            "one can run arbitrary code). Earlier bkwaves versions wrote pickled "
            "checkpoints: run again with this version to write a new one."
        )
    if start != b"PK\x03\x04":
        raise ParameterError(f"{path} is not {what}")
    try:
        with np.load(path, allow_pickle=False) as z:
            arrays = {name: z[name] for name in z.files}
        header = json.loads(arrays.pop("header").tobytes().decode("utf-8"))
    except (ValueError, KeyError, OSError, EOFError, zipfile.BadZipFile, UnicodeDecodeError):
        raise ParameterError(f"{path} is not {what} (damaged or of another format)") from None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise ParameterError(f"{path} is not {what}")
    if header.get("version") != VERSION:
        raise ParameterError(
            f"{path} is a checkpoint of format version {header.get('version')!r} (written by "
            f"bkwaves {header.get('bkwaves', '?')}); this bkwaves reads version {VERSION} only"
        )
    if header.get("kind") != kind:
        raise ParameterError(f"{path} is a {header.get('kind')} checkpoint, not {what}")
    return header["meta"], arrays


def rebuild(build, meta: dict, arrays: dict, path, kind: str):
    """``build(meta, arrays, path)``, a model rebuilt from a checkpoint's record: a header
    whose record is not one bkwaves wrote (a key missing, a value of another type) is
    refused in one line naming the file, not with the KeyError or TypeError it causes."""
    try:
        return build(meta, arrays, path)
    except ParameterError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError, IndexError) as e:
        what = f"{type(e).__name__}: {e}"
        raise ParameterError(
            f"{path} is a damaged {kind} checkpoint (its record does not rebuild one: {what})"
        ) from None


def restore_engine(engine, arrays: dict, path) -> None:
    """Restore a Rust engine from the checkpoint's ``engine`` bytes, naming ``path`` on
    refusal (another configuration, or bytes of another engine version)."""
    try:
        engine.restore(np.ascontiguousarray(arrays["engine"], dtype=np.uint8).tobytes())
    except (ParameterError, ValueError, KeyError) as e:
        raise ParameterError(f"cannot restore the engine from {path}: {e}") from None


def params_record(params) -> dict:
    """A :class:`bkwaves.Params` as JSON-able data (floats round-trip exactly)."""
    d = {f.name: getattr(params, f.name) for f in dataclasses.fields(params)}
    if d.get("units") is not None:
        d["units"] = {f.name: getattr(d["units"], f.name) for f in dataclasses.fields(d["units"])}
    if d.get("friction_law") is not None:
        law = d["friction_law"]
        d["friction_law"] = {"name": law.name, "params": dict(law.params)}
    return d


def params_from_record(d: dict):
    from .params import Params, PhysicalUnits

    d = dict(d)
    if d.get("units") is not None:
        d["units"] = PhysicalUnits(**d["units"])
    if d.get("friction_law") is not None:
        from .friction import law

        d["friction_law"] = law(d["friction_law"]["name"], **d["friction_law"]["params"])
    return Params(**d)


def _json_scalar(x):
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"{type(x).__name__} {x!r} cannot be written to a checkpoint")
