"""Edges of the API a user meets: one block (the spring-block oscillator), in the API and
in configs; event numbers that are not the run's; snapshot times past t_end."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import bkwaves as bk

P = bk.Params(gamma=0.3, v=0.01, dx=0.1)


def _oscillator_slip(gamma, v):
    """One block slipping from the threshold (u = 1, u_t = v): u_tt = -u - 2 gamma (u_t - v)
    until u_t = v again, integrated by scipy (independent of the engine)."""

    def stuck_again(t, y):
        return y[1] - v

    stuck_again.terminal, stuck_again.direction = True, 1
    sol = solve_ivp(
        lambda t, y: [y[1], -y[0] - 2 * gamma * (y[1] - v)],
        [0, 100],
        [1.0, v],
        events=stuck_again,
        method="DOP853",
        rtol=1e-12,
        atol=1e-13,
        first_step=1e-6,
    )
    return float(sol.t_events[0][0]), float(sol.y_events[0][0][0])


@pytest.mark.parametrize(
    "make",
    [
        lambda b: bk.Chain(1, P, u0=0.6, boundary=b),
        lambda b: bk.Lattice((1, 1), P, u0=0.6, boundary=b),
    ],
    ids=["chain", "lattice"],
)
@pytest.mark.parametrize("boundary", ["free", "periodic"])
def test_one_block_is_the_damped_oscillator(make, boundary):
    res = make(boundary).run(max_events=3)
    s = res.slips
    duration, u_end = _oscillator_slip(0.3, 0.01)
    assert s["t_start"].iloc[0] == pytest.approx((1 - 0.6) / 0.01, abs=1e-9)
    np.testing.assert_allclose(s["t_end"] - s["t_start"], duration, rtol=0, atol=1e-7)
    np.testing.assert_allclose(s["u_end"], u_end, rtol=0, atol=1e-7)
    # stuck, the block's stress rises with the loader at exactly v
    wait = s["t_start"].to_numpy()[1:] - s["t_end"].to_numpy()[:-1]
    np.testing.assert_allclose(wait, (1 - s["u_end"].to_numpy()[:-1]) / 0.01, rtol=1e-12)


@pytest.mark.parametrize(
    "model,domain",
    [("chain", "blocks = 1"), ("lattice", "shape = [1, 1]")],
)
def test_one_block_config_runs_and_writes(tmp_path, model, domain):
    cfg = tmp_path / "one.toml"
    cfg.write_text(
        f'model = "{model}"\n[params]\ngamma = 0.3\nv = 0.01\ndx = 0.1\n'
        f'[domain]\n{domain}\nboundary = "periodic"\n'
        '[initial]\nkind = "uniform"\nvalue = 0.6\n[run]\nmax_events = 2\n'
        "[output]\nsnapshot_events = 1\n"
    )
    slips = bk.run(str(cfg), str(tmp_path / "one.nc")).tables["slips"]
    duration, _ = _oscillator_slip(0.3, 0.01)
    np.testing.assert_allclose(slips["t_end"] - slips["t_start"], duration, atol=1e-7)
    xr = pytest.importorskip("xarray")
    with xr.open_dataset(tmp_path / "one.nc") as ds:
        assert ds["u"].shape[1:] == ((1,) if model == "chain" else (1, 1))


def test_event_that_is_not_the_runs_is_a_named_error():
    la = bk.Lattice((40, 30), bk.Params(gamma=0.45, v=0.0, dx=0.1), u0=0.7)
    res = la.kick((20, 15), -2.0).run(t_end=3.0)
    assert np.isfinite(res.first_slip_times(event=0)).sum() == len(res.slips["block"].unique())
    assert res.first_slip_times(event=np.int64(0)).shape == (30, 40)
    for bad in (99, -1, 0.5, "0"):
        for f in (res.first_slip_times, res.slip_map):
            with pytest.raises(ValueError, match=r"^invalid event = .*: allowed .*0") as e:
                f(event=bad)
            assert "\n" not in str(e.value)
    quiet = bk.Chain(100, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).run(t_end=1.0)
    with pytest.raises(ValueError, match="this run has no events"):
        quiet.first_slip_times(event=0)


def test_snapshots_past_t_end_wait_for_the_next_run():
    ch = bk.Chain(200, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0)
    first = ch.run(t_end=5.0, snapshots=[3.0, 8.0])
    assert first.snapshots["t"].values.tolist() == [3.0]
    second = ch.run(t_end=10.0)
    assert second.snapshots["t"].values.tolist() == [3.0, 8.0]
    # the one taken later is the state of a run that stopped there, to the dense output's
    # accuracy (the two runs cut their steps at different times: 2e-11 here)
    ref = bk.Chain(200, bk.Params(gamma=0.3, v=0.0, dx=0.1), u0=0.6).kick(0, -2.0)
    ref_u = ref.run(t_end=8.0).u
    np.testing.assert_allclose(second.snapshots["u"].values[1], ref_u, rtol=0, atol=1e-9)
