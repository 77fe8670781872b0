"""A folder read for ``ccu import``: its ``fabrication.json``, its plates, their crease pairs
and the leading pair chosen.

:func:`select_pair` reads every plate file of a folder
(:func:`compas_ccu.fabrication.plate_drawings.read_plate_folder`), pairs their creases
(:func:`compas_ccu.fabrication.crease_pairs.pair_creases`) and chooses the pair that leads: the
one asked for, the folder's only one, the design's (``fabrication.json``'s ``leading_crease``) or
that of the shallowest attachment tree; its stack-upper plate first. :func:`read_manifest` is
the folder's ``fabrication.json`` (or its parent's), :func:`model_ids` its map from the files'
ids to the model's.
"""

from __future__ import annotations

import json
from pathlib import Path

from compas_ccu.errors import DesignError
from compas_ccu.fabrication.crease_pairs import (
    CreasePair,
    crease_pattern,
    pair_creases,
    stack_upper_leads,
)
from compas_ccu.fabrication.import_tree import structure_tree, tree_depth
from compas_ccu.fabrication.plate_drawings import read_plate_folder

__all__ = ["model_ids", "read_manifest", "select_pair"]


def read_manifest(folder) -> dict:
    """The ``fabrication.json`` of ``folder`` or of its parent (``ccu fabricate``'s ``plates``
    folder); ``{}`` if neither has one (hand-drawn files)."""
    folder = Path(folder)
    for place in (folder / "fabrication.json", folder.parent / "fabrication.json"):
        if place.is_file():
            return json.loads(place.read_text(encoding="utf-8"))
    return {}


def select_pair(folder: Path, *, crease, units, whole: bool = False):
    """Read a folder; the crease pair chosen (its stack-upper plate first) and every pattern.

    Parameters
    ----------
    folder : str or Path
    crease : int or str or None, keyword-only
        A crease id, a plate file name or a pair's key; None: the folder's only crease.
    units : str or None, keyword-only
        Units of the DXF files, overriding ``$INSUNITS``.
    whole : bool, keyword-only
        Without ``crease``, the design's leading crease (``fabrication.json``) or else the
        crease of the shallowest attachment tree leads (a mechanism grows from the middle of
        its layout) instead of a refusal.

    Returns
    -------
    manifest : dict
        :func:`read_manifest`.
    plates : list of PlateDrawing
    pairs : list of CreasePair
    pair : CreasePair
        The leading pair, its stack-upper plate first.
    patterns : dict
        ``{pair key: (pattern a, pattern b)}``, each
        :func:`compas_ccu.fabrication.crease_pairs.crease_pattern`.

    Raises
    ------
    DesignError
        Several creases and no choice, or no crease ``crease``.
    """
    folder = Path(folder)
    manifest = read_manifest(folder)
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


def model_ids(folder) -> tuple:
    """Workshop id -> model id of the plates and creases (``fabrication.json``'s
    ``model_ids``; the identity without it)."""
    ids = read_manifest(folder).get("model_ids") or {}
    plates, creases = ids.get("plates"), ids.get("creases")
    return (
        (lambda k: k) if plates is None else (lambda k, m=plates: m[int(k)]),
        (lambda k: k) if creases is None else (lambda k, m=creases: m[int(k)]),
    )
