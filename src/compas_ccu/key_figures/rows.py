"""The rows of text of the key figures and checks, and the wordings they share.

A row is ``(label, text)``; a row that continues the one above has an empty label; a failed
check is marked ``** ... **`` in its text (:func:`row_failed`). ``ccu info`` prints rows as lines
(:func:`rows_lines`, the label padded to :data:`LABEL_WIDTH`), the report as table rows. The
wordings every kind of row uses: a utilisation (:func:`utilisation_text`), a key figure's value
with its unit (:func:`value_text`) and the design factors of a check (:func:`basis_text`).
"""

from __future__ import annotations

import math

from compas_ccu.key_figures.table import FIGURES

__all__ = [
    "LABEL_WIDTH",
    "rows_lines",
    "row_failed",
    "utilisation_text",
    "value_text",
    "basis_text",
]


#: Width of the label column of ``ccu info``.
LABEL_WIDTH = 18


def rows_lines(rows) -> list:
    """Lines of text of ``rows``: the label padded to :data:`LABEL_WIDTH` (``ccu info``).

    >>> rows_lines([("plates", "10"), ("", "more")])
    ['plates            10', '                  more']
    """
    return [f"{label:<{LABEL_WIDTH}}{text}" for label, text in rows]


def row_failed(text: str) -> bool:
    """True if a row's text marks a failed check (``** ... **``)."""
    return "** " in text and " **" in text


def utilisation_text(u) -> str:
    """A utilisation as a user reads it: three decimals, and more where three would round a
    value across 1 (so that no failed check reads 1.000 and no passing one 1.000 either).

    Examples
    --------
    >>> utilisation_text(1.004), utilisation_text(0.5), utilisation_text(1.0)
    ('1.004', '0.500', '1.000')
    >>> utilisation_text(1.0004), utilisation_text(0.99996), utilisation_text(1.0 + 1e-12)
    ('1.0004', '0.99996', '1.000000000001')
    >>> utilisation_text(0.9995), utilisation_text(12.3456), utilisation_text(None)
    ('0.9995', '12.346', '—')
    >>> utilisation_text(float("nan")), utilisation_text(float("inf"))
    ('nan', 'inf')
    """
    if u is None:
        return "—"
    u = float(u)
    if not math.isfinite(u):
        return str(u)
    digits = 3
    while digits < 15 and u != 1.0 and float(f"{u:.{digits}f}") == 1.0:
        digits += 1
    return f"{u:.{digits}f}"


def value_text(name: str, value) -> str:
    """One key figure's value with its unit (the complete table of the report).

    >>> value_text("crease_span", 2.5), value_text("plates", 10), value_text("k_def", None)
    ('2.5 m', '10', '—')
    """
    unit = _UNITS[name]
    if value is None:
        return "—"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        text = f"{value:.6g}" if math.isfinite(value) else str(value)
    else:
        text = str(value)
    return f"{text} {unit}" if unit and text else text


_UNITS = {f.name: f.unit for f in FIGURES}


def basis_text(basis: dict) -> str:
    """The design factors of a bending or FE check (``DesignFactors.to_dict()``) as text.

    >>> basis_text({"code": "characteristic"})
    'characteristic strengths f_k (k_mod = gamma_M = 1)'
    """
    if basis["code"] == "characteristic":
        return "characteristic strengths f_k (k_mod = gamma_M = 1)"
    creep = "" if basis.get("k_def") is None else f", k_def {basis['k_def']:g}"
    return (
        f"{basis['basis']}: f_d = k_mod f_k / gamma_M, k_mod {basis['k_mod']:g}, gamma_M "
        f"{basis['gamma_M']:g}{creep} ({basis['source']})"
    )
