"""OpenSeesPy backend: ``ASDShellQ4 -corotational`` shells, ``equalDOF`` ties, Newton with cuts.

The model is rebuilt from scratch on every call (OpenSees keeps one global model per process,
so calls must not run concurrently in one process). Choices, measured on the roll-up cantilever
and the folded hinge (see the tests):

* every shell is ``ASDShellQ4`` with ``-corotational`` (the other OpenSees shells are linear or
  drift at large rotation), always given ``-local`` = the element's material direction 1
  projected onto its plane, so the element frame (and the output frame) is known: e1 = that
  direction, e3 = ``(x2 - x0) x (x3 - x1)``, e2 = e3 x e1;
* isotropic sections are ``ElasticMembranePlateSection``; orthotropic ones integrate an
  ``ElasticOrthotropic`` 3-D material condensed to plane stress (``PlateFiber``) through the
  thickness (``section PlateFiber``), directions 1, 2 along e1, e2;
* rigid ties are ``equalDOF`` on the three translations, grouped so that every group has one
  retained node, the prescribed one if any (so the Transformation handler never sees a prescribed
  constrained DOF), reactions summed over the group; spring ties and hinge springs are
  ``zeroLength`` elements in global axes;
* loads and prescribed displacements are re-applied at every sub-step (one ``Plain`` pattern with
  a ``Constant`` series), so any NaN pattern and any interpolation is exact;
* section forces come from ``eleResponse(e, 'stresses')``: per Gauss point
  ``[N11, N22, N12, M11, M22, M12, Q13, Q23]`` in the element frame. With ``-local`` given, these
  match our convention with no change of sign: ``M11`` bends the fibres along e1 and is positive
  when the top (+e3) surface is in tension (checked by a cantilever under a known end moment,
  rotated frames and an orthotropic plate in ``tests/test_fea_engine_opensees.py``). Without
  ``-local`` OpenSees picks its own in-plane axes, which is why moments may *look* named by
  the axis they act about.

OpenSeesPy prints "Process 0 Terminating" on stderr when the interpreter exits, from C after
Python's own exit handlers; once it is imported, an exit handler points stderr (file descriptor
2) at the null device after flushing Python's streams, so the message never reaches the user.
"""

from __future__ import annotations

import atexit
import importlib
import os
import sys
import time

import numpy as np

from compas_ccu.fea.problem import FEError, FEProblem, FEResult, buckling_steps
from compas_ccu.tolerances import DIVISION_FLOOR

__all__ = ["available", "solve"]

ENGINE = "opensees"

# tried in turn on every (sub-)step before it is cut
ALGORITHMS = ("Newton", "KrylovNewton")

# sparse LU; SparseGEN (SuperLU) crashed the process when free DOFs changed, ProfileSPD needs a
# symmetric tangent (the corotational one is not)
SYSTEM = "UmfPack"

# smallest |projection| of a material direction on an element plane that still defines e1
_MIN_IN_PLANE = 1e-3


def _null_stderr() -> None:
    """Flush Python's streams and point file descriptor 2 at the null device (at exit)."""
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):  # closed, or no stream
            pass
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 2)
        os.close(null)
    except OSError:  # pragma: no cover - no null device
        pass


_QUIET_EXIT = []  # the exit handler, once registered


def _quiet_exit() -> None:
    """Keep OpenSees' "Process 0 Terminating" (printed at exit) from the user's terminal."""
    if not _QUIET_EXIT:
        _QUIET_EXIT.append(atexit.register(_null_stderr))


def _import_opensees():
    """The ``openseespy.opensees`` module, or an :class:`FEError` that says why not."""
    ok, info = available()
    if not ok:
        raise FEError(f"FE engine 'opensees' is not available: {info}")
    return importlib.import_module("openseespy.opensees")


def available() -> tuple:
    """Whether OpenSeesPy imports.

    Returns
    -------
    tuple of (bool, str)
        ``(True, version)`` or ``(False, reason)``; a missing system BLAS (Debian's
        ``libblas3``, which the OpenSeesPy wheel links against) is named as such.
    """
    try:
        ops = importlib.import_module("openseespy.opensees")
        _quiet_exit()
    except (ImportError, RuntimeError, OSError) as exc:
        text = str(exc)
        if "blas" in text.lower() or "lapack" in text.lower():
            return False, (
                f"openseespy cannot load a system BLAS/LAPACK library ({text}); install "
                "Debian's libblas3 and liblapack3 (apt-get install libblas3 liblapack3)"
            )
        return False, f"openseespy does not import ({type(exc).__name__}: {text})"
    try:
        from importlib.metadata import version

        return True, version("openseespy")
    except Exception:  # the version is informative only
        return True, str(getattr(ops, "version", lambda: "unknown")())


def _element_axes(problem: FEProblem) -> np.ndarray:
    """(E, 3) local e1 of every element: its material direction projected onto its plane.

    Isotropic elements whose direction is (nearly) normal to them fall back to the side
    ``x1 - x0``; for an orthotropic model that is an error.
    """
    x = problem.nodes[problem.elements]
    normal = np.cross(x[:, 2] - x[:, 0], x[:, 3] - x[:, 1])
    length = np.linalg.norm(normal, axis=1)
    if np.any(length <= 0.0):
        bad = int(np.flatnonzero(length <= 0.0)[0])
        raise FEError(f"element {bad} is degenerate (its diagonals are parallel)")
    normal /= length[:, None]

    def project(v):
        v = v - np.einsum("ij,ij->i", v, normal)[:, None] * normal
        return v, np.linalg.norm(v, axis=1)

    axes, size = project(np.asarray(problem.directions, dtype=float))
    weak = size < _MIN_IN_PLANE * np.maximum(
        np.linalg.norm(problem.directions, axis=1), DIVISION_FLOOR
    )
    if np.any(weak):
        if problem.orthotropic:
            bad = int(np.flatnonzero(weak)[0])
            raise FEError(
                f"material direction {problem.directions[bad].tolist()} of element {bad} is "
                "(nearly) normal to the element: an orthotropic model needs in-plane directions"
            )
        side, side_size = project(x[:, 1] - x[:, 0])
        axes[weak], size[weak] = side[weak], side_size[weak]
    return axes / size[:, None]


def _tie_groups(problem: FEProblem) -> dict:
    """Groups of rigidly tied nodes, each with one retained node (the prescribed one if any).

    Returns
    -------
    dict
        Retained node -> sorted list of its group's nodes (the retained node included).
    """
    if problem.hinge_translational_stiffness is not None or len(problem.ties) == 0:
        return {}
    parent = {}

    def root(a):
        parent.setdefault(a, a)
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for master, slave in problem.ties.tolist():
        if master == slave:
            raise FEError(f"tie ({master}, {slave}) ties a node to itself")
        parent[root(slave)] = root(master)
    groups = {}
    for node in parent:
        groups.setdefault(root(node), []).append(node)
    first_master = {}
    for master, _ in problem.ties.tolist():
        first_master.setdefault(root(master), master)
    fixed = set(problem.fixed.tolist())
    members = {}
    for key, nodes in groups.items():
        prescribed = sorted(fixed.intersection(nodes))
        if len(prescribed) > 1:
            raise FEError(
                f"nodes {prescribed} are tied together (translations equal) and all prescribed: "
                "prescribe one of them only"
            )
        keep = prescribed[0] if prescribed else first_master[key]
        members[keep] = sorted(nodes)
    return members


class _Model:
    """One OpenSees model of an :class:`FEProblem` and the means to step it."""

    def __init__(self, ops, problem: FEProblem, tolerance: float, max_iterations: int):
        self.ops = ops
        self.problem = problem
        self.members = _tie_groups(problem)
        self.pattern = None
        self.series = 0
        self.free = None
        self._build()
        ops.constraints("Transformation")
        ops.numberer("RCM")
        ops.system(SYSTEM)
        ops.test("NormDispIncr", float(tolerance), int(max_iterations), 0)
        ops.algorithm(ALGORITHMS[0])
        ops.integrator("LoadControl", 1.0)
        ops.analysis("Static")

    def _build(self):
        ops, p = self.ops, self.problem
        if p.offsets is not None and np.any(p.offsets != 0.0):
            raise FEError(
                "eccentric shells (axis-shift hinges, offsets up to "
                f"{float(np.abs(p.offsets).max()):.4g} m) need engine 'kratos' (its shell "
                "sections take an offset); the opensees engine models hinges on the "
                "mid-surfaces only"
            )
        ops.model("basic", "-ndm", 3, "-ndf", 6)
        for i, xyz in enumerate(p.nodes.tolist()):
            ops.node(i + 1, *xyz)
        mat = p.material_used
        if p.orthotropic:
            ops.nDMaterial(
                "ElasticOrthotropic",
                1,
                mat.E1,
                mat.E2,
                mat.E2,
                mat.nu12,
                0.0,
                0.0,
                mat.G12,
                mat.G12,
                mat.G12,
                mat.density,
            )
            ops.nDMaterial("PlateFiber", 2, 1)
            ops.section("PlateFiber", 1, 2, p.thickness)
        else:
            ops.section(
                "ElasticMembranePlateSection", 1, mat.E1, mat.nu12, p.thickness, mat.density
            )
        axes = _element_axes(p)
        for e, (quad, axis) in enumerate(zip(p.elements.tolist(), axes.tolist())):
            nodes = [n + 1 for n in quad]
            ops.element("ASDShellQ4", e + 1, *nodes, 1, "-corotational", "-local", *axis)
        tag = len(p.elements)
        for keep, nodes in self.members.items():
            for node in nodes:
                if node != keep:
                    ops.equalDOF(keep + 1, node + 1, 1, 2, 3)
        k_line = p.hinge_translational_stiffness
        for (a, b), length in zip(p.ties.tolist(), p.tie_lengths.tolist()):
            springs = []
            if k_line is not None:
                springs.append(((1, 2, 3), k_line * length))
            if p.hinge_stiffness > 0.0:
                springs.append(((4, 5, 6), p.hinge_stiffness * length))
            for dofs, k in springs:
                tag += 1
                ops.uniaxialMaterial("Elastic", tag, k)
                mats = [tag, tag, tag]
                ops.element("zeroLength", tag, a + 1, b + 1, "-mat", *mats, "-dir", *dofs)
        for (a, b), k in zip(p.springs.tolist(), p.spring_stiffness.tolist()):
            tag += 1
            mats = []
            for j, kj in enumerate(k):
                ops.uniaxialMaterial("Elastic", tag + j, kj)
                mats.append(tag + j)
            ops.element("zeroLength", tag, a + 1, b + 1, "-mat", *mats, "-dir", 1, 2, 3)
            tag += 2
        for node in p.fixed_rotations.tolist():
            ops.fix(node + 1, 0, 0, 0, 1, 1, 1)

    def apply(self, t: float):
        """Replace the loads and prescribed displacements by their values at pseudo-time t."""
        ops, p = self.ops, self.problem
        if self.pattern is not None:
            ops.remove("loadPattern", self.pattern)
        self.series += 1
        self.pattern = self.series
        ops.timeSeries("Constant", self.series)
        ops.pattern("Plain", self.pattern, self.series)
        loads = p.loads_at(t)
        for node in np.flatnonzero(np.any(loads != 0.0, axis=1)).tolist():
            ops.load(node + 1, *loads[node].tolist())
        prescribed = p.prescribed_at(t)
        free = np.isnan(prescribed)
        if self.free is not None and not np.array_equal(free, self.free):
            # UmfPack fails to resize itself when the number of equations changes: renew it
            ops.system(SYSTEM)
        self.free = free
        for node, values in zip(p.fixed.tolist(), prescribed.tolist()):
            for dof, value in enumerate(values):
                if not np.isnan(value):
                    ops.sp(node + 1, dof + 1, value)

    def advance(self, t: float) -> tuple:
        """Try one increment to pseudo-time t: (converged, iterations, last norm).

        Newton first; if it fails, KrylovNewton from the same state (Newton converges only
        linearly when large membrane forces build up, see the module notes).
        """
        self.apply(t)
        total, last = 0, float("nan")
        for algorithm in ALGORITHMS:
            self.ops.algorithm(algorithm)
            ok = self.ops.analyze(1) == 0
            count = int(self.ops.testIter())
            norms = self.ops.testNorm()
            if len(norms) and count > 0:
                last = float(norms[min(count, len(norms)) - 1])
            total += count
            if ok:
                return True, total, last
        return False, total, last

    def state(self, t: float) -> tuple:
        """Displacements (N, 3), rotations (N, 3), forces (E, 6), reactions (F, 3) now."""
        ops, p = self.ops, self.problem
        disp = np.array([ops.nodeDisp(i + 1) for i in range(len(p.nodes))], dtype=float)
        forces = np.empty((len(p.elements), 6))
        for e in range(len(p.elements)):
            stress = np.asarray(ops.eleResponse(e + 1, "stresses"), dtype=float)
            forces[e] = stress.reshape(4, -1)[:, :6].mean(axis=0)
        ops.reactions()
        reactions = np.zeros((len(p.fixed), 3))
        for i, node in enumerate(p.fixed.tolist()):
            for member in self.members.get(node, [node]):
                reactions[i] += ops.nodeReaction(member + 1)[:3]
        reactions[np.isnan(p.prescribed_at(t))] = 0.0
        return disp[:, :3], disp[:, 3:6], forces, reactions, self.tie_forces(t)

    def tie_forces(self, t: float) -> np.ndarray:
        """(T, 3) force every tie passes to its slave: its elements' internal force, less loads."""
        ops, p = self.ops, self.problem
        out = np.zeros((len(p.ties), 3))
        if not hasattr(self, "_slave_elements"):
            slave = {int(b): k for k, b in enumerate(p.ties[:, 1])}
            self._slave_elements = [
                (e, j, slave[int(i)])
                for e, quad in enumerate(p.elements)
                for j, i in enumerate(quad)
                if int(i) in slave
            ]
        cache = {}
        for e, j, k in self._slave_elements:
            if e not in cache:
                cache[e] = np.asarray(ops.eleResponse(e + 1, "forces"), dtype=float)
            out[k] += cache[e][6 * j : 6 * j + 3]
        if len(p.ties):
            out -= p.loads_at(t)[p.ties[:, 1], :3]
        return out


def solve(
    problem: FEProblem,
    *,
    tolerance: float,
    max_iterations: int,
    max_cuts: int,
    buckling=False,
) -> FEResult:
    """Solve ``problem`` geometrically nonlinearly with OpenSeesPy, step by step.

    Every step i = 1 .. S is first tried in one Newton increment; when Newton does not reach
    ``tolerance`` (displacement-increment norm) within ``max_iterations``, the sub-step is
    halved, down to ``1 / 2**max_cuts`` of a step (and grown again after two successes).

    Parameters
    ----------
    problem : FEProblem
    tolerance : float
        Absolute tolerance of the displacement-increment norm, m (1e-6 works well).
    max_iterations : int
        Newton iterations per (sub-)step.
    max_cuts : int
        Halvings of a step allowed.

    Returns
    -------
    FEResult
        The state at the end of every converged step; ``converged`` is False with
        ``failed_step``, ``residual`` and a ``message`` if a step failed at the smallest
        sub-step (the rows then stop before that step).
    """
    if max_cuts < 0 or max_iterations < 1 or not (tolerance > 0.0):
        raise FEError(
            f"need tolerance > 0, max_iterations >= 1 and max_cuts >= 0, got {tolerance!r}, "
            f"{max_iterations!r}, {max_cuts!r}"
        )
    ops = _import_opensees()
    start = time.perf_counter()
    rows = {
        "displacements": [],
        "rotations": [],
        "forces": [],
        "reactions": [],
        "tie_forces": [],
    }
    iterations, cuts = [], 0
    failed_step, residual, message = None, None, ""
    ops.wipe()
    ops.logFile(os.devnull, "-noEcho")
    try:
        model = _Model(ops, problem, tolerance, max_iterations)
        t = 0.0
        for step in range(1, problem.steps + 1):
            level, streak, count = 0, 0, 0
            while t < step:
                t_next = min(t + 0.5**level, float(step))
                ok, n, last = model.advance(t_next)
                count += n
                if ok:
                    t = t_next
                    streak += 1
                    if level > 0 and streak >= 2:
                        level, streak = level - 1, 0
                    continue
                if level >= max_cuts:
                    failed_step, residual = step, last
                    message = (
                        f"step {step} of {problem.steps} did not converge at pseudo-time "
                        f"{t:.6g} -> {t_next:.6g} after {max_cuts} cut(s) (sub-step 1/"
                        f"{2**level} of a step): last displacement-increment norm "
                        f"{last:.3e} > tolerance {tolerance:.1e} in {max_iterations} iterations"
                    )
                    break
                level, streak, cuts = level + 1, 0, cuts + 1
            if failed_step is not None:
                break
            for key, value in zip(rows, model.state(t)):
                rows[key].append(value)
            iterations.append(count)
    finally:
        ops.wipe()
    n, e, f = len(problem.nodes), len(problem.elements), len(problem.fixed)
    shapes = {
        "displacements": (n, 3),
        "rotations": (n, 3),
        "forces": (e, 6),
        "reactions": (f, 3),
        "tie_forces": (len(problem.ties), 3),
    }
    arrays = {
        key: np.array(value) if value else np.zeros((0, *shapes[key]))
        for key, value in rows.items()
    }
    converged = failed_step is None
    if converged:
        message = f"converged: {problem.steps} step(s), {sum(iterations)} iterations, {cuts} cut(s)"
    note = "linear buckling needs the tangent matrix: available with the kratos engine only"
    wanted = buckling_steps(buckling, problem.steps)
    return FEResult(
        engine=ENGINE,
        buckling_note=note if wanted else "",
        buckling={k: (None, note) for k in sorted(wanted) if k <= len(iterations)},
        converged=converged,
        failed_step=failed_step,
        residual=residual,
        iterations=np.array(iterations, dtype=int),
        cuts=cuts,
        wall_time=time.perf_counter() - start,
        message=message,
        **arrays,
    )
