"""Exceptions raised by sawdrive.

Every message is the one-line message the ``sawdrive`` command line prints after ``error:``
for the same input, so a key named there (``load.preload``, ``posts.count``, ``--jobs``) is
named here too. Bad scene values (wrong type, missing or wrong unit, out of range, unknown
key) are :class:`ValueError` subclasses.
"""

from __future__ import annotations

from typing import Any, List, Optional, Tuple


class SawdriveError(Exception):
    """Base class of every sawdrive error."""


class SceneError(SawdriveError, ValueError):
    """A scene is refused: unknown key, wrong type or unit, value out of range (names the key)."""


class SceneFileError(SawdriveError, OSError):
    """A scene or sweep file cannot be read (names the file)."""


class SweepError(SawdriveError, ValueError):
    """A sweep file is malformed: unknown key, empty grid, unknown chart column."""


class ArgumentError(SawdriveError, ValueError):
    """A call's argument is refused (e.g. ``jobs=0``, an unknown material, a bad diameter)."""


class PipelineError(SawdriveError, RuntimeError):
    """A stage failed on a valid scene (model refusal, solver limit, writing results)."""


class SweepPointsFailed(PipelineError):
    """Some points of a sweep failed; the others are saved (rerun to retry the failed ones).

    ``failures`` lists ``(overrides, message)`` per failed point and ``result`` holds the
    :class:`sawdrive.SweepResult` of the points that succeeded.
    """

    def __init__(self, message: str, failures: List[Tuple[str, str]], result: Optional[Any] = None):
        super().__init__(message)
        self.failures = failures
        self.result = result
