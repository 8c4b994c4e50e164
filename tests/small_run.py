"""The small kicked chain run (200 blocks, 61 snapshots) that the output tests write, as a
config dict and as TOML (tests/test_output_safety.py, tests/test_full_disk.py)."""

SMALL = {
    "model": "chain",
    "params": {"gamma": 0.3, "v": 0.0, "dx": 0.05},
    "domain": {"blocks": 200},
    "initial": {"kind": "uniform", "value": 0.6},
    "triggers": [{"block": 0, "kind": "kick", "velocity": 2.0}],
    "run": {"t_end": 30.0},
    "output": {"snapshot_every": 0.5},
}
SMALL_TOML = (
    'model = "chain"\n[params]\ngamma = 0.3\nv = 0.0\ndx = 0.05\n[domain]\nblocks = 200\n'
    '[initial]\nkind = "uniform"\nvalue = 0.6\n'
    '[[triggers]]\nblock = 0\nkind = "kick"\nvelocity = 2.0\n'
    "[run]\nt_end = 30.0\n[output]\nsnapshot_every = 0.5\n"
)
