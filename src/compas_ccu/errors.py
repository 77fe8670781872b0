"""Exceptions of compas_ccu.

Every error names the cause and the offending value, so a user can fix the input.
All derive from :class:`CCUError` (a :class:`ValueError`), so ``except ValueError`` also works.
The ``ccu`` command prints a CCUError as one line with exit status 2; any other exception is a
bug in compas_ccu (traceback, exit status 1). Every error pickles (Dask sends them between
processes): classes with keyword-only attributes define ``__reduce__``.
"""

from __future__ import annotations

import importlib.util

__all__ = [
    "CCUError",
    "ProfileError",
    "DevelopabilityError",
    "DeploymentLimitError",
    "DesignError",
    "GeometryError",
    "MissingExtraError",
    "OptionError",
    "LimitError",
    "SelfIntersectionError",
    "SweepError",
    "FitError",
    "FEError",
    "ConvergenceError",
    "MaterialError",
    "rebuild_error",
    "require",
    "missing_modules",
    "CCUWarning",
    "UnitsWarning",
]


class CCUError(ValueError):
    """Base class of all compas_ccu errors."""


class CCUWarning(UserWarning):
    """Base class of the warnings of compas_ccu (the ``ccu`` command prints them as
    ``ccu: warning: ...``)."""


class UnitsWarning(CCUWarning):
    """A length of a design file is implausible for its ``[design] units`` (a likely mix-up of
    metres and millimetres); the message names the key, the value and the units that fit."""


class ProfileError(CCUError):
    """A crease profile cannot be built from the given parameters."""


class DevelopabilityError(CCUError):
    """A requested ruling or reflection-angle field is not developable (docs/geometry.md §1)."""


class GeometryError(CCUError):
    """Input geometry is degenerate or inconsistent (zero-length edge, straight crease, ...)."""


class OptionError(CCUError):
    """An option or argument value is not allowed (a bad ``ccu`` option, a figure format, a
    number of steps below 1, an unknown catalog design ...); the message names it."""


class MissingExtraError(CCUError):
    """An optional extra (viz, fea, fab, explore) needed for this is not installed
    (:func:`require` raises it)."""


class LimitError(CCUError):
    """A request beyond a work limit (segments, plates, states, sweep size, memory); the message
    names the limit, the value and how to raise it (:mod:`compas_ccu.limits`)."""


class DesignError(CCUError):
    """A design file is invalid: unknown key, wrong type or impossible value."""

    def __init__(self, message: str, *, key: str | None = None):
        self.key = key
        super().__init__(f"{key}: {message}" if key else message)


class DeploymentLimitError(CCUError):
    """The requested reflection angle lies beyond the deployment limit of the mechanism.

    Attributes
    ----------
    alpha : float
        The requested reference reflection angle, degrees.
    alpha_limit : float
        The largest reachable reference reflection angle, degrees.
    vertex : int
        Index of the crease vertex of the leading crease where the limit occurs.
    """

    def __init__(self, message: str, *, alpha: float, alpha_limit: float, vertex: int):
        self.alpha = alpha
        self.alpha_limit = alpha_limit
        self.vertex = vertex
        super().__init__(message)

    def __reduce__(self):
        return rebuild_error, (type(self), self.args, self.__dict__)


class SelfIntersectionError(CCUError):
    """Plates would pass through each other at the requested state: a crease overlaps itself
    in its plane, or two plates cross on the path from the flat stack (the certificate of
    :mod:`compas_ccu.kinematics.interference`).

    Attributes
    ----------
    alpha : float
        The requested reference reflection angle, degrees.
    crease : int or None
        Crease id (None: the leading crease curve when it joins no second plate, or two plates
        that cross).
    plates : tuple of int or None
        The ids of the two plates that cross first, or None (a crease overlapping itself).
    """

    def __init__(self, message: str, *, alpha: float, crease, plates=None):
        self.alpha = alpha
        self.crease = crease
        self.plates = plates
        super().__init__(message)

    def __reduce__(self):
        return rebuild_error, (type(self), self.args, self.__dict__)


class SweepError(CCUError):
    """A sweep file (``ccu explore``) or an optimisation study (``ccu optimize``) is invalid, or
    its output folder belongs to another sweep or study."""

    def __init__(self, message: str, *, key: str | None = None):
        self.key = key
        super().__init__(f"{key}: {message}" if key else message)


class FitError(CCUError):
    """A fit to geometry failed (``ccu asbuilt``, ``ccu fit``): a scan that fits no state of
    the design, a target no design within the bounds can reach, a fit that did not converge
    within its evaluations; the message names the cause and the value."""


class FEError(CCUError):
    """An FE problem is inconsistent or an engine is missing."""


class ConvergenceError(CCUError):
    """A nonlinear analysis did not converge, even after cutting the step.

    Attributes
    ----------
    step : int
        The step (1 .. S) that failed.
    residual : float
        The last relative residual / displacement-increment norm of Newton.
    result : compas_ccu.fea.FEResult
        The converged history up to ``step - 1`` (for inspection, not as a result).
    """

    def __init__(self, message: str, *, step: int, residual: float, result=None):
        self.step = step
        self.residual = residual
        self.result = result
        super().__init__(message)

    def __reduce__(self):  # keyword-only attributes: pickle them (Dask workers, copies)
        return rebuild_error, (type(self), self.args, self.__dict__)


class MaterialError(CCUError):
    """A material name or value is unknown or impossible."""


def rebuild_error(cls, args, attributes):
    """Unpickle an error whose ``__init__`` takes keyword-only attributes."""
    error = CCUError.__new__(cls, *args)
    error.args = args
    error.__dict__.update(attributes)
    return error


def missing_modules(names) -> list:
    """The modules of ``names`` that are not installed (found without importing them)."""
    return [m for m in names if importlib.util.find_spec(m) is None]


def require(modules, extra: str, *, what: str, note: str = "") -> None:
    """Raise :class:`MissingExtraError` unless ``modules`` of the optional extra are installed.

    The one message of a missing extra: what needs it, the extra, the modules not installed
    and the line that installs them. The modules are not imported (the caller imports them
    where it uses them).

    Parameters
    ----------
    modules : str or sequence of str
        The modules needed.
    extra : str
        The extra of compas_ccu that installs them (``"viz"``, ``"fab"``, ``"explore"`` ...).
    what : str
        What needs them: ``"'ccu fabricate'"``, ``"reading DXF files"``.
    note : str
        Appended to the message (another way out, another package to install).

    Raises
    ------
    MissingExtraError
        A module is not installed.

    Examples
    --------
    >>> require("json", "viz", what="'ccu figures'")
    >>> require(["json", "no_such_module"], "viz", what="'ccu figures'", note=" (or --no-figures)")
    Traceback (most recent call last):
    ...
    compas_ccu.errors.MissingExtraError: 'ccu figures' needs the viz extra (no_such_module not \
installed): pip install 'compas_ccu[viz]' (or --no-figures)
    """
    missing = missing_modules([modules] if isinstance(modules, str) else modules)
    if missing:
        raise MissingExtraError(
            f"{what} needs the {extra} extra ({', '.join(missing)} not installed): "
            f"pip install 'compas_ccu[{extra}]'{note}"
        )
