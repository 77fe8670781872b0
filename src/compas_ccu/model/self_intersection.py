"""The self-intersection checks of a model's deployment path: a crease overlapping itself in its
plane, and two plates (zero thickness) crossing on the way from the flat stack
(:class:`~compas_ccu.kinematics.interference.PathCertificate`). :class:`CCUModel`'s
``check_overlap``, ``certificate``, ``collision_free_alpha`` and ``check_interference`` are
these functions; :func:`geometry_key` and :func:`adopt_limits` let a model rebuilt from a design
whose geometry did not change (a new material, load or name) reuse the limits of the last one."""

from __future__ import annotations

import hashlib
import json
import math
import threading

import numpy as np

from compas_ccu.errors import SelfIntersectionError
from compas_ccu.kinematics.interference import PathCertificate, describe
from compas_ccu.kinematics.plates import stack_rows

__all__ = [
    "check_overlap",
    "path_certificate",
    "collision_free_alpha",
    "measured_collision_free_alpha",
    "check_interference",
    "geometry_key",
    "adopt_limits",
    "PathLimits",
    "NON_GEOMETRY_SECTIONS",
]

#: Design sections that do not change the placed zero-thickness geometry (the plate thickness,
#: which the thick plates' limits depend on, is keyed apart: :func:`thick_key`).
NON_GEOMETRY_SECTIONS = (
    "design",
    "plates",
    "design_code",
    "materials",
    "loads",
    "supports",
    "hinges",
    "fabrication",
)


def check_overlap(model, states, alphas) -> None:
    """Refuse placed ``states`` (at reference angles ``alphas``, degrees) of ``model`` in which
    a crease overlaps itself in its plane.

    Raises
    ------
    SelfIntersectionError
        Names the first such state, the crease and the largest alpha before any overlap.

    Examples
    --------
    The crease of ``examples/cone.toml`` overlaps itself beyond 75.5 degrees:

    >>> import numpy as np
    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> check_overlap(model, model.mechanism.deploy(np.radians([20.0, 40.0])), [20.0, 40.0]) is None
    True
    >>> over = model.mechanism.deploy(np.radians([80.0]))
    >>> check_overlap(model, over, [80.0])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.SelfIntersectionError: self-intersection at alpha = 80 deg: ... 75.5126 deg
    """
    bad = model.overlapping(states)
    if bad.any():
        k = int(np.flatnonzero(bad.any(axis=1))[0])
        ci = int(np.flatnonzero(bad[k])[0])
        what = "the leading crease" if ci == 0 else f"crease {ci - 1}"
        raise SelfIntersectionError(
            f"self-intersection at alpha = {alphas[k]:.6g} deg: {what} overlaps itself "
            f"in its plane (the plates would pass through each other); the largest "
            f"alpha before any crease overlaps is {model.overlap_alpha:.6g} deg",
            alpha=float(alphas[k]),
            crease=None if ci == 0 else ci - 1,
        )


def path_certificate(model) -> PathCertificate:
    """The interpenetration certificate of ``model``'s path from the flat stack to the limit,
    every plate pair, the hinges of every crease excluded where they meet.

    Examples
    --------
    >>> import math
    >>> from compas_ccu.model import load_model
    >>> result = path_certificate(load_model("examples/cone.toml")).result()
    >>> result.hit is None, round(math.degrees(result.clear), 4)  # clear up to the limit
    (True, 89.0625)
    """
    mechanism = model.mechanism

    def vertices_at(alphas):
        states = mechanism.deploy(alphas)
        return stack_rows(states.near, states.far)

    index = model.plates
    hinges = [(a, b, *index.crease_rows(ci)) for ci, (a, b) in enumerate(index.crease_plates)]
    return PathCertificate(
        vertices_at,
        upto=mechanism.alpha_limit,
        segments=model.segments,
        hinges=hinges,
        size=model.size,
        plates=index.count,
    )


class PathLimits(dict):
    """The path limits measured on a model (:attr:`CCUModel.limits`), each measured once even
    when two threads ask for it together (the studio's view and checks workers do)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._guard = threading.Lock()
        self._locks: dict = {}

    #: Kept objects, not values: a copy measures them again (the certificate holds a lock and
    #: its mechanism's placement).
    TRANSIENT = ("certificate",)

    def __reduce__(self):  # copied or pickled with its values, new locks
        values = {k: v for k, v in self.items() if k not in self.TRANSIENT}
        return (type(self), (values,))

    def measure(self, key, function):
        """The value under ``key``, measured by ``function()`` if it is not there yet (a
        second thread asking meanwhile waits for the first one's value)."""
        if key in self:
            return self[key]
        with self._guard:
            lock = self._locks.setdefault(key, threading.Lock())
        with lock:
            if key not in self:
                self[key] = function()
        return self[key]


def collision_free_alpha(model) -> float:
    """Largest reference alpha (degrees) of ``model`` reached from the flat stack without a
    crease overlapping itself or two plates crossing (the deployment limit if neither);
    computed once per model (and kept by :func:`adopt_limits`).

    Examples
    --------
    The plates of ``examples/cone.toml`` never cross; its crease overlaps itself first:

    >>> from compas_ccu.model import load_model
    >>> round(collision_free_alpha(load_model("examples/cone.toml")), 4)
    75.5126
    """

    def measure():
        overlap = math.radians(model.overlap_alpha)
        found = model.certificate.certify(overlap)
        return math.degrees(min(overlap, found.clear if found is not None else overlap))

    return model.limits.measure("collision_free_alpha", measure)


def measured_collision_free_alpha(model) -> float | None:
    """:func:`collision_free_alpha` of ``model`` if it has been measured (on this model or on
    one of the same geometry, :func:`adopt_limits`), else None; never measures it. For a
    caller that must not wait for the path scan (the studio draws a new model while its
    checks measure it); :attr:`CCUModel.overlap_alpha` is then measured too.

    >>> from compas_ccu.model import load_model
    >>> model = load_model("examples/cone.toml")
    >>> measured_collision_free_alpha(model) is None
    True
    >>> round(model.collision_free_alpha, 4) == round(measured_collision_free_alpha(model), 4)
    True
    """
    return model.limits.get("collision_free_alpha")


def geometry_key(model) -> str:
    """A digest of what places ``model``'s plates: every design section but
    :data:`NON_GEOMETRY_SECTIONS`, and the built crease boundaries at the design state (so a
    curve file whose content changed under the same name changes the key too)."""
    values = model.design.values
    shape = {k: v for k, v in values.items() if k not in NON_GEOMETRY_SECTIONS}
    digest = hashlib.sha1(json.dumps(shape, sort_keys=True, default=repr).encode())
    g = model.geometry
    for array in (g.design_near, g.design_far):
        digest.update(np.ascontiguousarray(array, dtype=float).tobytes())
    return digest.hexdigest()


def adopt_limits(model, previous) -> bool:
    """Let ``model`` share the path limits of ``previous`` (a model, or None) when their
    geometry is the same (:func:`geometry_key`): the overlap angle, the collision-free angle,
    the path certificate (scanned as far as either model asked) and the thick plates' first
    collisions (keyed by thickness), those measured already and those either model measures
    from now on (one dict, :attr:`CCUModel.limits`).

    Returns
    -------
    bool
        Whether the geometry was the same (and the limits are shared).
    """
    if previous is None or geometry_key(previous) != geometry_key(model):
        return False
    for name, value in list(model.limits.items()):
        previous.limits.setdefault(name, value)
    model.limits = previous.limits  # one PathLimits: what either measures, both have
    return True


def check_interference(model, alphas) -> None:
    """Refuse reference angles ``alphas`` (degrees) of ``model`` beyond the first state, on the
    path from the flat stack, in which two plates cross.

    Raises
    ------
    SelfIntersectionError
        Names the two plates, the alpha where they first meet and the largest alpha clear.

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> check_interference(load_model("examples/cone.toml"), [20.0, 40.0, 60.0]) is None
    True
    """
    alphas = np.atleast_1d(np.asarray(alphas, dtype=float))
    if not len(alphas):
        return
    found = model.certificate.certify(math.radians(float(alphas.max())))
    if found is None:
        return
    beyond = np.radians(alphas) > found.clear
    if beyond.any():
        ids = [model.plates.output_id(i) for i in range(model.plates.count)]
        alpha = float(alphas[np.flatnonzero(beyond)[0]])
        raise SelfIntersectionError(
            f"self-intersection at alpha = {alpha:.6g} deg: " + describe(found, ids),
            alpha=alpha,
            crease=None,
            plates=tuple(ids[i] for i in found.plates),
        )
