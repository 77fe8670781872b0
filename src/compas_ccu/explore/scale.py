"""Span scaling studies (``ccu scale``): one design scaled from its span to a target span.

Every length of the design file (the schema's keys in metres: profile span and rise, control
points, ruling apex and points, widths, spacings, the radial axis, target curves, the plane
origin, the positions of funicular loads, the plates' cut patterns of a ``[[layout.patterns]]``
design from ``ccu import``) is multiplied by the scale factor, so each step is the geometrically
similar design at the new span; the lengths are found by the loader's walk
(:func:`compas_ccu.design.units.map_lengths`). The plate thickness follows a *thickness law*:

======================  ==============================================================
``constant``            the base thickness at every span
``proportional``        ``t0 · s`` (``s`` = span / base span): fully similar plates
``cuberoot``            ``t0 · s^(2/3)``, the cube root of the span ratio squared
``given``               one thickness per step, from the user
======================  ==============================================================

The hinge strip width, the material and the number of segments and plates are kept. Each step is
measured by :func:`compas_ccu.explore.evaluate.evaluate_variant` (the columns of ``ccu
explore``: shape, stack, plate size, mass, bending utilisation, collisions, optional FE), plus
whether every plate still fits a stock sheet.
"""

from __future__ import annotations

import math

import numpy as np

from compas_ccu import limits
from compas_ccu.analysis.plate_size import fits_sheet
from compas_ccu.design.schema import SCHEMA, STOCK_SHEET
from compas_ccu.design.units import map_lengths
from compas_ccu.errors import OptionError
from compas_ccu.explore.evaluate import evaluate_variant

__all__ = ["THICKNESS_LAWS", "SHEET", "law_thickness", "scaled_document", "scale_study"]
__all__ += ["CSV_COLUMNS", "write_csv", "plot_scale"]

#: The thickness laws of a scaling study.
THICKNESS_LAWS = ("constant", "proportional", "cuberoot", "given")
#: The stock sheet the plates are checked against when none is given (the design files'
#: default, :data:`compas_ccu.design.schema.STOCK_SHEET`), m.
SHEET = STOCK_SHEET
#: Lengths that do not grow with the structure: the plate thickness follows its law, the hinge
#: strips are a product width, the loads (a concrete thickness) are the loads', the workshop's
#: stock sheets, kerf and tools are the workshop's.
_NOT_SCALED = ("plates.thickness", "plates.hinge_width", "loads", "fabrication")


def law_thickness(law: str, t0: float, ratio: float, given: float | None = None) -> float:
    """Plate thickness at span ratio ``ratio`` from base thickness ``t0``.

    >>> round(law_thickness("cuberoot", 0.008, 8.0), 12)  # 8^(2/3) = 4
    0.032
    """
    if law == "constant":
        return t0
    if law == "proportional":
        return t0 * ratio
    if law == "cuberoot":
        return t0 * ratio ** (2.0 / 3.0)
    if law == "given":
        if given is None:
            raise OptionError("thickness law 'given' needs a thickness for every step")
        return float(given)
    raise OptionError(f"unknown thickness law {law!r}; known: {', '.join(THICKNESS_LAWS)}")


def scaled_document(document: dict, factor: float, *, thickness: float | None = None) -> dict:
    """The design document with every length multiplied by ``factor`` (and ``thickness``).

    Parameters
    ----------
    document : dict
        A design document (as parsed from TOML).
    factor : float
        Scale factor of the lengths (> 0).
    thickness : float, optional
        The plate thickness of the scaled design, m (default: unchanged).

    Examples
    --------
    >>> doc = {"crease": {"profile": "arc", "span": 2.5, "rise": 1.0, "segments": 64},
    ...        "layout": {"type": "parallel", "plates": 10, "spacing": 0.12}}
    >>> out = scaled_document(doc, 2.0, thickness=0.012)
    >>> out["crease"], out["layout"]["spacing"], out["plates"]["thickness"]
    ({'profile': 'arc', 'span': 5.0, 'rise': 2.0, 'segments': 64}, 0.24, 0.012)
    """
    if not factor > 0.0:
        raise OptionError(f"the scale factor must be > 0, got {factor!r}")
    out = map_lengths(document, SCHEMA, lambda v: v * factor, skip=_NOT_SCALED)
    if thickness is not None:
        out.setdefault("plates", {})["thickness"] = float(thickness)
    return out


def scale_study(
    document: dict,
    base_span: float,
    *,
    to_span: float,
    steps: int = 7,
    law: str = "constant",
    thicknesses=None,
    sheet=SHEET,
    path_states: int = 21,
    collisions: bool = True,
    fe: dict | None = None,
    progress=None,
) -> list:
    """Measure ``document`` scaled from ``base_span`` to ``to_span`` in ``steps`` equal steps.

    Parameters
    ----------
    document : dict
        The base design document.
    base_span : float
        Its crease span (the key figure ``crease_span``), m.
    to_span : float
        The last span, m.
    steps : int
        Steps after the base design (``steps + 1`` rows).
    law : str
        One of :data:`THICKNESS_LAWS`.
    thicknesses : sequence of float, optional
        With law ``given``: one thickness (m) per row.
    sheet : (float, float)
        Stock sheet length and width, m.
    path_states, collisions, fe
        As :func:`compas_ccu.explore.evaluate.evaluate_variant`.
    progress : callable, optional
        Called with every finished row.

    Returns
    -------
    list of dict
        One row per span: ``span_target``, ``scale``, ``thickness_law`` and the evaluation's
        columns (``status``, ``span``, ``mass``, ``bending_utilisation``, ...), ``fits_sheet``.
    """
    if steps < 1:
        raise OptionError(f"steps must be >= 1, got {steps}")
    limits.check("variants", steps + 1, what=f"spans (steps {steps} + the base)")
    if not (math.isfinite(to_span) and to_span > 0.0):
        raise OptionError(f"the target span must be a finite number > 0 m, got {to_span!r}")
    sheet = tuple(sheet)
    if len(sheet) != 2 or not all(math.isfinite(v) and v > 0.0 for v in sheet):
        raise OptionError(f"the sheet must be two finite lengths > 0 m, got {sheet!r}")
    if thicknesses is not None and not all(math.isfinite(t) and t > 0.0 for t in thicknesses):
        raise OptionError(f"the thicknesses must be finite numbers > 0 m, got {thicknesses!r}")
    spans = np.linspace(base_span, to_span, steps + 1)
    if law == "given":
        if thicknesses is None or len(thicknesses) != len(spans):
            got = 0 if thicknesses is None else len(thicknesses)
            raise OptionError(
                f"thickness law 'given' needs {len(spans)} thicknesses (one per span), got {got}"
            )
    elif law not in THICKNESS_LAWS:
        raise OptionError(f"unknown thickness law {law!r}; known: {', '.join(THICKNESS_LAWS)}")
    t0 = float(document.get("plates", {}).get("thickness", SCHEMA["plates"]["thickness"].default))
    rows = []
    for i, span in enumerate(spans):
        ratio = float(span / base_span)
        given = None if thicknesses is None else thicknesses[i]
        t = law_thickness(law, t0, ratio, given)
        variant = scaled_document(document, ratio, thickness=t)
        row = {"span_target": float(span), "scale": ratio, "thickness_law": law}
        row.update(evaluate_variant(variant, path_states=path_states, collisions=collisions, fe=fe))
        fits = None
        if row.get("plate_length") is not None:
            fits = bool(fits_sheet(np.array([[row["plate_length"], row["plate_width"]]]), sheet)[0])
        row["fits_sheet"] = fits
        rows.append(row)
        if progress is not None:
            progress(row)
    return rows


#: The columns of ``scale.csv``, in order (``ccu explore``'s columns that a study reports).
CSV_COLUMNS = (
    "span_target", "scale", "thickness_law", "status", "error",
    "span", "rise", "thickness", "plates", "plate_length", "plate_width", "fits_sheet",
    "stack_length", "stack_width", "stack_height", "mass", "bending_utilisation",
    "bending_curvature", "deployment_energy", "actuation_force", "collision_free",
    "min_clearance", "alpha_limit", "overlap_alpha",
    "fe_utilisation", "fe_deflection_ratio", "fe_buckling_factor", "fe_bending_MPa",
    "fe_hinge_tension", "fe_hinge_shear", "fe_hinge_mean", "fe_actuation_force",
)  # fmt: skip


def write_csv(rows: list, path) -> None:
    """``rows`` as CSV with :data:`CSV_COLUMNS` (the FE columns only when measured)."""
    import csv

    columns = [c for c in CSV_COLUMNS if not c.startswith("fe_") or any(c in r for r in rows)]
    with open(path, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(columns)
        for row in rows:
            writer.writerow(["" if row.get(c) is None else row.get(c) for c in columns])


def plot_scale(rows: list, *, sheet=SHEET, title: str | None = None):
    """Key columns of a scaling study against the span (one panel each).

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    ok = [r for r in rows if r["status"] == "ok"]
    span = np.array([r["span"] for r in ok])
    panels = [
        ("mass", "mass (kg)", None),
        ("bending_utilisation", "bending utilisation (active bending)", (1.0, "limit 1")),
        (
            "plate_length",
            "largest plate: length (m)",
            (max(sheet), f"stock sheet {max(sheet):g} m"),
        ),
        ("stack_height", "flat stack height (m)", None),
        ("actuation_force", "force between the feet to deploy (N)", None),
    ]
    for name, label, limit in (
        ("fe_buckling_factor", "linear buckling factor (FE)", (1.0, "factor 1")),
        ("fe_deflection_ratio", "deflection / its limit (FE)", (1.0, "limit (span/500)")),
        ("fe_hinge_mean", "hinge line force, governing case mean (FE, N/m)", None),
    ):
        if any(r.get(name) is not None for r in ok):
            panels.append((name, label, limit))
    columns = 3 if len(panels) > 4 else 2
    rows_n = int(np.ceil(len(panels) / columns))
    fig, axes = plt.subplots(rows_n, columns, figsize=(4.2 * columns, 3.2 * rows_n))
    for ax, (name, label, limit) in zip(np.ravel(axes), panels):
        values = np.array([np.nan if r.get(name) is None else r[name] for r in ok], float)
        ax.plot(span, values, "o-", color="#1f63d6")
        if limit is not None:
            ax.axhline(limit[0], color="#c0262d", lw=1, ls="--", label=limit[1])
            ax.legend(loc="best", fontsize=8)
        ax.set_xlabel("span (m)")
        ax.set_ylabel(label)
        ax.grid(True, color="#dddddd")
    for ax in np.ravel(axes)[len(panels) :]:
        ax.set_visible(False)
    law = ok[0]["thickness_law"] if ok else ""
    fig.suptitle(title or f"span scaling study (thickness law: {law})")
    fig.tight_layout()
    return fig
