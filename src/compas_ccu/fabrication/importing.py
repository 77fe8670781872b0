"""The reverse of fabrication: plate DXFs back to a design that deploys (``ccu import``).

A folder of plate cut files, as :func:`compas_ccu.fabrication.dxf.write_plate_dxf` writes them
or drawn by hand to the same convention (docs/import.md), is read back:

``CUT``
    the closed outline of the plate (LWPOLYLINE or POLYLINE, bulges allowed);
``CREASE``
    every crease of the plate, on the outline: LWPOLYLINE, POLYLINE, ARC, SPLINE or a chain of
    LINEs. XDATA ``COMPAS_CCU`` (crease id, other plate id) pairs the plates; without it the
    plates are paired by their creases' lengths;
``RULING_SCORE``
    every interior ruling as a LINE from the crease to the other side of the plate (or on the
    reference layer ``RULING``, where ``ccu fabricate`` puts them when they are not scored).
    The two end rulings are the outline's edges at the crease's ends.

The crease vertices are the crease's end points and the rulings' feet on it, in order along it;
the ruling ends are the rulings' far end points. :func:`import_structure` joins every plate of
the folder into one mechanism that deploys the whole structure, and writes it as a design
document (``ccu import``): the leading plate as a ``state = "flat"`` design with ``explicit``
rulings, every other plate as a ``[[layout.patterns]]`` table (its cut pattern, its parent and
the parent's boundary it hangs from; :mod:`compas_ccu.design.patterns`).
:func:`import_design` turns one crease and its two plates into a single-crease design, the one
:func:`compas_ccu.model.flat_design` writes (``ccu import --leading-pair-only``); there the
partner must be the leading plate's mirror image (same crease, same rulings).

Inconsistent drawings are refused before anything is written, the error naming the plate file
and the entity (DXF handle): a missing layer, a ruling that does not start on the crease or
crosses another one, partner creases of different length, a partner that is not the mirror
image of the leading plate.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from compas_ccu.design import Design
from compas_ccu.design.writer import design_toml
from compas_ccu.errors import DesignError
from compas_ccu.fabrication.crease_pairs import (
    CreasePair,
    check_partner,
    crease_pattern,
    pair_creases,
    stack_upper_leads,
)
from compas_ccu.fabrication.import_thickness import (
    UNDO_TOLERANCE,
    drawn_thickness,
    thickness_shifts,
    zero_thickness_rows,
)
from compas_ccu.fabrication.import_tree import (
    ImportedStructure,
    assemble_structure,
    structure_document,
    structure_tree,
    tree_depth,
)
from compas_ccu.fabrication.plate_drawings import (
    CreaseDrawing,
    PlateDrawing,
    read_plate_drawing,
    read_plate_folder,
)
from compas_ccu.geometry import rigid_align
from compas_ccu.kinematics.mechanism import Mechanism
from compas_ccu.model import CCUModel

__all__ = [
    "import_design",
    "round_trip_error",
    "import_structure",
    "structure_round_trip_error",
    "structure_error",
    "design_toml",
    "PlateDrawing",
    "CreaseDrawing",
    "CreasePair",
    "read_plate_drawing",
    "read_plate_folder",
    "crease_pattern",
    "pair_creases",
    "ImportedStructure",
    "structure_document",
    "thickness_shifts",
    "UNDO_TOLERANCE",
]


def _select(folder: Path, *, crease, units, whole: bool = False):
    """Read a folder; the crease pair chosen (its stack-upper plate first) and every pattern.

    ``whole``: without ``crease``, the crease of the shallowest attachment tree leads (a
    mechanism grows from the middle of its layout) instead of a refusal."""
    folder = Path(folder)
    manifest = {}
    for place in (folder / "fabrication.json", folder.parent / "fabrication.json"):
        if place.is_file():
            manifest = json.loads(place.read_text(encoding="utf-8"))
            break
    plates = read_plate_folder(folder, units=units)
    pairs = pair_creases(plates)
    patterns = {}
    for pair in pairs:
        patterns[pair.key] = (
            crease_pattern(pair.a, pair.crease_a),
            crease_pattern(pair.b, pair.crease_b),
        )
    listing = "; ".join(f"{p.key}: {p.a.label} - {p.b.label}" for p in pairs)
    if whole and crease is None and len(pairs) > 1:
        lead = manifest.get("leading_crease")  # ccu fabricate records the design's
        if lead is not None and any(p.crease_a.crease_id == lead for p in pairs):
            crease = lead
        else:
            return manifest, plates, pairs, _middle(pairs, patterns, manifest), patterns
    if crease is None and len(pairs) != 1:
        raise DesignError(
            f"{folder}: {len(pairs)} creases ({listing}); a design file holds one crease pair: "
            "choose one (--crease ID or the leading plate's file name; docs/import.md)"
        )
    if crease is None:
        pair = pairs[0]
    else:
        chosen = [
            p
            for p in pairs
            if str(crease) in (str(p.crease_a.crease_id), p.a.label, p.b.label, p.key)
        ]
        if not chosen:
            raise DesignError(f"{folder}: no crease {crease!r}; the creases: {listing}")
        pair = chosen[0]
    return manifest, plates, pairs, stack_upper_leads(pair, patterns, manifest), patterns


def _middle(pairs: list, patterns: dict, manifest: dict) -> CreasePair:
    """The crease pair whose attachment tree is the shallowest (the first of equals), its
    stack-upper plate first (``patterns`` reordered with it)."""
    best = None
    for pair in pairs:
        trial = dict(patterns)
        upper = stack_upper_leads(pair, trial, manifest)
        depth = tree_depth(structure_tree(upper, pairs, *trial[upper.key])[0])
        if best is None or depth < best[0]:
            best = (depth, pair)
    return stack_upper_leads(best[1], patterns, manifest)


def import_design(
    folder,
    *,
    crease=None,
    alpha: float | None = None,
    reference: float = 0.5,
    name: str | None = None,
    units: str | None = None,
    as_drawn: bool = False,
):
    """A flat design (TOML document) from a folder of plate DXFs.

    ``ccu fabricate``'s cut patterns carry the thickness correction of the axis-shift hinges
    (paper §5.3; :meth:`compas_ccu.thickness.ThickModel.cut_patterns`): every crease vertex is
    moved along its ruling into the plate so that the thick plates meet along planar hinges.
    When the folder has a ``fabrication.json`` with the plate thickness, the correction is
    undone: the design is the zero-thickness pattern whose corrected pattern is the one read
    (the whole folder's structure is needed for it: every crease's correction depends on the
    plates before it). Hand-drawn folders (no ``fabrication.json``) and ``as_drawn`` are
    imported as drawn.

    Parameters
    ----------
    folder : str or Path
        ``ccu fabricate``'s output folder (or its ``plates`` folder), or hand-drawn files.
    crease : int or str, optional
        Which crease to import when the folder holds several: a crease id (XDATA), or a plate
        file name (its first crease). Of its two plates the one higher in the flat-folded
        stack (``fabrication.json``) leads; without the stack order, the first file.
    alpha : float, optional
        Design reflection angle, degrees; default: ``fabrication.json``'s (required without it).
    reference : float
        Arc-length fraction of the reference vertex (default 0.5, the designs' default).
    name : str, optional
        Design name (default: ``fabrication.json``'s design name, else the folder's name).
    units : str, optional
        Units of the DXF files, overriding ``$INSUNITS`` (unitless files: mm).
    as_drawn : bool
        Take the patterns as drawn: do not undo ``fabrication.json``'s thickness correction.

    Returns
    -------
    document : dict
        The design (``crease.state = "flat"``, ``polyline`` crease, ``explicit`` rulings).
    report : dict
        ``plates`` (files), ``crease``, ``segments``, ``partner_error`` (largest relative
        difference between the partner and the leading plate's mirror image), ``pairs``,
        ``thickness_correction`` (None if taken as drawn; else ``thickness``, ``iterations``,
        ``largest`` shift undone and the last ``change``, m).

    Raises
    ------
    DesignError
        Inconsistent drawings (file and entity named), several creases and no choice, no alpha,
        a thickness correction that cannot be undone (no convergence: the folder named).

    Examples
    --------
    >>> import tempfile
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.fabrication.fabricate import fabricate
    >>> out = tempfile.mkdtemp()
    >>> _ = fabricate(load_model("examples/cone.toml"), out)
    >>> document, report = import_design(out)
    >>> document["crease"]["state"], document["rulings"]["type"], report["segments"]
    ('flat', 'explicit', 48)
    """
    folder = Path(folder)
    manifest, plates, pairs, pair, patterns = _select(folder, crease=crease, units=units)
    a_pattern, b_pattern = patterns[pair.key]
    if alpha is None:
        alpha = manifest.get("alpha")
    if alpha is None:
        check_partner(pair, a_pattern, b_pattern)
        raise DesignError(
            f"{folder}: no fabrication.json with the design angle: give the design reflection "
            "angle (--alpha DEG)"
        )
    info = None
    if drawn_thickness(folder, manifest, as_drawn) is not None:
        members, _, undone, info = zero_thickness_rows(
            folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
            as_drawn=as_drawn,
        )  # fmt: skip
        near_b, far_b = undone[1]
        if members[1].flipped:
            near_b, far_b = near_b[::-1], far_b[::-1]
        a_pattern = (*undone[0], a_pattern[2])
        b_pattern = (near_b, far_b, b_pattern[2])
    partner_error, _ = check_partner(pair, a_pattern, b_pattern)
    near, far, _ = a_pattern
    n = len(near) - 1
    document = {
        "design": {
            "name": name or manifest.get("design") or folder.name,
            "description": f"imported from the plate files of {folder.name} ({pair.key}: "
            f"{pair.a.label}, partner {pair.b.label})",
        },
        "crease": {
            "profile": "polyline",
            "points": near.tolist(),
            "segments": n,
            "reference": float(reference),
            "state": "flat",
        },
        "rulings": {"type": "explicit", "points": far.tolist()},
        "deployment": {"alpha": float(alpha)},
        "layout": {"type": "single"},
    }
    plates_section = {k: manifest[k] for k in ("thickness", "material") if k in manifest}
    if plates_section:
        document["plates"] = plates_section
    report = {
        "plates": [p.label for p in plates],
        "crease": pair.key,
        "leading": pair.a.label,
        "partner": pair.b.label,
        "segments": n,
        "partner_error": partner_error,
        "pairs": [p.key for p in pairs],
        "crease_id": pair.crease_a.crease_id,
        "plate_ids": [pair.a.plate_id, pair.b.plate_id],
        "thickness_correction": info,
    }
    return document, report


def _model_ids(folder) -> tuple:
    """Workshop id -> model id of the plates and creases (``fabrication.json``'s
    ``model_ids``; the identity without it)."""
    folder = Path(folder)
    for place in (folder / "fabrication.json", folder.parent / "fabrication.json"):
        if place.is_file():
            ids = json.loads(place.read_text(encoding="utf-8")).get("model_ids") or {}
            plates, creases = ids.get("plates"), ids.get("creases")
            return (
                (lambda k: k) if plates is None else (lambda k, m=plates: m[int(k)]),
                (lambda k: k) if creases is None else (lambda k, m=creases: m[int(k)]),
            )
    return (lambda k: k), (lambda k: k)


def round_trip_error(model, folder, *, crease=None, as_drawn: bool = False) -> dict:
    """Fabricate -> import -> deploy: the imported crease pair against the model's two plates.

    ``folder`` holds the plate files ``ccu fabricate`` wrote for ``model``. The imported design
    is deployed to the model's design angle and its two plates are compared, vertex by vertex
    (the crease records give the correspondence), with the model's plates of that crease after
    a best rigid alignment.

    Returns
    -------
    dict
        ``max`` (m) and ``max_relative`` (to the diagonal of the compared plates' bounding box)
        vertex distance, ``crease_id``, ``plate_ids`` (leading, partner), ``report`` (of
        :func:`import_design`).
    """
    document, report = import_design(folder, crease=crease, as_drawn=as_drawn)
    alpha = model.alpha_design
    new = CCUModel(Design(document)).deploy(alpha)
    old = model.deploy(alpha)
    plate_id, crease_id = _model_ids(folder)  # the files' ids follow the stack
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
    return {
        "max": distance,
        "max_relative": distance / size,
        "crease_id": cid,
        "plate_ids": [a_id, b_id],
        "report": report,
    }


def import_structure(
    folder,
    *,
    crease=None,
    alpha=None,
    reference=0.5,
    name: str | None = None,
    units=None,
    as_drawn: bool = False,
):
    """The whole structure of a folder of plate files: one mechanism and its design document.

    The leading crease pair is imported as by :func:`import_design` (its design fixes the
    leading strip, the design angle and the reference vertex); every other plate is attached
    to the plate it shares a crease with, as the mechanism attaches plates (the mirror image of
    the parent's rulings across the crease's plane, with the plate's own ruling lengths). The
    document (:func:`structure_document`, ``layout.type = "patterns"``) holds every plate's
    cut pattern; ``ccu import`` writes it.

    With ``fabrication.json``'s thickness (``ccu fabricate``'s folders), the thickness
    correction of the cut patterns is undone first (:func:`import_design`).

    Parameters
    ----------
    folder, alpha, reference, name, units, as_drawn
        As :func:`import_design`.
    crease : int or str, optional
        The leading crease. Default: with one crease, it; with several, ``fabrication.json``'s
        ``leading_crease`` (the design's, as ``ccu fabricate`` records it), else the crease
        with which the thickness correction of the patterns was made (found by undoing it),
        else (hand-drawn, ``as_drawn``) the crease of the shallowest attachment tree (the
        middle of the layout; the design angle is then that crease's).

    Returns
    -------
    ImportedStructure

    Raises
    ------
    DesignError
        As :func:`import_design` (except that the partner need not be the leading plate's
        mirror image), and a plate with more than two creases.

    Examples
    --------
    >>> import tempfile
    >>> from compas_ccu.model import load_model
    >>> from compas_ccu.fabrication.fabricate import fabricate
    >>> out = tempfile.mkdtemp()
    >>> _ = fabricate(load_model("examples/cone.toml"), out)
    >>> structure = import_structure(out)
    >>> undone = structure.report["thickness_correction"]
    >>> structure.plate_ids, undone["thickness"], undone["iterations"], undone["leading"]
    ([1, 0], 0.005, 1, 'crease 0')
    >>> layout = structure.document["layout"]
    >>> layout["type"], layout["leading"], [(t["parent"], t["boundary"], t["id"])
    ...                                     for t in layout["patterns"]]
    ('patterns', 1, [(0, 'near', 0)])
    """
    folder = Path(folder)
    manifest, plates, pairs, pair, patterns = _select(
        folder, crease=crease, units=units, whole=True
    )
    read = dict(patterns)  # as read: the undoing may reorder pairs' patterns
    if alpha is None:
        alpha = manifest.get("alpha")
    if alpha is None:
        raise DesignError(
            f"{folder}: no fabrication.json with the design angle: give the design reflection "
            "angle (alpha, --alpha DEG)"
        )
    members, links, undone, info = zero_thickness_rows(
        folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
        as_drawn=as_drawn,
    )  # fmt: skip
    if crease is None and info is not None and info["leading"] != pair.key:
        # the correction was made with another crease leading: the design's leading crease
        patterns = dict(read)
        found = next(p for p in pairs if p.key == info["leading"])
        pair = stack_upper_leads(found, patterns, manifest)
        members, links, undone, info = zero_thickness_rows(
            folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
            as_drawn=as_drawn,
        )  # fmt: skip
    name = name or manifest.get("design") or folder.name
    _, mechanism = assemble_structure(
        members, links, undone, alpha=alpha, reference=reference, name=name
    )
    ids = [m.plate.plate_id if m.plate.plate_id is not None else m.plate.label for m in members]
    document = structure_document(members, undone, ids, alpha=alpha, reference=reference, name=name)
    document["design"]["description"] = (
        f"imported from the plate files of {folder.name}: {len(members)} plates, leading "
        f"{pair.key} ({pair.a.label}, partner {pair.b.label})"
    )
    plates_section = {k: manifest[k] for k in ("thickness", "material") if k in manifest}
    if plates_section:
        document["plates"] = plates_section
    report = {
        "crease": pair.key,
        "leading": pair.a.label,
        "partner": pair.b.label,
        "attached": [m.plate.label for m in members],
        "plates": [p.label for p in plates],
        "pairs": [p.key for p in pairs],
        "segments": len(members[0].near) - 1,
        "ids_written": "leading" in document["layout"],
        "thickness_correction": info,
    }
    return ImportedStructure(mechanism, ids, Design(document), report, document)


def structure_round_trip_error(model, folder, *, crease=None, as_drawn: bool = False) -> dict:
    """Fabricate -> import -> deploy for the whole structure (:func:`import_structure`).

    Both mechanisms are deployed to the model's design angle; every vertex of every plate is
    compared with the model's (plates matched by id) after a best rigid alignment.

    Returns
    -------
    dict
        ``max`` (m), ``max_relative`` (to the structure's bounding-box diagonal), ``plates``.
    """
    imported = import_structure(folder, crease=crease, as_drawn=as_drawn)
    out = structure_error(model, folder, imported.mechanism, imported.plate_ids)
    out["report"] = imported.report
    return out


def structure_error(model, folder, mechanism: Mechanism, plate_ids) -> dict:
    """An imported mechanism against the model whose plate files ``folder`` holds.

    Both are deployed to the model's design angle; every vertex of every plate is compared
    with the model's after a best rigid alignment, plates matched by id: ``plate_ids`` (of
    the mechanism's plates) are the plate files' ids, mapped to the model's by
    ``fabrication.json``. The model of a design file ``ccu import`` wrote compares with
    ``loaded.mechanism, loaded.geometry.plate_ids``.

    Returns
    -------
    dict
        ``max`` (m), ``max_relative`` (to the structure's bounding-box diagonal), ``plates``.
    """
    alpha = math.radians(model.alpha_design)
    new = mechanism.deploy(alpha)
    old = model.mechanism.deploy(alpha)
    old_ids = list(model.geometry.plate_ids)
    plate_id, _ = _model_ids(folder)
    a, b = [], []
    for i, pid in enumerate(plate_ids):
        j = old_ids.index(plate_id(pid))
        a += [new.near[0, i], new.far[0, i]]
        b += [old.near[0, j], old.far[0, j]]
    a, b = np.concatenate(a), np.concatenate(b)
    moved = rigid_align(a, b)
    distance = float(np.linalg.norm(moved - b, axis=1).max())
    size = float(np.linalg.norm(np.ptp(b, axis=0)))
    return {"max": distance, "max_relative": distance / size, "plates": len(plate_ids)}
