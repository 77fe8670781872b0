"""Fabricate -> import -> deploy: how far an imported design is from the model fabricated.

:func:`round_trip_error` compares the leading crease pair (:func:`import_design`),
:func:`structure_round_trip_error` the whole structure (:func:`import_structure`), and
:func:`structure_error` any mechanism with the model whose plate files a folder holds: both
deployed to the model's design angle, vertex by vertex after a best rigid alignment, plates
matched by id through ``fabrication.json``'s ``model_ids``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from compas_ccu.design import Design
from compas_ccu.errors import DesignError
from compas_ccu.fabrication.import_documents import import_design, import_structure
from compas_ccu.fabrication.import_selection import model_ids
from compas_ccu.geometry import rigid_align
from compas_ccu.kinematics.mechanism import Mechanism
from compas_ccu.model import CCUModel

__all__ = [
    "RoundTripDeviation",
    "round_trip_error",
    "structure_error",
    "structure_round_trip_error",
]


@dataclass
class RoundTripDeviation:
    """How far an imported design lands from the model whose files it was read from.

    Attributes
    ----------
    max : float
        The largest vertex distance after a best rigid alignment, m.
    max_relative : float
        ``max`` over the bounding-box diagonal of what was compared.
    plates : int
        The number of plates compared.
    crease_id : int or None
        The model's id of the imported leading crease (a crease pair's comparison).
    plate_ids : list of int or None
        The model's ids of its two plates, leading first (a crease pair's comparison).
    report : dict or None
        The import's report (:func:`import_design` / :func:`import_structure`).

    Examples
    --------
    >>> RoundTripDeviation(max=2e-12, max_relative=1e-12, plates=2).max_relative < 1e-9
    True
    """

    max: float
    max_relative: float
    plates: int
    crease_id: int | None = None
    plate_ids: list | None = None
    report: dict | None = None


def round_trip_error(model, folder, *, crease=None, as_drawn: bool = False) -> RoundTripDeviation:
    """Fabricate -> import -> deploy: the imported crease pair against the model's two plates.

    ``folder`` holds the plate files ``ccu fabricate`` wrote for ``model``. The imported design
    is deployed to the model's design angle and its two plates are compared, vertex by vertex
    (the crease records give the correspondence), with the model's plates of that crease after
    a best rigid alignment.

    Returns
    -------
    RoundTripDeviation
        ``max`` (m) and ``max_relative`` (to the diagonal of the compared plates' bounding box)
        vertex distance, ``crease_id``, ``plate_ids`` (leading, partner), ``report`` (of
        :func:`import_design`).
    """
    document, report = import_design(folder, crease=crease, as_drawn=as_drawn)
    alpha = model.alpha_design
    new = CCUModel(Design(document)).deploy(alpha)
    old = model.deploy(alpha)
    plate_id, crease_id = model_ids(folder)  # the files' ids follow the stack
    cid = crease_id(report["crease_id"])
    record = next((c for c in old.creases if c["id"] == cid), None)
    if record is None:
        raise DesignError(f"the model has no crease {cid!r} (the plate files' XDATA)")
    n = model.segments
    old_xyz = np.asarray(old.deployed)
    new_xyz = np.asarray(new.deployed)
    a_id, b_id = (plate_id(k) for k in report["plate_ids"])
    side = {pid: k for k, pid in enumerate(record["plates"])}
    rows_old, rows_new = [], []
    for k_new, pid in ((0, a_id), (1, b_id)):
        idx = np.asarray(record["vertices"][side[pid]])  # along the crease, as in the DXF
        far = np.where(idx <= n, idx + n + 1, idx - n - 1)
        plate = old_xyz[old.plate_ids.index(pid)]
        rows_old += [plate[idx], plate[far]]
        mine = new_xyz[new.plate_ids.index(k_new)]
        rows_new += [mine[: n + 1], mine[n + 1 :]]
    a = np.concatenate(rows_new)
    b = np.concatenate(rows_old)
    moved = rigid_align(a, b)
    distance = float(np.linalg.norm(moved - b, axis=1).max())
    size = float(np.linalg.norm(np.ptp(b, axis=0)))
    return RoundTripDeviation(
        max=distance,
        max_relative=distance / size,
        plates=2,
        crease_id=cid,
        plate_ids=[a_id, b_id],
        report=report,
    )


def structure_round_trip_error(
    model, folder, *, crease=None, as_drawn: bool = False
) -> RoundTripDeviation:
    """Fabricate -> import -> deploy for the whole structure (:func:`import_structure`).

    Both mechanisms are deployed to the model's design angle; every vertex of every plate is
    compared with the model's (plates matched by id) after a best rigid alignment.

    Returns
    -------
    RoundTripDeviation
        ``max`` (m), ``max_relative`` (to the structure's bounding-box diagonal), ``plates``,
        ``report`` (of :func:`import_structure`).
    """
    imported = import_structure(folder, crease=crease, as_drawn=as_drawn)
    out = structure_error(model, folder, imported.mechanism, imported.plate_ids)
    out.report = imported.report
    return out


def structure_error(model, folder, mechanism: Mechanism, plate_ids) -> RoundTripDeviation:
    """An imported mechanism against the model whose plate files ``folder`` holds.

    Both are deployed to the model's design angle; every vertex of every plate is compared
    with the model's after a best rigid alignment, plates matched by id: ``plate_ids`` (of
    the mechanism's plates) are the plate files' ids, mapped to the model's by
    ``fabrication.json``. The model of a design file ``ccu import`` wrote compares with
    ``loaded.mechanism, loaded.geometry.plate_ids``.

    Returns
    -------
    RoundTripDeviation
        ``max`` (m), ``max_relative`` (to the structure's bounding-box diagonal), ``plates``.
    """
    alpha = math.radians(model.alpha_design)
    new = mechanism.deploy(alpha)
    old = model.mechanism.deploy(alpha)
    old_ids = list(model.geometry.plate_ids)
    plate_id, _ = model_ids(folder)
    a, b = [], []
    for i, pid in enumerate(plate_ids):
        j = old_ids.index(plate_id(pid))
        a += [new.near[0, i], new.far[0, i]]
        b += [old.near[0, j], old.far[0, j]]
    a, b = np.concatenate(a), np.concatenate(b)
    moved = rigid_align(a, b)
    distance = float(np.linalg.norm(moved - b, axis=1).max())
    size = float(np.linalg.norm(np.ptp(b, axis=0)))
    return RoundTripDeviation(max=distance, max_relative=distance / size, plates=len(plate_ids))
