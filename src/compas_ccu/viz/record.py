"""The report as an engineering record: what went in (the design file as read, its SHA-256, the
package version, the date, the units, the material constants) and what the workshop got (the
fabrication folder: every file, the sheets and the bill of materials).

:func:`design_record` and :func:`read_fabrication` gather plain data; the report
(:mod:`compas_ccu.viz.report`) renders it as HTML and PDF.

The fabrication folder is read tolerantly: every file is listed; ``fabrication.json`` (written by
``ccu fabricate``) is read if it is there and parses: its ``workshop`` (the sheets, their
utilisation), ``bom`` (the bill of materials: its rows and totals) and ``failed_checks`` are
shown; other writers' tables ``bom`` and ``sheets`` (lists of objects, at the top level or under
``nesting``) and a number ``utilisation`` are shown as they are; ``design_sha256`` is compared
with the design file's hash. Its ``sheets.json``
(the nesting: every part placed on its sheet) is what the viewer shows as the cut patterns
(:func:`read_sheets`).
"""

from __future__ import annotations

import datetime
import hashlib
import json
import math
import platform
from pathlib import Path

from compas_ccu import __version__
from compas_ccu.errors import CCUError, OptionError
from compas_ccu.key_figures.text import material_rows, workshop_rows
from compas_ccu.outputs import MANIFEST
from compas_ccu.thickness import ThickModel

__all__ = [
    "design_record",
    "read_fabrication",
    "read_sheets",
    "table_columns",
    "cell_text",
    "FABRICATION_KEYS",
    "SHEETS_FILE",
]

#: The nesting file of a fabrication folder (``ccu fabricate``; format ``ccu.sheets``).
SHEETS_FILE = "sheets.json"

#: Keys of ``fabrication.json`` the report reads (all optional).
FABRICATION_KEYS = (
    "design",
    "design_sha256",
    "workshop",
    "bom",
    "failed_checks",
    "sheets",
    "nesting",
    "utilisation",
)


def design_record(model, design_file=None, *, now=None) -> dict:
    """The inputs of a report: design file text and hash, version, date, units, materials.

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    design_file : str or Path, optional
        The design TOML the model was loaded from: its text is kept verbatim with its SHA-256
        (of the bytes, as :func:`compas_ccu.fea.record.last_validation` keys validations).
    now : datetime.datetime, optional
        The date of the record (default: now, UTC).

    Returns
    -------
    dict
        ``file`` (name or None), ``text`` (str or None), ``sha256`` (str or None), ``version``,
        ``python``, ``date`` (UTC, ISO 8601), ``units`` (the file's length units and the
        report's), ``material`` (rows of :func:`compas_ccu.key_figures.text.material_rows`, or
        None with ``material_error``), ``material_constants`` (plain numbers, SI units).

    Examples
    --------
    >>> from compas_ccu.model import load_model
    >>> r = design_record(load_model("examples/cone.toml"), "examples/cone.toml")
    >>> r["file"], len(r["sha256"]), r["units"]["lengths in the file"]
    ('cone.toml', 64, 'm')
    """
    now = now or datetime.datetime.now(datetime.timezone.utc)
    record = {
        "file": None,
        "text": None,
        "sha256": None,
        "version": __version__,
        "python": platform.python_version(),
        "date": now.astimezone(datetime.timezone.utc).isoformat(timespec="seconds"),
        "units": {
            "lengths in the file": model.design.units,
            "lengths in the report": "m (DXF: mm)",
            "angles": "deg",
            "stresses": "MPa (moduli GPa)",
        },
        "material": None,
        "material_error": None,
        "material_constants": None,
    }
    if design_file is not None:
        path = Path(design_file)
        data = path.read_bytes()
        record.update(
            file=path.name,
            text=data.decode("utf-8", errors="replace"),
            sha256=hashlib.sha256(data).hexdigest(),
        )
    try:
        thick = ThickModel(model)
    except CCUError as exc:
        record["material_error"] = str(exc)
        return record
    m, f = thick.material, thick.factors
    record["material"] = material_rows(m, f, thickness=thick.thickness, grain=thick.grain)
    record["material_constants"] = {
        **m.to_dict(),
        "thickness": thick.thickness,
        "grain": thick.grain,
        "design_factors": f.to_dict(),
    }
    return record


def read_fabrication(folder, *, design=None, sha256=None) -> dict:
    """Read a fabrication folder (``ccu fabricate``) tolerantly.

    Parameters
    ----------
    folder : str or Path
    design : str, optional
        The design's name: a ``fabrication.json`` of another design is refused.
    sha256 : str, optional
        The design file's hash: a ``fabrication.json`` with another ``design_sha256`` is
        refused (one without that key is accepted).

    Returns
    -------
    dict
        ``folder`` (Path), ``files`` (relative POSIX paths of every file, sorted),
        ``manifest`` (the parsed ``fabrication.json`` or None), ``problems`` (list of str: what
        could not be read), ``bom`` and ``sheets`` (lists of dicts or None), ``workshop_rows``
        (list of (label, text): :func:`compas_ccu.key_figures.text.workshop_rows`),
        ``utilisation`` (float or None), ``failed_checks`` (list of str), ``layout`` (the
        parsed ``sheets.json`` for the viewer, or None).

    Raises
    ------
    OptionError
        ``folder`` is not a folder, or its ``fabrication.json`` is of another design.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> d = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (d / "plate_0.dxf").write_text("0\\nEOF\\n")
    >>> f = read_fabrication(d)
    >>> f["files"], f["manifest"], f["bom"]
    (['plate_0.dxf'], None, None)
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise OptionError(
            f"--fabrication must be a folder written by 'ccu fabricate', got {str(folder)!r}"
        )
    files = sorted(
        p.relative_to(folder).as_posix()
        for p in folder.rglob("*")
        if p.is_file() and p.name != MANIFEST and not p.name.startswith(".ccu-")
    )
    out = {
        "folder": folder,
        "files": files,
        "manifest": None,
        "problems": [],
        "bom": None,
        "workshop_rows": [],
        "sheets": None,
        "utilisation": None,
        "failed_checks": [],
        "layout": None,
    }
    if (folder / SHEETS_FILE).is_file():  # the nesting for the viewer (none: its own layout)
        try:
            out["layout"] = read_sheets(folder)
        except OptionError as exc:
            out["problems"].append(f"{exc}; the viewer shows its own layout of the cut patterns")
        else:
            _same_design(out["layout"], folder, design, sha256)
    manifest = _read_manifest(folder, out["problems"])
    if manifest is not None:
        out["manifest"] = manifest
        _same_design(manifest, folder, design, sha256)
        _read_tables(manifest, out)
    return out


def _read_manifest(folder: Path, problems: list):
    """The folder's ``fabrication.json`` parsed, or None (what went wrong added to
    ``problems``)."""
    path = folder / "fabrication.json"
    if not path.is_file():
        problems.append("no fabrication.json in the folder: the files are listed only")
        return None
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        problems.append(f"fabrication.json could not be read: {exc}")
        return None
    if not isinstance(manifest, dict):
        problems.append(f"fabrication.json holds a {type(manifest).__name__}, not an object")
        return None
    return manifest


def _read_tables(manifest: dict, out: dict) -> None:
    """The workshop rows, failed checks, ``bom`` and ``sheets`` tables and utilisation of a
    ``fabrication.json`` into ``out`` (:func:`read_fabrication`); what cannot be shown is
    added to its ``problems``."""
    nesting = manifest.get("nesting") if isinstance(manifest.get("nesting"), dict) else {}
    workshop = manifest.get("workshop") if isinstance(manifest.get("workshop"), dict) else {}
    if isinstance(workshop.get("sheets"), list):  # ccu fabricate
        nesting = {**nesting, **_workshop_tables(workshop)}
    bom = manifest.get("bom")
    if isinstance(bom, dict) and isinstance(bom.get("rows"), list):  # ccu fabricate
        try:
            out["workshop_rows"] = workshop_rows(manifest)
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            out["problems"].append(f"fabrication.json: the workshop summary is incomplete ({exc})")
        manifest = {**manifest, "bom": bom["rows"]}
    checks = manifest.get("failed_checks")
    if isinstance(checks, list):
        out["failed_checks"] = [str(c) for c in checks]
    for key in ("bom", "sheets"):
        table = manifest.get(key, nesting.get(key))
        if table is None:
            continue
        if isinstance(table, list) and all(isinstance(r, dict) for r in table):
            out[key] = table
        else:
            out["problems"].append(f"fabrication.json: {key} is not a list of objects, not shown")
    u = manifest.get("utilisation", nesting.get("utilisation"))
    if isinstance(u, (int, float)) and not isinstance(u, bool) and math.isfinite(u):
        out["utilisation"] = float(u)


def _workshop_tables(workshop: dict) -> dict:
    """The sheets table and utilisation of ``ccu fabricate``'s ``workshop`` summary."""
    rows = []
    for k, sheet in enumerate(workshop["sheets"], start=1):
        if not isinstance(sheet, dict):
            return {}
        size = sheet.get("size") or [None, None]
        t = sheet.get("thickness")
        u = sheet.get("utilisation")
        rows.append(
            {
                "sheet": k,
                "size_mm": " x ".join(f"{1000 * v:g}" for v in size if v is not None),
                "thickness_mm": None if t is None else round(1000 * t, 6),
                "parts": len(sheet.get("parts") or []),
                "utilisation": None if u is None else f"{100 * u:.1f} %",
                "part_names": sheet.get("parts"),
            }
        )
    return {"sheets": rows, "utilisation": workshop.get("utilisation")}


def read_sheets(folder, *, design=None, sha256=None) -> dict:
    """The nesting of a fabrication folder: its ``sheets.json``, parsed and checked.

    Parameters
    ----------
    folder : str or Path
        A folder written by ``ccu fabricate``.
    design : str, optional
        The design's name: the nesting of another design is refused.
    sha256 : str, optional
        The design file's hash: a nesting recorded with another ``design_sha256`` is refused
        (one without that key is accepted).

    Returns
    -------
    dict
        ``sheets.json`` (``compas_ccu.fabrication.workshop.WorkshopPlan.layout``): ``sheets``,
        ``parts`` (placed on their sheets, m), ``model_plate_ids``, ``design``; what
        :func:`compas_ccu.viz.viewer.viewer_figure` takes as ``sheets``.

    Raises
    ------
    OptionError
        ``folder`` is not a folder, has no ``sheets.json`` (an older ``ccu fabricate``: write
        it again), the file is no nesting (no ``sheets`` and ``parts`` lists), or is of another
        design or another version of the design file; the message names the folder.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> read_sheets(tempfile.mkdtemp())  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    compas_ccu.errors.OptionError: --fabrication '...' has no sheets.json (the nesting ...
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise OptionError(
            f"--fabrication must be a folder written by 'ccu fabricate', got {str(folder)!r}"
        )
    path = folder / SHEETS_FILE
    if not path.is_file():
        raise OptionError(
            f"--fabrication {str(folder)!r} has no {SHEETS_FILE} (the nesting of the parts on "
            "the sheets): it was written by an older 'ccu fabricate', or is no fabrication "
            "folder; run 'ccu fabricate' again"
        )
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise OptionError(
            f"--fabrication {str(folder)!r}: {SHEETS_FILE} cannot be read: {exc}"
        ) from None
    if not isinstance(doc, dict) or doc.get("format") != "ccu.sheets":
        raise OptionError(
            f"--fabrication {str(folder)!r}: {SHEETS_FILE} is not a 'ccu.sheets' nesting"
        )
    missing = [k for k in ("sheets", "parts") if not isinstance(doc.get(k), list)]
    if missing:
        raise OptionError(
            f"--fabrication {str(folder)!r}: {SHEETS_FILE} has no {' and no '.join(missing)} list"
        )
    _same_design(doc, folder, design, sha256)
    return doc


def _same_design(doc: dict, folder: Path, design, sha256) -> None:
    """Refuse a ``fabrication.json`` or ``sheets.json`` of another design or file version."""
    if design is not None and doc.get("design") not in (None, design):
        raise OptionError(
            f"--fabrication {str(folder)!r} holds the fabrication of design "
            f"{doc.get('design')!r}, not of {design!r}"
        )
    if sha256 is not None and doc.get("design_sha256") not in (None, sha256):
        raise OptionError(
            f"--fabrication {str(folder)!r} was written from another version of the design file "
            f"(design_sha256 {doc.get('design_sha256')!r}, the file's is {sha256!r})"
        )


def table_columns(rows) -> list:
    """The columns of a list of objects: every key, in order of first appearance.

    >>> table_columns([{"a": 1}, {"b": 2, "a": 3}])
    ['a', 'b']
    """
    return list(dict.fromkeys(k for r in rows for k in r))


def cell_text(value) -> str:
    """A table cell of a fabrication table: numbers to 4 significant digits, lists joined.

    >>> cell_text(0.123456), cell_text(None), cell_text([1, 2]), cell_text(True)
    ('0.1235', '', '1, 2', 'yes')
    """
    if value is None:
        return ""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, (list, tuple)):
        return ", ".join(cell_text(v) for v in value)
    if isinstance(value, dict):
        return json.dumps(value, separators=(",", ":"))
    return str(value)
