"""The one progress bar of bkwaves (rich, on stderr, gone when done): the chain and free
boundary engines' ``run(progress=True)`` and the ``bkwaves run`` command."""

from __future__ import annotations

import math


class ProgressBar:
    """A transient progress bar of ``total`` units labelled ``label``; does nothing when
    not ``enabled``. rich is imported only when a bar is shown."""

    def __init__(self, enabled: bool, total: float, label: str, unit: str = ""):
        self._progress = None
        if not enabled:
            return
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            Progress,
            TaskProgressColumn,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self._progress = Progress(
            TextColumn("{task.description}"),
            BarColumn(),
            TaskProgressColumn(),
            TextColumn(f"{unit}{{task.completed:.4g}}/{{task.total:.4g}}"),
            TimeElapsedColumn(),
            TimeRemainingColumn(),
            console=Console(stderr=True),
            transient=True,
        )
        self._progress.start()
        self._task = self._progress.add_task(label, total=total)

    def update(self, completed: float) -> None:
        if self._progress is not None:
            self._progress.update(self._task, completed=completed)

    def close(self) -> None:
        if self._progress is not None:
            self._progress.stop()
            self._progress = None


class RunProgress(ProgressBar):
    """Progress of an engine run: over time from ``t0`` to a finite ``t_end``, else over
    the ``max_events`` events counted from ``events0``."""

    def __init__(self, enabled, label, t0, t_end, max_events, events0=0):
        self.by_time = math.isfinite(t_end)
        self.t0, self.events0 = t0, events0
        if self.by_time:
            super().__init__(enabled, t_end - t0, label, "t - t0 = ")
        else:
            super().__init__(enabled, float(max_events or 1), label, "events ")

    def advance(self, t: float, events: int) -> None:
        self.update(t - self.t0 if self.by_time else events - self.events0)
