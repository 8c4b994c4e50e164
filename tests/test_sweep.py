"""Parameter sweeps on Dask (bkwaves sweep, bk.sweep): schema, results against direct
calls, resume, failures, and a real scheduler with two worker processes, one of which is
killed mid-sweep."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import bkwaves as bk
from bkwaves.sweeps import DONE, FAILED, SweepSpec, load_sweep, parse_sweep, sweep

WAVE = {
    "task": "wave",
    "base": {"gamma": 0.3},
    "axes": {
        "u_plus": {"linspace": {"start": 0.2, "stop": 0.8, "num": 4}},
        "gamma": {"values": [0.0, 0.3]},
    },
}


@pytest.fixture(scope="module")
def client():
    """One in-process threaded cluster for the fast tests (the process-based default
    LocalCluster is tested once below)."""
    from distributed import Client, LocalCluster

    cluster = LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=":0"
    )
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


# --------------------------------------------------------------------------- schema


@pytest.mark.parametrize(
    "doc, where",
    [
        ({**WAVE, "task": "nope"}, "task"),
        ({**WAVE, "colour": 1}, "colour"),
        ({**WAVE, "axes": {"u_plus": {"values": []}}}, "axes.u_plus.values"),
        ({**WAVE, "axes": {"u_plus": {"values": [0.1], "linspace": {}}}}, "axes.u_plus"),
        ({**WAVE, "axes": {"u_plus": {"linspace": {"start": 0.1, "stop": 0.5}}}}, "num"),
        (
            {**WAVE, "axes": {"u_plus": {"logspace": {"start": 0, "stop": 1, "num": 3}}}},
            "axes.u_plus.logspace",
        ),
        ({**WAVE, "base": {"gamma": 0.3, "colour": 2}}, "base.colour"),
        ({**WAVE, "combine": "zip"}, "zip"),
        ({**WAVE, "axes": {"u_plus": {"bounds": [0.1, 0.9]}}}, "adaptive"),
        ({**WAVE, "axes": {"u_plus": {"values": [0.1, 0.1]}}}, "repeat"),
    ],
)
def test_bad_sweeps_name_the_key(doc, where):
    with pytest.raises(bk.ParameterError, match=where.replace(".", r"\.")):
        parse_sweep(doc)


def test_spec_round_trip_and_points():
    spec = parse_sweep(WAVE)
    assert spec.shape == (4, 2) and spec.dims == ("u_plus", "gamma")
    again = SweepSpec.from_dict(spec.to_dict())
    assert again == spec
    p = spec.point((1, 0))
    assert p == {"gamma": 0.0, "u_plus": pytest.approx(0.4)}
    # the key is a function of the whole input: another base gives another key
    other = parse_sweep({**WAVE, "base": {"gamma": 0.1}})
    assert spec.key(spec.point((1, 1))) == spec.key(spec.point((1, 1)))
    assert spec.key(spec.point((1, 1))) != spec.key(spec.point((1, 0)))
    assert other.key(other.point((1, 1))) == spec.key(spec.point((1, 1)))  # gamma on the axis
    zipped = parse_sweep(
        {
            "task": "speed",
            "combine": "zip",
            "axes": {"u_plus": {"values": [0.1, 0.5]}, "dx": {"values": [0.05, 0.1]}},
        }
    )
    assert zipped.shape == (2,) and zipped.point((1,)) == {"u_plus": 0.5, "dx": 0.1}
    seeds = parse_sweep(
        {"task": "speed", "axes": {"u_plus": {"range": {"start": 1, "stop": 4, "step": 1}}}},
    )
    assert seeds.axes[0].values == (1, 2, 3)


def test_load_sweep_file_defaults_output_beside(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text('task = "speed"\n[axes.u_plus]\nvalues = [0.3, 0.6]\n')
    spec = load_sweep(f)
    assert spec.output_path == str(tmp_path / "s.zarr")
    f.write_bytes(b"task = \xff\n")
    with pytest.raises(bk.ParameterError, match="not valid TOML"):
        load_sweep(f)


# --------------------------------------------------------------------------- results


def test_results_equal_direct_calls_and_resume_recomputes_nothing(tmp_path, client):
    out = tmp_path / "w.zarr"
    r = sweep(WAVE, out, client=client)
    assert (r.computed, r.skipped, r.failed) == (8, 0, 0)
    ds = r.dataset
    assert ds["status"].dims == ("u_plus", "gamma") and (ds["status"] == DONE).all()
    for u in ds.u_plus.values:
        for g in ds.gamma.values:
            w = bk.traveling_wave(float(u), float(g))
            cell = ds.sel(u_plus=u, gamma=g)
            assert float(cell["c"]) == w.c
            assert str(cell["regime"].values) == w.regime
            if w.w is None:
                assert np.isnan(float(cell["w"]))
            else:
                assert float(cell["w"]) == w.w
    again = sweep(WAVE, out, client=client)
    assert (again.computed, again.skipped) == (0, 8)


def test_interrupted_sweep_keeps_points_and_resumes_the_rest(tmp_path, client):
    out = tmp_path / "w.zarr"
    r = sweep(WAVE, out, client=client, _stop_after=3)
    assert r.interrupted and r.computed == 3
    assert int((r.dataset["status"] == DONE).sum()) == 3
    rest = sweep(WAVE, out, client=client)
    assert (rest.computed, rest.skipped) == (5, 3)
    assert (rest.dataset["status"] == DONE).all()


def test_failed_point_records_its_error_and_the_sweep_goes_on(tmp_path, client):
    doc = {"task": "speed", "axes": {"u_plus": {"values": [0.3, 1.5, 0.6]}}}
    r = sweep(doc, tmp_path / "f.zarr", client=client)
    ds = r.dataset
    assert (r.computed, r.failed) == (2, 1)
    assert list(ds["status"].values) == [DONE, FAILED, DONE]
    assert "u_plus" in str(ds["error"].values[1])
    assert float(ds["c"][2]) == float(bk.front_speed(0.6))
    # failed points stay failed on a re-run unless asked
    again = sweep(doc, tmp_path / "f.zarr", client=client)
    assert (again.computed, again.failed, again.skipped) == (0, 0, 3)
    retry = sweep(doc, tmp_path / "f.zarr", client=client, retry_failed=True)
    assert (retry.computed, retry.failed, retry.skipped) == (0, 1, 2)


def test_a_changed_input_is_recomputed_and_other_stores_are_refused(tmp_path, client):
    out = tmp_path / "w.zarr"
    sweep(WAVE, out, client=client)
    with pytest.raises(bk.ParameterError, match="different sweep"):
        sweep({**WAVE, "axes": {"u_plus": {"values": [0.5]}}}, out, client=client)
    # someone else's directory that happens to end in .zarr is never touched
    foreign = tmp_path / "theirs.zarr"
    foreign.mkdir()
    (foreign / "precious.txt").write_text("keep")
    with pytest.raises(bk.ParameterError, match="not a bkwaves sweep"):
        sweep(WAVE, foreign, client=client, overwrite=True)
    assert (foreign / "precious.txt").read_text() == "keep"
    r = sweep({**WAVE, "axes": {"u_plus": {"values": [0.5]}}}, out, client=client, overwrite=True)
    assert r.computed == 1


def test_local_cluster_of_processes(tmp_path):
    doc = {"task": "speed", "axes": {"u_plus": {"values": [0.2, 0.4]}}}
    r = sweep(doc, tmp_path / "p.zarr", workers=2, processes=True)
    assert r.workers == 2 and r.computed == 2 and r.dashboard
    np.testing.assert_array_equal(r.dataset["c"].values, bk.front_speed(np.array([0.2, 0.4])))


def test_a_scheduler_address_leaves_no_client_behind(tmp_path):
    """bk.sweep(..., scheduler=ADDRESS) connects a client of its own and closes it: the
    caller's cluster outlives the sweep without a dangling default client."""
    from distributed import LocalCluster, default_client

    def current():
        try:
            return default_client()
        except ValueError:  # "No clients found"
            return None

    # other tests of this module may hold a client of their own (the `client` fixture):
    # the sweep must leave the default client as it found it, whatever that was
    before = current()
    doc = {"task": "speed", "axes": {"u_plus": {"values": [0.2, 0.4]}}}
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None
    ) as cluster:
        r = sweep(doc, tmp_path / "a.zarr", scheduler=cluster.scheduler_address)
        assert r.computed == 2
        assert current() is before

        # and the sweep's own connection to the scheduler is closed (the scheduler may take
        # a moment to drop it)
        def sweep_clients():
            return [c for c in cluster.scheduler.clients if c.startswith("Client-")]

        deadline = time.monotonic() + 10.0
        while sweep_clients() and time.monotonic() < deadline:
            time.sleep(0.05)
        assert sweep_clients() == []


# --------------------------------------------------------------------------- a real cluster


def _dask() -> str:
    """The `dask` command of the Python running the tests (its venv's bin), whether or not
    that venv is on PATH; else whatever PATH finds."""
    beside = Path(sys.executable).parent / "dask"
    return str(beside) if beside.exists() else "dask"


def _env():
    env = dict(os.environ)
    root = Path(bk.__file__).resolve().parents[1]
    env["PYTHONPATH"] = os.pathsep.join([str(root), env.get("PYTHONPATH", "")])
    return env


def _wait_for(pred, timeout, what):
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        v = pred()
        if v:
            return v
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def _done_count(out: Path) -> int:
    import zarr

    try:
        g = zarr.open_group(str(out), mode="r", use_consolidated=False)
        return int((np.asarray(g["status"][...]) == DONE).sum())
    except Exception:  # noqa: BLE001 - the store may not exist yet
        return 0


def test_real_scheduler_survives_a_killed_worker(tmp_path):
    """A scheduler and two worker processes on 127.0.0.1 (ephemeral ports); the sweep runs
    through --scheduler; one worker is killed mid-sweep; every point ends done exactly once,
    with the values a direct call gives."""
    env = _env()
    sfile = tmp_path / "scheduler.json"
    procs = []
    try:
        procs.append(
            subprocess.Popen(
                [
                    _dask(),
                    "scheduler",
                    "--host",
                    "127.0.0.1",
                    "--port",
                    "0",
                    "--no-dashboard",
                    "--scheduler-file",
                    str(sfile),
                ],
                env=env,
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
        )
        _wait_for(lambda: sfile.exists() and sfile.stat().st_size > 0, 60, "the scheduler")
        addr = json.loads(sfile.read_text())["address"]
        for _ in range(2):
            procs.append(
                subprocess.Popen(
                    [
                        _dask(),
                        "worker",
                        addr,
                        "--nthreads",
                        "1",
                        "--no-nanny",
                        "--no-dashboard",
                        "--host",
                        "127.0.0.1",
                    ],
                    env=env,
                    stdout=subprocess.DEVNULL,
                    stderr=subprocess.DEVNULL,
                )
            )
        n_u, n_dx = 6, 2
        toml = tmp_path / "fronts.toml"
        toml.write_text(
            'task = "front"\n[base]\ngamma = 0.3\nblocks = 3000\n'
            f"[axes.u_plus]\nlinspace = {{start = 0.5, stop = 0.8, num = {n_u}}}\n"
            "[axes.dx]\nvalues = [0.05, 0.1]\n"
        )
        out = tmp_path / "fronts.zarr"
        cli = subprocess.Popen(
            [
                sys.executable,
                "-m",
                "bkwaves",
                "sweep",
                str(toml),
                "-o",
                str(out),
                "--scheduler",
                addr,
                "--json",
            ],
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        _wait_for(lambda: _done_count(out) >= 2 or cli.poll() is not None, 120, "2 points")
        assert cli.poll() is None, "the sweep ended before a worker could be killed"
        victim = procs[1]
        victim.send_signal(signal.SIGKILL)
        victim.wait(10)
        stdout, stderr = cli.communicate(timeout=300)
        assert cli.returncode == 0, stderr
        summary = json.loads(stdout)
        assert summary["points"] == n_u * n_dx
        # every point computed once: no loss, no duplicate
        assert summary["computed"] == n_u * n_dx and summary["skipped"] == 0, (
            summary,
            str(bk.sweep_result(out)["error"].values),
        )
        assert summary["failed"] == 0
        ds = bk.sweep_result(out)
        assert (ds["status"] == DONE).all()
        for u in ds.u_plus.values[::3]:
            m = bk.chain.front(float(u), 0.3, 0.1, blocks=3000)
            assert float(ds["c"].sel(u_plus=u, dx=0.1)) == m.c
    finally:
        for p in procs:
            if p.poll() is None:
                p.terminate()
        for p in procs:
            try:
                p.wait(10)
            except subprocess.TimeoutExpired:
                p.kill()


def test_adaptive_sweep_refines_where_the_output_changes_fastest(tmp_path, client):
    """c = 1/sqrt(1 - u^2) is flat at small u and steep near 1: the learner puts far more
    points near u = 1 than a uniform grid would; a re-run with a larger goal continues
    from the stored points."""
    doc = {
        "task": "speed",
        "axes": {"u_plus": {"bounds": [0.001, 0.999]}},
        "adaptive": {"output": "c", "npoints": 24},
    }
    out = tmp_path / "a.zarr"
    r = sweep(doc, out, client=client)
    ds = r.dataset
    u = ds.u_plus.values
    assert r.computed == 24 and len(u) == 24 and (ds["status"] == DONE).all()
    assert np.all(np.diff(u) > 0)
    np.testing.assert_array_equal(ds["c"].values, bk.front_speed(u))
    # uniform sampling would put 10 % of the points in [0.9, 0.999]
    assert np.mean(u >= 0.9) > 0.3
    more = sweep({**doc, "adaptive": {"output": "c", "npoints": 30}}, out, client=client)
    assert (more.skipped, more.computed) == (24, 6)
    assert len(more.dataset.u_plus) == 30


def test_run_task_over_seeds_with_catalogs(tmp_path, client):
    """task = "run": each point is bk.run of the base config with the axes set; the summary
    equals the direct in-memory run, and each point's catalog is written once beside."""
    from bkwaves.sweeps import points_dir

    base = bk.config.load_config(
        Path(__file__).parents[1] / "examples" / "free_boundary_random.toml"
    ).to_dict()
    base["run"] = {"t_end": 600.0}
    base["output"] = {"units": "native"}
    doc = {
        "task": "run",
        "base": base,
        "axes": {"seed": {"seeds": 3}, "initial.amplitude": {"values": [0.02, 0.2]}},
        "output": {"catalogs": True},
    }
    out = tmp_path / "seeds.zarr"
    r = sweep(doc, out, client=client)
    ds = r.dataset
    assert r.computed == 6 and (ds["status"] == DONE).all()
    assert ds["n_events"].dims == ("seed", "amplitude")
    direct = bk.run({**base, "seed": 2, "initial": {**base["initial"], "amplitude": 0.2}})
    cell = ds.sel(seed=2, amplitude=0.2)
    assert float(cell["n_events"]) == direct.summary["n_events"]
    assert float(cell["t"]) == direct.summary["t"]
    files = sorted(points_dir(out).glob("*.events.parquet"))
    assert len(files) == 6
    key = str(cell["key"].values)
    import pandas as pd

    pd.testing.assert_frame_equal(
        pd.read_parquet(points_dir(out) / f"{key}.events.parquet"), direct.events
    )


@pytest.mark.parametrize(
    "path",
    sorted((Path(__file__).parents[1] / "examples").glob("sweep_*.toml")),
    ids=lambda p: p.name,
)
def test_example_sweeps_are_valid(path):
    spec = load_sweep(path)
    assert spec.output_path.endswith(".zarr") and len(spec.indices()) > 1


def test_sigterm_keeps_finished_points_and_exits_143(tmp_path):
    """SIGTERM to `bkwaves sweep` mid-sweep: exit 143 with a message saying how to go on;
    the finished points are in the store; the same command computes only the rest."""
    toml = tmp_path / "fronts.toml"
    toml.write_text(
        'task = "front"\n[base]\ngamma = 0.3\nblocks = 8000\ndx = 0.05\n'
        "[axes.u_plus]\nlinspace = {start = 0.5, stop = 0.8, num = 40}\n"
    )
    out = tmp_path / "fronts.zarr"
    cmd = [
        sys.executable,
        "-m",
        "bkwaves",
        "sweep",
        str(toml),
        "-o",
        str(out),
        "--workers",
        "1",
        "--json",
    ]
    cli = subprocess.Popen(
        cmd, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    _wait_for(lambda: _done_count(out) >= 2 or cli.poll() is not None, 120, "2 points")
    assert cli.poll() is None, "the sweep ended before it could be interrupted"
    cli.send_signal(signal.SIGTERM)
    _stdout, stderr = cli.communicate(timeout=120)
    assert cli.returncode == 143, stderr
    assert "run the same command again" in stderr
    kept = _done_count(out)
    assert 2 <= kept < 40
    again = subprocess.run(cmd, env=_env(), capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stderr
    summary = json.loads(again.stdout)
    assert summary["skipped"] == kept and summary["computed"] == 40 - kept


def test_run_task_snapshots_per_point(tmp_path, client):
    base = bk.config.load_config(
        Path(__file__).parents[1] / "examples" / "free_boundary_source.toml"
    ).to_dict()
    base["run"] = {"max_events": 2}
    doc = {
        "task": "run",
        "base": base,
        "axes": {"params.gamma": {"values": [0.2, 0.3]}},
        "output": {"snapshots": True},
    }
    out = tmp_path / "snap.zarr"
    r = sweep(doc, out, client=client)
    assert r.computed == 2
    from bkwaves.sweeps import points_dir

    for g in (0.2, 0.3):
        key = str(r.dataset["key"].sel(gamma=g).values)
        import xarray as xr

        with xr.open_dataset(points_dir(out) / f"{key}.nc", engine="h5netcdf") as snap:
            direct = bk.run({**base, "params": {**base["params"], "gamma": g}}, snapshots=True)
            np.testing.assert_array_equal(snap["u"].values, direct.snapshots["u"].values)
    assert not list(points_dir(out).glob("*.parquet"))  # catalogs were not asked for
