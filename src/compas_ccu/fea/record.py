"""The last validation of a design file (for ``ccu info``) and the agreement of two engines.

Validations are remembered in the user's cache folder (``$CCU_CACHE_DIR``, else
``$XDG_CACHE_HOME/compas_ccu`` or ``~/.cache/compas_ccu``), keyed by the SHA-256 of the design
file's contents: a changed design shows no stale validation.
"""

from __future__ import annotations

import datetime
import hashlib
import json
import os
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from compas_ccu.fea.stresses import principal
from compas_ccu.outputs import write_json
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = ["cache_folder", "remember", "last_validation", "agreement", "EngineAgreement"]


def cache_folder() -> Path:
    root = os.environ.get("CCU_CACHE_DIR")
    if root:
        return Path(root)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "compas_ccu"


def _key(design: str) -> str:
    return hashlib.sha256(Path(design).read_bytes()).hexdigest()


def remember(design: str, summary: dict, out) -> Path:
    """Store the headline of a validation summary for the design file ``design``."""
    keys = ("design", "engine", "mode", "alpha", "span", "deviation", "stresses", "checks")
    keys += ("plates",)
    record = {k: summary.get(k) for k in keys}
    record["deviation"] = {
        k: summary["deviation"][k] for k in ("max_percent", "mean_percent", "max_m")
    }
    record["when"] = datetime.datetime.now().isoformat(timespec="seconds")
    record["out"] = str(Path(out).resolve())
    if "agreement" in summary:
        record["agreement"] = summary["agreement"]
    folder = cache_folder() / "validations"
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / (_key(design) + ".json")
    write_json(path, record)
    return path


def last_validation(design: str) -> dict | None:
    """The stored record of the last validation of this design file's contents, or None."""
    path = cache_folder() / "validations" / (_key(design) + ".json")
    if not path.exists():
        return None
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


@dataclass(frozen=True)
class EngineAgreement:
    """How closely two validations of the same model agree at the target state
    (:func:`agreement`; ``validation.json`` ``agreement``). Pairs are ``[a, b]``.

    Attributes
    ----------
    engines : list of str
        (2,) the two engines' names.
    position_max_m : float
        The largest node position difference, m.
    position_max_percent : float
        The same in % of the span.
    deviation_max_percent : list of float
        (2,) each validation's peak deviation from the kinematic model, % of the span.
    deviation_max_relative : float
        The relative difference of the two peak deviations.
    moment_max_Nm_per_m : list of float
        (2,) each validation's peak principal bending moment, N m/m.
    moment_max_relative : float
        The relative difference of the two peak moments.
    wall_time_s : list of float
        (2,) each engine's wall time, s.
    """

    engines: list
    position_max_m: float
    position_max_percent: float
    deviation_max_percent: list
    deviation_max_relative: float
    moment_max_Nm_per_m: list
    moment_max_relative: float
    wall_time_s: list

    def to_dict(self) -> dict:
        """Plain data (strict JSON), the fields in order (copies)."""
        return asdict(self)


def agreement(a, b) -> EngineAgreement:
    """How closely two validations of the same model agree (e.g. Kratos and OpenSees).

    The largest node position difference in % of span, and relative differences of the peak
    deviation and the peak moment at the target state (:class:`EngineAgreement`).
    """
    k = a.deployment_steps - 1
    span = float(a.spans[k])
    dx = np.linalg.norm(a.positions[k] - b.positions[k], axis=1).max()
    da, db = a.deviation[k].max(), b.deviation[k].max()
    ma = np.abs(principal(a.result.forces[k][:, 3:])).max()
    mb = np.abs(principal(b.result.forces[k][:, 3:])).max()

    def rel(x, y):
        return float(abs(x - y) / max(abs(x), abs(y), DIVISION_FLOOR))

    return EngineAgreement(
        engines=[a.result.engine, b.result.engine],
        position_max_m=float(dx),
        position_max_percent=float(100.0 * dx / span),
        deviation_max_percent=[float(100 * da / span), float(100 * db / span)],
        deviation_max_relative=rel(da, db),
        moment_max_Nm_per_m=[float(ma), float(mb)],
        moment_max_relative=rel(ma, mb),
        wall_time_s=[float(a.result.wall_time), float(b.result.wall_time)],
    )
