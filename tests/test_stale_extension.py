"""The test session's guard against an editable extension built from older Rust sources
(tests/conftest.py): checked on a tree of files with chosen modification times."""

import importlib.machinery
import os

from conftest import _stale_extension

SUFFIX = importlib.machinery.EXTENSION_SUFFIXES[0]


def _tree(tmp_path, built=1000.0):
    """A repository with a built extension (mtime ``built``) and sources older than it."""
    pkg = tmp_path / "python" / "bkwaves"
    pkg.mkdir(parents=True)
    src = tmp_path / "crates" / "bkwaves-core" / "src"
    src.mkdir(parents=True)
    files = {
        "ext": pkg / f"_core{SUFFIX}",
        "rs": src / "engine.rs",
        "tests_rs": src / "tests_engine.rs",
        "tests": src / "tests.rs",
        "manifest": tmp_path / "crates" / "bkwaves-core" / "Cargo.toml",
        "lock": tmp_path / "Cargo.lock",
    }
    for name, path in files.items():
        path.write_text(name)
        t = built if name == "ext" else built - 10.0
        os.utime(path, (t, t))
    return pkg, files


def _touch(path, t):
    os.utime(path, (t, t))


def test_an_extension_newer_than_every_source_is_not_stale(tmp_path):
    pkg, _ = _tree(tmp_path)
    assert _stale_extension(tmp_path, pkg) is None


def test_a_newer_rust_source_a_manifest_or_the_lock_makes_it_stale(tmp_path):
    for key, rel in [
        ("rs", "crates/bkwaves-core/src/engine.rs"),
        ("manifest", "crates/bkwaves-core/Cargo.toml"),
        ("lock", "Cargo.lock"),
    ]:
        pkg, files = _tree(tmp_path / key)
        _touch(files[key], 2000.0)
        assert str(_stale_extension(tmp_path / key, pkg)) == rel


def test_the_newest_of_several_newer_sources_is_named(tmp_path):
    pkg, files = _tree(tmp_path)
    _touch(files["lock"], 2000.0)
    _touch(files["rs"], 3000.0)
    assert str(_stale_extension(tmp_path, pkg)) == "crates/bkwaves-core/src/engine.rs"


def test_test_modules_do_not_make_it_stale(tmp_path):
    # (they are not in the extension: #[cfg(test)])
    pkg, files = _tree(tmp_path)
    _touch(files["tests_rs"], 2000.0)
    _touch(files["tests"], 2000.0)
    assert _stale_extension(tmp_path, pkg) is None


def test_a_package_installed_elsewhere_or_without_an_extension_is_never_stale(tmp_path):
    pkg, files = _tree(tmp_path / "repo")
    _touch(files["rs"], 2000.0)
    assert _stale_extension(tmp_path / "repo", pkg) is not None
    # installed into a virtual environment: the tree's sources say nothing about it
    site = tmp_path / "venv" / "site-packages" / "bkwaves"
    site.mkdir(parents=True)
    (site / f"_core{SUFFIX}").write_text("ext")
    _touch(site / f"_core{SUFFIX}", 1.0)
    assert _stale_extension(tmp_path / "repo", site) is None
    # an editable tree never built
    files["ext"].unlink()
    assert _stale_extension(tmp_path / "repo", pkg) is None
