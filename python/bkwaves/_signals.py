"""Signals of the command line, from the first line bkwaves runs.

Before the command line knows what it will do, SIGINT (Ctrl-C) and SIGTERM are only
noted (:func:`install_early`, called when ``bkwaves`` starts, before its imports): a
signal that arrives while it starts is answered with one line and its exit status
(130, 143) once the command line can speak, never with a traceback nor a silent death.
Then each command decides: ``bkwaves run`` notes them and stops between engine chunks
(``bkwaves.runner``); the other commands get :func:`install_raising`: SIGINT raises
KeyboardInterrupt and SIGTERM :class:`Terminated` (a KeyboardInterrupt too), so the
cleanup a Ctrl-C does also runs for SIGTERM.
"""

from __future__ import annotations

import os
import signal
import sys

#: The signal noted while only noting (None: none).
pending: int | None = None
#: True in the command line's other commands: ``Chain.run`` passes an interrupt on
#: instead of returning what it computed (a figure must not be drawn from half a run).
propagate = False


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C's KeyboardInterrupt."""


def _note(signum, frame):
    global pending
    pending = signum


def _raise(signum, frame):
    global pending
    pending = signum
    if signum == signal.SIGTERM:
        raise Terminated
    raise KeyboardInterrupt


def _redeliver(unraisable) -> None:
    """``sys.unraisablehook`` of the raising commands. Where a signal's exception meets a
    finaliser or a weakref callback (the garbage collector runs them between any two
    lines), Python cannot pass it on: it would print "Exception ignored" and carry on, and
    the command would ignore Ctrl-C until it ends. The signal is delivered again a moment
    later, from outside, where it can stop the command; other unraisable exceptions go to
    the hook that was there before."""
    if isinstance(unraisable.exc_value, KeyboardInterrupt) and pending is not None:
        import threading  # (not at start-up: the handlers are installed before any import)

        threading.Timer(0.01, os.kill, (os.getpid(), pending)).start()
        return
    _previous_hook(unraisable)


_previous_hook = sys.unraisablehook


def _install(handler) -> None:
    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            if signal.getsignal(sig) == signal.SIG_IGN:
                continue  # ignored by whoever started us (a background job): stays so
            signal.signal(sig, handler)
        except ValueError:  # not the main thread
            pass


def save() -> tuple:
    """The handlers and the state now (for :func:`restore`)."""
    handlers = {}
    for sig in (signal.SIGINT, signal.SIGTERM):
        try:
            handlers[sig] = signal.getsignal(sig)
        except ValueError:
            pass
    return handlers, pending, propagate, sys.unraisablehook


def restore(saved: tuple) -> None:
    global pending, propagate
    handlers, pending, propagate, sys.unraisablehook = saved
    for sig, h in handlers.items():
        try:
            signal.signal(sig, h)
        except (ValueError, TypeError):
            pass


def install_early() -> None:
    """Note SIGINT and SIGTERM (see the module's docs)."""
    _install(_note)


def install_raising() -> None:
    """SIGINT raises KeyboardInterrupt, SIGTERM :class:`Terminated`."""
    global propagate, _previous_hook
    propagate = True
    if sys.unraisablehook is not _redeliver:
        _previous_hook = sys.unraisablehook
        sys.unraisablehook = _redeliver
    _install(_raise)
