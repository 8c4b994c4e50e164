"""Settings for the whole test session."""

import signal

import pytest


@pytest.fixture(autouse=True, scope="session")
def _sigint_as_from_a_terminal():
    """The tests send SIGINT to child processes as a terminal's Ctrl-C would. A test run
    started as a background job of a non-interactive shell (``bash .ci/run &``) inherits
    SIGINT ignored, every child would inherit that too, and bkwaves rightly leaves an
    ignored SIGINT ignored (python/bkwaves/_signals.py), so those tests would measure the
    launcher, not bkwaves. Python's own handler here makes children start with SIGINT at
    its default, as from a terminal."""
    old = signal.getsignal(signal.SIGINT)
    if old == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    if old == signal.SIG_IGN:
        signal.signal(signal.SIGINT, old)


def _stale_extension(root=None, pkg=None):
    """The newest Rust source (crates/, test modules aside) changed after the compiled
    extension of an editable install (python/bkwaves/_core*), or None. A test run against
    an extension built from older sources checks an engine that is not the code in the
    tree: a kicked lattice front measured against the chain with an extension built
    before the event location's fix (docs/lattice.md, "Ties") reported a 3.5e-14
    difference that the sources no longer had. A fresh install (.ci/run) is never
    stale. ``root`` (the repository) and ``pkg`` (the directory bkwaves is imported from)
    default to this tree and the package the import system finds
    (tests/test_stale_extension.py passes others)."""
    import importlib.machinery
    import importlib.util
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent if root is None else Path(root)
    if pkg is None:
        spec = importlib.util.find_spec("bkwaves")  # (finds the package, imports nothing)
        if spec is None or spec.origin is None:
            return None
        pkg = Path(spec.origin).resolve().parent
    pkg = Path(pkg)
    # the file the import takes: the first suffix in the import system's order
    exts = [pkg / f"_core{s}" for s in importlib.machinery.EXTENSION_SUFFIXES]
    ext = next((p for p in exts if p.exists()), None)
    if pkg != root / "python" / "bkwaves" or ext is None:
        return None  # installed, not built in this tree
    built = ext.stat().st_mtime
    sources = [*root.glob("crates/**/*.rs"), root / "Cargo.lock"]
    sources += root.glob("crates/*/Cargo.toml")
    newer = [
        p
        for p in sources
        if p.exists()
        and not (p.stem == "tests" or p.stem.startswith("tests_") or p.stem.endswith("_tests"))
        and p.stat().st_mtime > built
    ]
    return max(newer, key=lambda p: p.stat().st_mtime).relative_to(root) if newer else None


def pytest_configure(config):
    stale = _stale_extension()
    if stale is not None:
        raise pytest.UsageError(
            f"bkwaves._core is older than {stale}: rebuild it (maturin develop --release) "
            "before testing, or the tests check an engine that is not the code in the tree"
        )
