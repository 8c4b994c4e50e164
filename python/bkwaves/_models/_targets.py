"""The run loop both free boundary models share: advance the engine from one snapshot
time to the next, write the snapshots asked (at times and every k events), checkpoint when
due, and keep the loop's place in the checkpoint so a resumed run makes the same engine
calls and writes the same snapshots."""

from __future__ import annotations

import math


class TargetLoop:
    """The targets of a run (the snapshot times up to t_end, and t_end) and its place
    among them.

    Building it writes the snapshot at t = 0 (``snap``) unless the run resumes; a resumed
    run takes its place from the checkpoint's runner state.
    """

    def __init__(self, cfg, ctl, snap, actions=()):
        from ..runner import _snapshot_times

        t_end = cfg.t_end if cfg.t_end is not None else math.inf
        times = _snapshot_times(cfg).tolist()
        if times and times[0] <= 0.0:
            if not ctl.resuming:
                snap()
            times.pop(0)
        self.wanted = {t for t in times if t <= t_end}
        # actions (time, act): act() when the engine reaches that time (a trigger), in
        # the order given, after the snapshot of that time (those at t = 0 now; none at or
        # after t_end)
        self.actions: dict[float, list] = {}
        for t, act in actions:
            if t < t_end:
                self.actions.setdefault(float(t), []).append(act)
        if not ctl.resuming:
            for act in self.actions.pop(0.0, []):
                act()
        else:
            self.actions.pop(0.0, None)
        self.targets = sorted(self.wanted | set(self.actions) | {t_end})
        if ctl.resuming:
            rs = ctl.state["runner"]
            self.next, self.last_every_k = int(rs["next_target"]), int(rs["last_every_k"])
        else:
            self.next = self.last_every_k = 0

    def state(self) -> dict:
        """The loop's place, for the checkpoint's runner state."""
        return {"next_target": self.next, "last_every_k": self.last_every_k}

    def run(self, eng, cfg, ctl, bar, chunk, completed, snap, save, after_chunk=None) -> bool:
        """Advance ``eng`` through the targets until the last one, ``cfg.max_events``
        completed events (``completed()``) or a stop asked by ``ctl``; ``save(state)``
        writes a checkpoint when one is due, ``after_chunk()`` runs after every engine
        call. Returns whether the run finished."""
        target_events = cfg.max_events if cfg.max_events is not None else 2**62
        finished = self.next == len(self.targets)
        while not finished and not ctl.stop:
            target = self.targets[self.next]
            status = eng.advance(float(target), int(chunk), int(target_events))
            done = completed()
            bar.update(eng.time if cfg.t_end else done)
            k = cfg.snapshot_events
            if k and done // k > self.last_every_k:
                self.last_every_k = done // k
                snap()
            if status == "time":
                self.next += 1
                if target in self.wanted:
                    snap()
                for act in self.actions.get(target, ()):
                    act()
            if after_chunk is not None:
                after_chunk()
            if status == "events" or self.next == len(self.targets):
                finished = True
                break
            ctl.chunk_done()
            if not ctl.stop and ctl.due():
                save(self.state())
        return finished
