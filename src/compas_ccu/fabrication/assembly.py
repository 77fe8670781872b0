"""The assembly steps: one list for ``fabrication.json`` and the assembly sheet.

:func:`assembly_steps` orders the assembly in the flat-folded stack's order: first every split
plate is joined on a flat table (per cut, the lower splice plate laid down, the parts laid UP
face up on it with their cut edges together, the upper splice plate glued and screwed over the
cut), then the plates are laid bottom to top, UP face up, and as each is laid the hinge strips
joining it to the plates below are glued. Every step names its parts (the bill of materials'
item names: ``P3``, ``P3.1``, ``S3.1D``, ``hinge C2``), the face and where:

* ``action``: ``"splice"`` (a splice plate), ``"join"`` (the parts of a split plate), ``"lay"``
  (a plate on the stack) or ``"glue"`` (a hinge strip);
* ``parts``: the item names the step handles, ``plate``: the plate id (None for a hinge);
* ``face``: ``"lower"`` / ``"upper"`` (a splice plate), ``"UP"`` (the plate face that is up),
  the hinge's faces (``"intrados"`` / ``"extrados"``, None if unknown);
* ``where``: per step kind, ``ruling`` and ``along`` (the cut's ruling and its distance along
  the plate's near edge from ruling 0, m), ``stack`` (position, 1 = bottom) and ``on`` (the
  plate below), or ``crease`` and ``plates``;
* ``text``: the step in words, ``step``: its number from 1.
"""

from __future__ import annotations

import numpy as np

__all__ = ["assembly_steps", "step_items"]


def _along(flat: np.ndarray, n: int, j: int) -> float:
    """Arc length of the near edge from ruling 0 to ruling ``j``, m."""
    return float(np.linalg.norm(np.diff(flat[: j + 1], axis=0), axis=1).sum())


def _splice_steps(data, i: int, cuts: list) -> list:
    """The steps that join split plate ``i`` (array index) on the table."""
    pid = int(data.plate_ids[i])
    flat = np.asarray(data.flat[i], dtype=float)
    n = data.segments
    where = [{"ruling": int(j), "along": _along(flat, n, int(j))} for j in cuts]
    parts = [f"P{pid}.{q + 1}" for q in range(len(cuts) + 1)]
    lower = [f"S{pid}.{q + 1}D" for q in range(len(cuts))]
    steps = []
    for q, w in enumerate(where):
        steps.append(
            {
                "action": "splice",
                "parts": [lower[q]],
                "plate": pid,
                "face": "lower",
                "where": w,
                "text": f"Lay splice {lower[q]} on the table under the cut of P{pid} at ruling "
                f"{w['ruling']} ({w['along']:.3f} m along the near edge), centred on the ruling",
            }
        )
    cut_text = ", ".join(f"ruling {w['ruling']}" for w in where)
    steps.append(
        {
            "action": "join",
            "parts": parts,
            "plate": pid,
            "face": "UP",
            "where": {"rulings": [w["ruling"] for w in where]},
            "text": f"Lay {' + '.join(parts)} UP face up on {', '.join(lower)}, cut edges "
            f"together at {cut_text}; glue and screw",
        }
    )
    for q, w in enumerate(where):
        upper = f"S{pid}.{q + 1}U"
        steps.append(
            {
                "action": "splice",
                "parts": [upper],
                "plate": pid,
                "face": "upper",
                "where": w,
                "text": f"Glue and screw splice {upper} over the cut of P{pid} at ruling "
                f"{w['ruling']} (upper face)",
            }
        )
    return steps


def _glue_step(data, crease: dict, pairing) -> dict:
    cid = int(crease["id"])
    a, b = (int(x) for x in crease["plates"])
    faces = pairing[cid] if pairing is not None and cid < len(pairing) else None
    lo, hi = sorted((a, b), key=lambda x: data.stack_position[data.index(x)])
    return {
        "action": "glue",
        "parts": [f"hinge C{cid}"],
        "plate": None,
        "face": faces,
        "where": {"crease": cid, "plates": [lo, hi]},
        # the old keys, kept for readers of fabrication.json
        "crease": cid,
        "plates": [lo, hi],
        "faces": faces,
        "text": f"Glue hinge C{cid} joining P{lo} and P{hi} along their crease"
        + (f" ({faces} faces)" if faces else ""),
    }


def assembly_steps(data, splits: dict, pairing=None) -> list:
    """The assembly in stack order (module docstring).

    Parameters
    ----------
    data : FabricationData
    splits : dict
        Plate id -> the rulings its cuts follow (empty or missing: the plate is whole).
    pairing : list of str, optional
        Per crease id: the faces its hinge joins; default ``data.metadata["pairing"]``.

    Returns
    -------
    list of dict

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> flat = np.array([[0.0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]])
    >>> data = SimpleNamespace(plate_ids=[0, 1], stack_position=[0, 1], flat=[flat, flat],
    ...     segments=2, creases=[{"id": 0, "plates": [0, 1]}], metadata={},
    ...     index=[0, 1].index)
    >>> texts = [s["text"] for s in assembly_steps(data, {0: [1]}, ["intrados"])]
    >>> texts[:3]  # doctest: +NORMALIZE_WHITESPACE
    ['Lay splice S0.1D on the table under the cut of P0 at ruling 1 (1.000 m along the near
      edge), centred on the ruling', 'Lay P0.1 + P0.2 UP face up on S0.1D, cut edges together
      at ruling 1; glue and screw', 'Glue and screw splice S0.1U over the cut of P0 at ruling 1
      (upper face)']
    >>> texts[3:]  # doctest: +NORMALIZE_WHITESPACE
    ['Lay P0 (P0.1 + P0.2) UP face up on the table (stack 1 of 2)', 'Lay P1 UP face up on P0
      (stack 2 of 2)', 'Glue hinge C0 joining P0 and P1 along their crease (intrados faces)']
    """
    if pairing is None:
        pairing = data.metadata.get("pairing")
    order = sorted(range(len(data.plate_ids)), key=lambda i: int(data.stack_position[i]))
    steps = []
    for i in order:
        cuts = splits.get(int(data.plate_ids[i]), [])
        if cuts:
            steps += _splice_steps(data, i, cuts)
    laid = set()
    creases = sorted(data.creases, key=lambda c: int(c["id"]))
    for k, i in enumerate(order):
        pid = int(data.plate_ids[i])
        below = None if k == 0 else int(data.plate_ids[order[k - 1]])
        cuts = splits.get(pid, [])
        joined = (
            "" if not cuts else f" ({' + '.join(f'P{pid}.{q + 1}' for q in range(len(cuts) + 1))})"
        )
        steps.append(
            {
                "action": "lay",
                "parts": [f"P{pid}"] if not cuts else [],
                "plate": pid,
                "face": "UP",
                "where": {"stack": k + 1, "on": below},
                "stack": k + 1,
                "text": f"Lay P{pid}{joined} UP face up "
                + ("on the table" if below is None else f"on P{below}")
                + f" (stack {k + 1} of {len(order)})",
            }
        )
        for c in creases:
            a, b = (int(x) for x in c["plates"])
            if pid in (a, b) and ({a, b} - {pid}) <= laid:
                steps.append(_glue_step(data, c, pairing))
        laid.add(pid)
    for n, s in enumerate(steps):
        s["step"] = n + 1
    return steps


def step_items(steps) -> list:
    """Every item name the steps handle, in order of first use (the BOM's item names)."""
    seen = {}
    for s in steps:
        for name in s["parts"]:
            seen.setdefault(name, None)
    return list(seen)
