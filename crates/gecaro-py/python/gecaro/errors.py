"""The exceptions of gecaro.

Every failure of a gecaro call raises a subclass of :class:`GecaroError`, with
the message the command line prints for the same failure:

* :class:`InputError` (also a ``ValueError``): a malformed file, a value that
  breaks a rule of the robot model, data that do not fit the method, an array
  of the wrong shape or dtype, an unknown name.
* :class:`NotIdentifiableError`: the data give fewer independent equations
  than there are unknowns.
* :class:`NotConvergedError`: an identification that did not converge (its
  best iterate is in ``.result``), an unreachable inverse-model target, a
  points generation that found no configurations.
* :class:`NumericalError`: another numerical failure (a factorisation of
  non-finite values, a plot).

Ctrl-C during a long call raises ``KeyboardInterrupt`` as usual. Joint values
outside the joint limits give a :class:`LimitWarning` (an error with
``strict_limits=True``).
"""

from __future__ import annotations

from typing import Any, Optional

__all__ = [
    "GecaroError",
    "InputError",
    "NumericalError",
    "NotIdentifiableError",
    "NotConvergedError",
    "LimitWarning",
]


class GecaroError(Exception):
    """Base class of every gecaro error."""


class InputError(GecaroError, ValueError):
    """Bad input: files, values, shapes, names (the command line's exit code 3)."""


class NumericalError(GecaroError):
    """Well-formed input without a trustworthy answer (the command line's exit code 4)."""


class NotIdentifiableError(NumericalError):
    """Fewer independent equations than unknowns: add configurations."""


class NotConvergedError(NumericalError):
    """An iteration that did not reach its goal.

    For an identification, ``result`` holds the best iterate (a
    :class:`gecaro.Identification`); it is ``None`` otherwise.
    """

    result: Optional[Any] = None


class LimitWarning(UserWarning):
    """Measured joint values outside the robot's joint limits."""
