"""The import itself: a folder of plate files to a design document (``ccu import``).

:func:`import_design` turns the leading crease pair into a single-crease flat design (its
partner must be the leading plate's mirror image); :func:`import_structure` joins every plate of
the folder into one mechanism and its design document (``layout.type = "patterns"``). Both undo
the thickness correction of ``ccu fabricate``'s cut patterns when the folder's
``fabrication.json`` gives the thickness. The drawing convention and every public name of the
import: :mod:`compas_ccu.fabrication.importing`.
"""

from __future__ import annotations

from pathlib import Path

from compas_ccu.design import Design
from compas_ccu.errors import DesignError
from compas_ccu.fabrication.crease_pairs import check_partner, stack_upper_leads
from compas_ccu.fabrication.import_selection import select_pair
from compas_ccu.fabrication.import_thickness import drawn_thickness, zero_thickness_rows
from compas_ccu.fabrication.import_tree import (
    ImportedStructure,
    assemble_structure,
    structure_document,
)

__all__ = ["import_design", "import_structure"]


def _undone_pair(folder, manifest, pairs, pair, patterns, *, alpha, reference, as_drawn):
    """The leading pair's two patterns with the thickness correction undone, and its report
    (:func:`compas_ccu.fabrication.import_thickness.zero_thickness_rows`)."""
    a_pattern, b_pattern = patterns[pair.key]
    members, _, undone, info = zero_thickness_rows(
        folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
        as_drawn=as_drawn,
    )  # fmt: skip
    near_b, far_b = undone[1]
    if members[1].flipped:
        near_b, far_b = near_b[::-1], far_b[::-1]
    return (*undone[0], a_pattern[2]), (near_b, far_b, b_pattern[2]), info


def _add_plates(document: dict, manifest: dict) -> None:
    """``[plates]`` thickness and material of ``fabrication.json``, if it has them."""
    plates_section = {k: manifest[k] for k in ("thickness", "material") if k in manifest}
    if plates_section:
        document["plates"] = plates_section


def _pair_document(folder, manifest, pair, near, far, *, name, alpha, reference) -> dict:
    """The single-crease flat design of the leading pair: crease ``near``, ruling ends ``far``."""
    document = {
        "design": {
            "name": name or manifest.get("design") or folder.name,
            "description": f"imported from the plate files of {folder.name} ({pair.key}: "
            f"{pair.a.label}, partner {pair.b.label})",
        },
        "crease": {
            "profile": "polyline",
            "points": near.tolist(),
            "segments": len(near) - 1,
            "reference": float(reference),
            "state": "flat",
        },
        "rulings": {"type": "explicit", "points": far.tolist()},
        "deployment": {"alpha": float(alpha)},
        "layout": {"type": "single"},
    }
    _add_plates(document, manifest)
    return document


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
    manifest, plates, pairs, pair, patterns = select_pair(folder, crease=crease, units=units)
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
        a_pattern, b_pattern, info = _undone_pair(
            folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
            as_drawn=as_drawn,
        )  # fmt: skip
    partner_error, _ = check_partner(pair, a_pattern, b_pattern)
    near, far, _ = a_pattern
    n = len(near) - 1
    document = _pair_document(
        folder, manifest, pair, near, far, name=name, alpha=alpha, reference=reference
    )
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


def _undone_structure(
    folder, manifest, pairs, pair, patterns, read, *, alpha, reference, as_drawn, lead
):
    """Every plate's rows with the thickness correction undone
    (:func:`compas_ccu.fabrication.import_thickness.zero_thickness_rows`) and the leading pair.

    With ``lead`` (no crease asked for), a correction made with another crease leading is
    undone again with that crease, the design's, leading (``patterns`` as ``read``). Returns
    ``(pair, (members, links, undone, info))``.
    """
    rows = zero_thickness_rows(
        folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
        as_drawn=as_drawn,
    )  # fmt: skip
    info = rows[3]
    if lead and info is not None and info["leading"] != pair.key:
        # the correction was made with another crease leading: the design's leading crease
        patterns = dict(read)
        found = next(p for p in pairs if p.key == info["leading"])
        pair = stack_upper_leads(found, patterns, manifest)
        rows = zero_thickness_rows(
            folder, manifest, pairs, pair, patterns, alpha=alpha, reference=reference,
            as_drawn=as_drawn,
        )  # fmt: skip
    return pair, rows


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
    manifest, plates, pairs, pair, patterns = select_pair(
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
    pair, (members, links, undone, info) = _undone_structure(
        folder, manifest, pairs, pair, patterns, read, alpha=alpha, reference=reference,
        as_drawn=as_drawn, lead=crease is None,
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
    _add_plates(document, manifest)
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
