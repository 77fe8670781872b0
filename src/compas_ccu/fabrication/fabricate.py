"""``ccu fabricate``: every workshop file of a design in one folder.

Layout of ``OUT``::

    plates/plate_<id>.dxf     one DXF per plate, millimetres: CUT, CREASE, RULING_SCORE (or
                              RULING when not scored), LABEL
    sheets/sheet_<k>.dxf      one DXF per sheet: every part nested, kerf-compensated toolpaths
    sheets.json               the nesting: every part placed on its sheet (m), for the viewer
    bom.csv                   the bill of materials
    hinges.dxf                the textile hinge strips as cut patterns (mm)
    <name>.3dm                Rhino: plates, creases, rulings, solids, cut patterns, stack (m)
    solids.obj, solids.glb    the thick plates at the design state (OBJ doubles, glTF float32)
    stack.obj                 the flat-folded stack
    <name>.fold               FOLD 1.2: folded form, cut patterns, flat-folded stack
    assembly.svg, assembly.pdf   plate numbering and stacking order
    fabrication.json          what was written and the checks (stack, corrections, collisions,
                              bending), the sheets, the bill of materials and the assembly steps

Plate and crease ids follow the flat-folded stack (plate k at stack position k, crease k the
k-th from the bottom); ``fabrication.json``'s ``model_ids`` maps them to the model's ids.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path
from typing import NamedTuple

from compas_ccu.errors import SelfIntersectionError
from compas_ccu.fabrication import fabrication_data
from compas_ccu.fabrication.dxf import write_plate_dxf
from compas_ccu.fabrication.fold import fold_document, fold_json
from compas_ccu.fabrication.hinge_dxf import write_hinge_dxf
from compas_ccu.fabrication.hinges import hinge_strips
from compas_ccu.fabrication.meshes import write_gltf, write_obj
from compas_ccu.fabrication.rhino import write_3dm
from compas_ccu.fabrication.sheet import write_assembly_sheets
from compas_ccu.fabrication.splices import splice_summary
from compas_ccu.fabrication.workshop import (
    WorkshopOptions,
    plan_workshop,
    write_bom_csv,
    write_sheet_dxf,
)
from compas_ccu.key_figures.text import utilisation_text
from compas_ccu.thickness import ThickModel
from compas_ccu.thickness.bending import bending_verdict

__all__ = ["fabricate", "workshop_summary", "failed_checks"]

#: Third-party modules the writers import (the ``fab`` and ``viz`` extras, and shapely).
REQUIRED_MODULES = ("ezdxf", "rhino3dm", "trimesh", "shapely", "matplotlib")


def _require_modules() -> None:
    missing = [m for m in REQUIRED_MODULES if importlib.util.find_spec(m) is None]
    if missing:
        raise ModuleNotFoundError(
            f"ccu fabricate needs {', '.join(missing)}: pip install 'compas_ccu[fab,viz]'; "
            "nothing was written"
        )


def workshop_summary(summary: dict, data) -> dict:
    """The thick model's summary with the model's plate and crease ids turned into the
    workshop's (:func:`compas_ccu.fabrication.workshop_ids`)."""
    plates = {m: k for k, m in enumerate(data.metadata["model_plate_ids"])}
    creases = data.metadata["model_crease_ids"]
    out = json.loads(json.dumps(summary))
    out["stack_order"] = [plates[int(m)] for m in summary["stack_order"]]
    for key in ("pairing", "offset_planarity_design", "correction_design"):
        if isinstance(out.get(key), list) and len(out[key]) == len(creases):
            out[key] = [summary[key][m] for m in creases]
    worst = out.get("bending", {}).get("worst")
    if worst and worst.get("plate") is not None:
        worst["plate"] = plates[int(worst["plate"])]
    for key in ("first", "closest"):
        record = out.get("collisions", {}).get(key)
        if record and "plates" in record:
            record["plates"] = [plates[int(m)] for m in record["plates"]]
    return out


def _leading_crease(model, model_creases: list) -> int:
    """The workshop id of the model's leading crease (the fixed crease of its leading plate):
    the crease whose reflection angle the design angle is (``ccu import`` leads with it)."""
    lead = next(ci for ci, c in enumerate(model.mechanism.creases) if c.fixed)
    return int(list(model_creases).index(lead))


def failed_checks(manifest: dict) -> list:
    """The checks of a ``fabrication.json`` manifest that failed, in words (empty: all pass)."""
    failed = []
    if manifest.get("bending", {}).get("exceeded"):
        b = manifest["bending"]
        verdict = bending_verdict(True, b.get("basis", {}))
        failed.append(
            f"bending utilisation {utilisation_text(b['max_utilisation'])} > 1 (plate "
            f"{b['worst']['plate']}): " + verdict.split(": ", 1)[1]
        )
    splices = (manifest.get("workshop") or {}).get("splice_bending") or {}
    if splices.get("exceeded"):
        worst = max(splices["cuts"], key=lambda c: c["utilisation"])
        broken = worst["utilisation_characteristic"] > 1.0
        failed.append(
            f"splice plates: bending utilisation {utilisation_text(worst['utilisation'])} > 1"
            + (
                f" ({utilisation_text(worst['utilisation_characteristic'])} characteristic: "
                "they would break)"
                if broken
                else ""
            )
            + f" where plate "
            f"{worst['plate']} is cut along ruling {worst['ruling']} (the plate's "
            f"{utilisation_text(worst['plate_utilisation'])} x {splices['factor']:.3g} for splices "
            f"{splices['splice_thickness'] * 1000:.3g} mm thick glued on both faces): use "
            "thinner splice plates ([fabrication] splice_thickness) or larger sheets"
        )
    spliced = (manifest.get("splices") or {}).get("collisions") or {}
    if spliced.get("interpenetration"):
        failed.append(
            "splice plates lie inside their neighbouring plates at the design state "
            "(fabrication.json splices.collisions)"
        )
    if manifest.get("collisions", {}).get("interpenetration"):
        failed.append("the thick plates interpenetrate (written with --allow-collisions)")
    return failed


def _remove_stale(out: Path, files: set) -> list:
    """Remove the files a previous ``ccu fabricate`` listed in ``out/fabrication.json`` that
    this one does not write (a design with fewer plates or sheets would leave plate files
    that ``ccu import`` reads as part of the structure). Only files of that list inside
    ``out`` are removed; nothing else in the folder is touched."""
    path = out / "fabrication.json"
    try:
        old = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    if not isinstance(old, dict) or old.get("format") != "ccu.fabrication":
        return []
    root = out.resolve()
    removed = []
    for name in old.get("files") or []:
        if not isinstance(name, str) or name in files:
            continue
        target = (out / name).resolve()
        if root not in target.parents or not target.is_file():
            continue  # outside the folder (a hand-edited list) or gone already
        target.unlink()
        removed.append(name)
    return removed


def _thick_model(model, *, thickness, material, grain, allow: bool) -> tuple:
    """The thick plates of ``model`` and their summary; refused (nothing written) if they
    interpenetrate on the way to the design state, unless ``allow``."""
    thick = ThickModel(model, thickness=thickness, material=material, grain=grain)
    summary = thick.summary()
    first = summary["collisions"]["first"]
    if first is not None and not allow:
        raise SelfIntersectionError(
            f"thick plates {first['plates'][0]} and {first['plates'][1]} interpenetrate at "
            f"alpha = {first['alpha']:.4g} deg on the way to the design state (depth "
            f"{first['depth'] * 1000:.3g} mm near {[round(v, 4) for v in first['point']]} m); "
            "nothing was written (allow_collisions / --allow-collisions writes anyway)",
            alpha=first["alpha"],
            crease=None,
        )
    return thick, summary


def _plan(data, thick, strips, workshop: WorkshopOptions, summary: dict):
    """The workshop plan (:func:`compas_ccu.fabrication.workshop.plan_workshop`): parts, sheets,
    splices, bill of materials and assembly; refuses a part that fits no sheet, naming it."""
    bend = thick.bending()
    return plan_workshop(
        data,
        strips,
        workshop,
        density=float(thick.material.density),
        pairing=summary.get("pairing"),
        utilisation=bend.utilisation.max(axis=0),
        strength_factor=bend.factors.strength_factor,
    )


class _Files(NamedTuple):
    """The files of a ``ccu fabricate`` folder, relative to it."""

    stem: str  #: the design's name made a file name
    plates: list  #: ``plates/plate_<id>.dxf``, in array order
    sheets: list  #: ``sheets/sheet_<k>.dxf``

    @property
    def names(self) -> list:
        """Every file but ``fabrication.json``, in the manifest's order."""
        return (
            self.plates
            + self.sheets
            + [
                "sheets.json",
                "bom.csv",
                "hinges.dxf",
                f"{self.stem}.3dm",
                "solids.obj",
                "solids.glb",
                "stack.obj",
                f"{self.stem}.fold",
                "assembly.svg",
                "assembly.pdf",
            ]
        )


def _file_names(data, plan) -> _Files:
    """The files :func:`fabricate` writes for ``data`` and its workshop ``plan``."""
    stem = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in data.name) or "design"
    plates = [f"plates/plate_{pid}.dxf" for pid in data.plate_ids]
    sheets = [f"sheets/sheet_{k + 1}.dxf" for k in range(len(plan.sheets))]
    return _Files(stem, plates, sheets)


def _manifest(model, data, thick, strips, plan, workshop, summary, files, design_sha256) -> dict:
    """``fabrication.json``: what is written, the ids, the thick model's checks (``summary``),
    the splices and stack height, the workshop, bill of materials and assembly, and the checks
    that failed (:func:`failed_checks`)."""
    manifest = {
        "format": "ccu.fabrication",
        "version": 1,
        "design": data.name,
        **({} if design_sha256 is None else {"design_sha256": str(design_sha256)}),
        "alpha": data.alpha,
        "units": {"dxf": "mm", "3dm": "m", "obj": "m", "glb": "m", "fold": "m"},
        "files": files.names + ["fabrication.json"],
        "plates": len(data.plate_ids),
        "hinge_width": data.hinge_width,
        "hinge_strips": len(strips),
        "model_ids": {
            "plates": data.metadata["model_plate_ids"],
            "creases": data.metadata["model_crease_ids"],
        },
        "leading_crease": _leading_crease(model, data.metadata["model_crease_ids"]),
        **summary,
    }
    manifest["splices"] = splice_summary(thick, data, plan.splices, plan.splits, workshop)
    manifest["stack_height_plates"] = manifest["splices"]["stack_height_plates"]
    manifest["stack_height"] = manifest["splices"]["stack_height"]  # with the splice plates
    work = plan.summary()
    manifest["bom"] = work.pop("bom")
    manifest["assembly"] = work.pop("assembly")
    manifest["workshop"] = work
    manifest["failed_checks"] = failed_checks(manifest)
    return manifest


def _write_files(
    out: Path, files: _Files, data, plan, strips, workshop, manifest, *, fold, layout, text
) -> None:
    """Every file into ``out`` (after every check): the stale files of an earlier run removed
    (:func:`_remove_stale`), then the writers; ``fold``, ``layout`` (``sheets.json``) and
    ``text`` (``fabrication.json``) are composed already."""
    _remove_stale(out, set(manifest["files"]))
    (out / "plates").mkdir(parents=True, exist_ok=True)
    (out / "sheets").mkdir(exist_ok=True)
    for i, name in enumerate(files.plates):
        write_plate_dxf(data, i, out / name, score_rulings=workshop.score_rulings)
    for k, name in enumerate(files.sheets):
        write_sheet_dxf(plan, k, out / name, name=data.name)
    (out / "sheets.json").write_text(layout, encoding="utf-8")
    write_bom_csv(plan, out / "bom.csv")
    write_hinge_dxf(strips, out / "hinges.dxf", name=data.name)
    write_3dm(data, out / f"{files.stem}.3dm")
    write_obj(data, out / "solids.obj", state="deployed")
    write_gltf(data, out / "solids.glb", state="deployed")
    write_obj(data, out / "stack.obj", state="stack")
    (out / f"{files.stem}.fold").write_text(fold, encoding="utf-8")
    write_assembly_sheets(
        data,
        [out / "assembly.svg", out / "assembly.pdf"],
        steps=plan.assembly,
        stack=manifest["splices"],
    )
    (out / "fabrication.json").write_text(text, encoding="utf-8")


def fabricate(
    model,
    out,
    *,
    thickness=None,
    material=None,
    grain=None,
    hinge_width=None,
    allow_collisions: bool = False,
    workshop: WorkshopOptions | None = None,
    design_sha256: str | None = None,
) -> dict:
    """Write the fabrication files of ``model`` at its design state into ``out``.

    Every check runs before the first file (or the folder ``out``) is written: the writers'
    modules are importable, the thickness, material and hinge width are possible (the hinge
    strips are built, so a strip too wide for a crease's curvature is refused too), the thick
    plates do not interpenetrate, and ``fabrication.json`` is composed as strict JSON. Into a
    folder of an earlier ``ccu fabricate``, the files its ``fabrication.json`` listed and this
    one does not write are removed first (nothing else is touched).

    Parameters
    ----------
    model : compas_ccu.model.CCUModel
    out : str or Path
    thickness, material, grain, hinge_width : optional
        Override the design's ``[plates]`` values.
    allow_collisions : bool
        Write the files even if the thick plates interpenetrate on the way from the flat stack
        to the design state.
    workshop : WorkshopOptions, optional
        Sheets, cutter, nesting and prices; default: the design's ``[fabrication]`` section.
    design_sha256 : str, optional
        SHA-256 of the design file the model was read from: recorded in ``fabrication.json``
        and ``sheets.json``, so that the report and the viewer refuse this folder for another
        version of the file.

    Returns
    -------
    dict
        The manifest written to ``fabrication.json``: its ``workshop`` (sheets, utilisation,
        splits, the hinge roll), ``bom`` (the bill of materials, as in ``bom.csv``) and
        ``assembly`` (the steps in stack order) are what the report reads;
        :func:`failed_checks` lists the failed checks.

    Raises
    ------
    SelfIntersectionError
        The thick plates interpenetrate along the path (unless ``allow_collisions``).
    GeometryError, MaterialError
        Impossible thickness, hinge width or material; a part that fits no sheet in stock
        (named).
    ModuleNotFoundError
        A writer's module (the ``fab`` / ``viz`` extras) is missing.
    """
    _require_modules()
    thick, summary = _thick_model(
        model, thickness=thickness, material=material, grain=grain, allow=allow_collisions
    )
    data = fabrication_data(model, thick=thick, hinge_width=hinge_width)
    summary = workshop_summary(summary, data)
    strips = hinge_strips(data)  # refuses a hinge width too large for a crease's curvature
    if workshop is None:
        workshop = WorkshopOptions.from_section(model.design.fabrication)
    plan = _plan(data, thick, strips, workshop, summary)  # refuses a part that fits no sheet
    fold = fold_json(fold_document(data))
    files = _file_names(data, plan)
    manifest = _manifest(model, data, thick, strips, plan, workshop, summary, files, design_sha256)
    text = json.dumps(manifest, indent=1, allow_nan=False)
    layout = plan.layout()
    if design_sha256 is not None:
        layout["design_sha256"] = str(design_sha256)
    layout_text = json.dumps(layout, separators=(",", ":"), allow_nan=False)
    # --- every check passed: write
    _write_files(
        Path(out),
        files,
        data,
        plan,
        strips,
        workshop,
        manifest,
        fold=fold,
        layout=layout_text,
        text=text,
    )
    return manifest
