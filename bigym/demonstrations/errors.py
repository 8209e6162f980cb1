"""Exceptions of the demonstration system.

Every error a user can meet derives from :class:`DemoError`, so one ``except DemoError``
catches them all; each message says what went wrong and, where there is one, what to do.
The extra attributes survive pickling, so errors raised in pool workers arrive intact.
"""

from __future__ import annotations


class DemoError(Exception):
    """Base class of every demonstration error."""

    def __init__(self, message: str, **details) -> None:
        super().__init__(message)
        self.message = message
        self.details = details
        for key, value in details.items():
            setattr(self, key, value)

    def __reduce__(self):
        return (_rebuild_error, (type(self), self.message, self.details))

    def __str__(self) -> str:
        return self.message


def _rebuild_error(cls, message, details):
    error = cls.__new__(cls)
    DemoError.__init__(error, message, **details)
    return error


class DemoNotFoundError(DemoError):
    """No demo matches the request (task, action mode, robot)."""


class TooManyDemosRequestedError(DemoNotFoundError):
    """More demos were asked for than the store holds for that request."""


class DemoChecksumError(DemoError):
    """A file's size or sha256 differs from the manifest (truncated or tampered download)."""


class DemoCorruptError(DemoError):
    """A file is not a readable demo: truncated, not safetensors, or missing keys."""


class DemoStoreBusyError(DemoError):
    """Another writer holds a remote store's write lease: attribute ``holder`` (who, since when)."""


class DemoBuildError(DemoError):
    """A demo of a shipped dataset could not be rebuilt as its manifest says."""


class DemoActionModeError(DemoError):
    """The demo was recorded with another action mode (or robot) than the one asked for."""


class DemoDivergenceError(DemoError):
    """A replay left the recorded trajectory: attributes ``step``, ``size``, ``where``, ``tolerance``."""


class DemoReplayError(DemoError):
    """A replay ran but did not reproduce the demo (no success at the end, unstable physics)."""


class DemoVersionWarning(UserWarning):
    """The demo was recorded with another bigym or MuJoCo version or another compiled model."""
