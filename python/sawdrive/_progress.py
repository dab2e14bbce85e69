"""Progress of long calls on a terminal or in a notebook.

The native call wakes every 0.1 s while the work runs on another thread and calls the
progress callback with ``(elapsed_s, done, total)`` (``done``/``total``: saved sweep points,
else ``None``). The default display is one line on stderr, rewritten with ``\\r`` (terminals
and Jupyter both honour it), shown only after :data:`SHOW_AFTER_S` so fast calls print nothing,
and erased when the call returns.
"""

from __future__ import annotations

import sys
from typing import Any, Callable, Optional, Tuple, Union

#: Seconds a call must run before its progress line appears (fast calls stay silent). Unit: s.
SHOW_AFTER_S = 0.5

ProgressArg = Union[None, bool, Callable[[float, Optional[int], Optional[int]], None]]

_FRAMES = "|/-\\"


#: ``(stream, whether it is a TTY)`` of the last stderr asked about: the answer is kept per
#: stream, so that a call does not pay a system call (on a loaded machine, a chance for the
#: scheduler to run something else: tens of µs) to decide whether to show a progress line.
_TTY_OF: Tuple[Any, bool] = (None, False)


def attached() -> bool:
    """Whether a terminal (stderr is a TTY) or a Jupyter kernel is attached."""
    global _TTY_OF
    if "ipykernel" in sys.modules:
        return True
    stream, tty = _TTY_OF
    if stream is not sys.stderr:
        stream = sys.stderr
        try:
            tty = stream.isatty()
        except (AttributeError, ValueError):
            tty = False
        _TTY_OF = (stream, tty)
    return tty


class Spinner:
    """One self-rewriting line on stderr: ``sawdrive <what>  [points k/N]  12.3 s``."""

    def __init__(self, what: str):
        self.what = what
        self.shown = 0
        self.ticks = 0

    def __call__(self, elapsed_s: float, done: Optional[int], total: Optional[int]) -> None:
        if elapsed_s < SHOW_AFTER_S:
            return
        self.ticks += 1
        points = f"  points {done}/{total}" if total is not None else ""
        line = f"{_FRAMES[self.ticks % len(_FRAMES)]} sawdrive {self.what}{points}  {elapsed_s:.1f} s"
        sys.stderr.write("\r" + line.ljust(self.shown))
        sys.stderr.flush()
        self.shown = len(line)

    def close(self) -> None:
        """Erase the line (if one was shown)."""
        if self.shown:
            sys.stderr.write("\r" + " " * self.shown + "\r")
            sys.stderr.flush()
            self.shown = 0


def callback(progress: ProgressArg, what: str):
    """The callback for a call's ``progress`` argument and a closer to run afterwards.

    ``None``: a spinner when a terminal or notebook is attached; ``True``/``False``: always or
    never; a callable: called with ``(elapsed_s, done, total)`` on every tick.
    """
    if callable(progress):
        return progress, lambda: None
    enabled = attached() if progress is None else bool(progress)
    if not enabled:
        return None, lambda: None
    spinner = Spinner(what)
    return spinner, spinner.close
