"""The assembly sheet's steps in words: ``fabrication.json``'s assembly steps as numbered lines.

:func:`assembly_text` groups the steps (:func:`_step_groups`: a split plate's joining steps;
a plate laid with the hinges glued to it) and writes one line per group (:func:`_group_text`).
"""

from __future__ import annotations

import textwrap

__all__ = ["assembly_text"]


def _group_text(group: list, total: int) -> str:
    """One line of the sheet for consecutive steps of one plate (:func:`_step_groups`)."""
    first, last = group[0]["step"], group[-1]["step"]
    head = f"{first}." if first == last else f"{first}-{last}."
    words = []
    for s in group:
        name = ", ".join(s["parts"])
        if s["action"] == "splice":
            words.append(f"{name} {'under' if s['face'] == 'lower' else 'over'}")
        elif s["action"] == "join":
            cuts = ", ".join(str(j) for j in s["where"]["rulings"])
            words.append(f"{' + '.join(s['parts'])} UP face up, cut edges at ruling {cuts}")
        elif s["action"] == "lay":
            on = s["where"]["on"]
            words.append(
                f"lay P{s['plate']} UP face up "
                + ("on the table" if on is None else f"on P{on}")
                + f" (stack {s['where']['stack']} of {total})"
            )
        else:
            lo, hi = s["where"]["plates"]
            faces = f" {s['face'][:3]}" if s["face"] else ""
            words.append(f"glue {name} P{lo}/P{hi}{faces}")
    if group[0]["action"] in ("splice", "join"):
        return f"{head} P{group[0]['plate']} on the table: " + ", ".join(words)
    return f"{head} " + "; ".join(words)


def _step_groups(steps) -> list:
    """The steps grouped: a split plate's joining steps, and a plate laid with its hinges."""
    groups = []
    for s in steps:
        joining = s["action"] in ("splice", "join")
        key = ("join", s["plate"]) if joining else ("stack", s["plate"])
        if s["action"] == "glue" and groups and groups[-1][0][0] == "stack":
            key = groups[-1][0]
        if groups and groups[-1][0] == key:
            groups[-1][1].append(s)
        else:
            groups.append((key, [s]))
    return [g for _, g in groups]


def assembly_text(data, order, steps) -> str:
    """The assembly panel's text: what to cut, then the steps of ``fabrication.json``
    (:func:`compas_ccu.fabrication.assembly.assembly_steps`) grouped, numbered and wrapped."""
    t = float(data.thickness) * 1000.0
    w = float(data.hinge_width) * 1000.0
    lines = [
        f"Cut every part ({data.material}, {t:g} mm) face up as drawn ('UP' reads from above); "
        f"hinge strips {w:g} mm, centred on the creases (int / ext: intrados / extrados faces). "
        "Steps as in fabrication.json:",
    ]
    lines += [_group_text(g, len(order)) for g in _step_groups(steps)]
    return "\n".join(
        textwrap.fill(s, 98, subsequent_indent="     ", break_on_hyphens=False) for s in lines
    )
