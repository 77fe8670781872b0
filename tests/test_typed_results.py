"""Typed results: a public function returns a dataclass or an array, not a bare dict, where the
result crosses a module; a dict is only a document (``__data__``, ``to_dict`` / ``as_dict``, a
``summary``, a profile's ``parameters``, a state's ``metrics``), a table row, plotly keyword
arguments, a message to another process or a mapping (:data:`NOT_RESULTS`). The core packages
(curves, strips, kinematics, model) have no bare dict result at all; in the rest of
``src/compas_ccu`` the ones left may only go (:data:`REMAINING`, a ratchet).

A mapping is a dict whose keys are data, not fields: a crease kind, a parameter, a plate or
crease id, a quadrant, a key set that depends on the design or on what was asked. It is
annotated with its key and value types (``-> dict[int, str]``), and it must ALSO be on the
``"mapping"`` list: writing ``dict[str, Any]`` over a record hides nothing, because a
subscripted dict annotation that is not listed counts against :data:`REMAINING` as a bare one
does (:func:`mapping_results`). A record with fixed fields read by key is a dataclass."""

from __future__ import annotations

import ast
from pathlib import Path

from parsed import nodes

SRC = Path(__file__).resolve().parents[1] / "src" / "compas_ccu"
CORE = ("curves", "strips", "kinematics", "model")
#: The names whose dict is a document written to a file (JSON / TOML), not a result.
DOCUMENTS = {"__data__", "to_dict", "as_dict", "summary", "parameters", "metrics"}

#: Public functions whose dict is not a result, by why (``path:name`` under src/compas_ccu).
NOT_RESULTS = {
    # a file's document (TOML, JSON, FOLD, DXF, 3DM), read back or about to be written, or a
    # section of one: its keys are the file's
    "document": (
        "catalog.py:document", "catalog.py:write_catalog", "cli/check.py:read_record",
        "cli/model_commands.py:info_data", "design/curve_files.py:read_curve_files",
        "design/curve_files.py:absolute_curve_files", "design/document.py:parse_toml",
        "design/document.py:read_toml", "design/document.py:metric_document",
        "design/document.py:document_in", "design/key.py:with_units",
        "design/sections.py:to_values", "design/units.py:map_lengths",
        "design/units.py:convert_document", "design/validation.py:validate",
        "explore/parsing.py:table", "explore/parsing.py:default_constraints",
        "explore/parsing.py:parse_goals", "explore/parsing.py:flatten",
        "explore/parsing.py:apply_settings", "explore/runner.py:read_manifest",
        "explore/scale.py:scaled_document", "explore/study.py:cheap_constraints",
        "explore/study.py:fe_constraints", "explore/study.py:document_for",
        "explore/sweep.py:document_for", "explore/study_summary.py:summarise_study",
        "explore/summary.py:summarise", "explore/summary.py:counts",
        "explore/summary.py:stage_seconds", "fabrication/bom.py:bill_of_materials",
        "fabrication/dxf.py:read_plate_dxf", "fabrication/fabricate.py:workshop_summary",
        "fabrication/fabricate.py:fabricate", "fabrication/fold.py:fold_document",
        "fabrication/fold.py:read_fold", "fabrication/fold_frame.py:fold_frame",
        "fabrication/import_selection.py:read_manifest",
        "fabrication/import_tree.py:leading_document",
        "fabrication/import_tree.py:structure_document", "fabrication/plan.py:layout",
        "fabrication/rhino.py:read_3dm_summary", "fabrication/splices.py:splice_summary",
        "fea/history.py:load_path", "fea/validation.py:load_path",
        "fea/record.py:last_validation", "ghpython/components.py:crease_design",
        "fea/design_values.py:clauses",  # validation.json's stiffness ``clauses``, read back
        "structure.py:to_contract", "studio/documents.py:parse_document",
        "studio/session.py:document", "studio/session.py:valid_document",
        "thickness/summary.py:thick_summary",
        "thickness/collision_check.py:first_contact",  # a CollisionReport's ``first``
        "viz/record.py:design_record",
        "viz/record.py:read_fabrication", "viz/record.py:read_sheets",
        "viz/viewer_ground.py:sheet_document",
    ),
    # a table row: column (metric, key figure) -> value, merged into the row a sweep or study
    # writes to results.jsonl / Parquet / CSV (explore/evaluate.py ``row.update(...)``) or the
    # catalog's table; the column names are the metric table's (docs/explore.md), so a
    # dataclass would only be turned back into the same row
    "row": (
        "explore/metrics.py:shape_metrics", "explore/metrics.py:path_metrics",
        "explore/metrics.py:thickness_metrics", "explore/metrics.py:collision_metrics",
        "explore/metrics.py:fe_metrics", "explore/evaluate.py:row_template",
        "explore/evaluate.py:evaluate_variant", "explore/runner.py:cluster_failure",
        "explore/sampler.py:evaluation", "explore/results.py:read",
        "explore/results.py:column_types", "catalog.py:catalog_metrics",
        "key_figures/measure.py:design_state_figures", "key_figures/measure.py:state_figures",
        "key_figures/measure.py:path_figures", "key_figures/measure.py:thickness_figures",
        "key_figures/measure.py:group",
    ),
    # plotly keyword arguments: a layout, a camera, a slider, a trace's x / y / z
    "plotly": (
        "viz/viewer_controls.py:readout_annotation", "viz/viewer_controls.py:eye",
        "viz/viewer_controls.py:scene_layout", "viz/viewer_controls.py:figure_title",
        "viz/viewer_controls.py:slider", "viz/viewer_controls.py:play_buttons",
        "viz/viewer_controls.py:figure_layout", "viz/viewer_traces.py:xyz",
    ),
    # a message or keyword arguments crossing a process boundary: nesting_worker runs as a
    # script without compas_ccu and answers in JSON lines; the studio's and the explorer's jobs
    # are pickled keyword arguments and results of a process pool
    "process": (
        "fabrication/nesting_worker.py:search", "studio/target.py:job",
        "studio/target.py:fit_job", "studio/target_upload.py:read_upload",
        "studio/export.py:export", "explore/study.py:options", "explore/sweep.py:options",
    ),
    # keys are data (a kind, a parameter, a plate, a crease, a quadrant), not fields: the key
    # set depends on the design or on what was asked, and callers iterate it; annotated
    # ``dict[K, V]`` (:func:`mapping_results`) and listed here, nowhere else
    "mapping": (
        "explore/pareto.py:violations",  # constraint's metric -> violation
        "explore/study.py:distributions",  # parameter -> Optuna distribution
        "explore/study.py:settings_of",  # parameter -> design value
        "fabrication/fold_angles.py:crease_fold_angles",  # crease id -> (m - 1,) angles
        "fabrication/hinge_dxf.py:write_hinge_dxf",  # crease id -> the strip's translation
        "fabrication/splices.py:stagger_cuts",  # plate id -> its cuts' rulings
        "key_figures/measure.py:crease_kind_counts",  # crease kind -> count
        "structure.py:crease_kind_counts",  # crease kind -> count
        "limits.py:apply",  # the limits asked for (name -> value): keyword arguments
        "scene/draw.py:plate_kinds",  # plate id -> the kind of its creases
        "viz/quadrants.py:quadrant_pairs",  # quadrant (Q1 .. Q4, a figure's columns) -> crease
    ),
}  # fmt: skip

#: The bare ``-> dict`` results left outside the core packages and :data:`NOT_RESULTS`: this
#: number may only fall (convert one, lower it); a new bare dict result fails the test.
REMAINING = 0


def _dict_results(root: Path, packages) -> list:
    """``(path:line name, subscripted)`` of every public function or method annotated a dict
    (``dict``, ``Dict``, ``dict[K, V]``, with or without ``| None`` / ``Optional``) under
    ``root/<package>`` (every ``*.py`` under ``root`` for ``packages`` None) whose name is not a
    document's; ``subscripted`` tells ``dict[K, V]`` from a bare dict."""
    found = []
    folders = [root] if packages is None else [root / p for p in packages]
    for folder in folders:
        for path in sorted(folder.rglob("*.py")):
            for node in nodes(path):
                if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                    continue
                if node.returns is None or node.name in DOCUMENTS:
                    continue
                if node.name.startswith("_") and not node.name.startswith("__"):
                    continue  # private: never crosses a module
                kind = _dict_kind(node.returns)
                if kind is not None:
                    name = f"{path.relative_to(root).as_posix()}:{node.lineno} {node.name}"
                    found.append((name, kind == "subscripted"))
    return found


def _dict_kind(returns: ast.expr):
    """``"bare"`` for ``dict``, ``"subscripted"`` for ``dict[K, V]`` (either optional: ``X |
    None``, ``Optional[X]``), None for any other annotation."""
    if isinstance(returns, ast.Constant) and isinstance(returns.value, str):
        returns = ast.parse(returns.value, mode="eval").body  # a quoted annotation
    if isinstance(returns, ast.BinOp) and isinstance(returns.op, ast.BitOr):
        sides = [returns.left, returns.right]
        none = [s for s in sides if isinstance(s, ast.Constant) and s.value is None]
        returns = next((s for s in sides if s not in none), None) if none else None
    elif (
        isinstance(returns, ast.Subscript)
        and isinstance(returns.value, ast.Name)
        and returns.value.id == "Optional"
    ):
        returns = returns.slice
    if isinstance(returns, ast.Name) and returns.id in ("dict", "Dict"):
        return "bare"
    if (
        isinstance(returns, ast.Subscript)
        and isinstance(returns.value, ast.Name)
        and returns.value.id in ("dict", "Dict")
    ):
        return "subscripted"
    return None


def bare_dict_results(root: Path, packages=CORE) -> list:
    """``path:line name`` of every public function or method annotated ``-> dict`` (or
    ``dict | None``) under ``root/<package>`` (every ``*.py`` under ``root`` for ``packages``
    None) whose name is not a document's."""
    return [name for name, subscripted in _dict_results(root, packages) if not subscripted]


def mapping_results(root: Path, packages=CORE) -> list:
    """The same for the functions annotated ``-> dict[K, V]``: a mapping if it is on the
    ``"mapping"`` list of :data:`NOT_RESULTS`, a bare dict result under another name if not."""
    return [name for name, subscripted in _dict_results(root, packages) if subscripted]


def _key(result: str) -> str:
    """``path:name`` of a ``path:line name`` result."""
    return "{}:{}".format(result.split(":")[0], result.split()[1])


def unlisted(found: list) -> list:
    """The results of :func:`bare_dict_results` not in :data:`NOT_RESULTS` (its mappings
    aside: a bare dict is never a mapping)."""
    listed = {name for kind, names in NOT_RESULTS.items() if kind != "mapping" for name in names}
    return [r for r in found if _key(r) not in listed]


def unlisted_mappings(found: list) -> list:
    """The results of :func:`mapping_results` not on the ``"mapping"`` list."""
    return [r for r in found if _key(r) not in NOT_RESULTS["mapping"]]


def left(root: Path, packages=None) -> list:
    """The dict results that count against :data:`REMAINING`: the bare ones not listed and the
    subscripted ones not listed as mappings."""
    return unlisted(bare_dict_results(root, packages)) + unlisted_mappings(
        mapping_results(root, packages)
    )


def test_the_core_packages_return_typed_results():
    assert bare_dict_results(SRC) == []
    assert unlisted_mappings(mapping_results(SRC)) == []


def test_no_new_bare_dict_result_outside_the_documents_rows_and_messages():
    remaining = left(SRC)
    assert len(remaining) == REMAINING, "\n".join(remaining)


def test_every_listed_document_is_a_dict_function_of_src():
    bare = {_key(r) for r in bare_dict_results(SRC, None)}
    mappings = {_key(r) for r in mapping_results(SRC, None)}
    listed = [name for names in NOT_RESULTS.values() for name in names]
    assert len(listed) == len(set(listed))
    others = [name for kind, names in NOT_RESULTS.items() if kind != "mapping" for name in names]
    assert [name for name in others if name not in bare] == []
    # a mapping is annotated with its key and value types
    assert [name for name in NOT_RESULTS["mapping"] if name not in mappings] == []


def test_the_check_finds_a_bare_dict_result(tmp_path):
    (tmp_path / "model").mkdir()
    (tmp_path / "model" / "a.py").write_text(
        "def round_trip(design) -> dict:\n    return {}\n"
        "def _options() -> dict:\n    return {}\n"
        "class M:\n    def __data__(self) -> dict:\n        return {}\n"
        "    def limits(self) -> dict | None:\n        return None\n"
    )
    assert bare_dict_results(tmp_path, ("model",)) == [
        "model/a.py:1 round_trip",
        "model/a.py:8 limits",
    ]


def test_the_ratchet_counts_a_new_result_and_not_a_listed_one(tmp_path):
    (tmp_path / "explore").mkdir()
    (tmp_path / "explore" / "metrics.py").write_text(
        "def fe_metrics(model) -> dict:\n    return {}\n"
        "def fe_result(model) -> dict:\n    return {}\n"
    )
    assert unlisted(bare_dict_results(tmp_path, None)) == ["explore/metrics.py:3 fe_result"]


def test_a_subscripted_dict_counts_unless_it_is_a_listed_mapping(tmp_path):
    (tmp_path / "scene").mkdir()
    (tmp_path / "scene" / "draw.py").write_text(
        "from typing import Any, Dict, Optional\n"
        "def plate_kinds(structure) -> dict[int, str | None]:\n    return {}\n"
        "def record(structure) -> dict[str, Any]:\n    return {}\n"
        "def record2(structure) -> Optional[Dict[str, float]]:\n    return {}\n"
        "def record3(structure) -> 'dict[str, float] | None':\n    return {}\n"
        "def points(structure) -> list[dict]:\n    return []\n"
    )
    found = mapping_results(tmp_path, None)
    assert found == [
        "scene/draw.py:2 plate_kinds",
        "scene/draw.py:4 record",
        "scene/draw.py:6 record2",
        "scene/draw.py:8 record3",
    ]
    assert bare_dict_results(tmp_path, None) == []
    # a new subscripted dict is counted: only the listed mapping is not
    assert left(tmp_path) == found[1:]
