"""The Kratos model of an :class:`~compas_ccu.fea.problem.FEProblem`, for the :mod:`.kratos`
engine: the model part (nodes with their DOFs, the shell elements with their offset sections,
the hinges as master–slave ties or springs, the springs, the point-load conditions, the fixed
rotations) and the Newton–Raphson strategy that solves it.

Ids are 1-based: node ``i`` of the problem is Kratos node ``i + 1``, shell ``e`` element
``e + 1``; the hinge and spring elements follow the shells.
"""

from __future__ import annotations

import json

import numpy as np

from compas_ccu.fea.problem import FEError

__all__ = [
    "ELEMENT",
    "OFFSET_PROPERTIES",
    "model_part",
    "add_dofs",
    "add_shells",
    "add_hinges",
    "add_load_conditions",
    "fix_rotations",
    "newton_strategy",
]

ELEMENT = "LegacyThickShellCorotationalElement3D4N"
#: The first property id of the element sections with an offset (after hinges and springs).
OFFSET_PROPERTIES = 1_000_000


def model_part(KM, SMA, problem) -> tuple:
    """The Kratos model of ``problem`` and its model part ``"ccu"``, built.

    Parameters
    ----------
    KM, SMA : module
        KratosMultiphysics and its StructuralMechanicsApplication.
    problem : FEProblem

    Returns
    -------
    model : KratosMultiphysics.Model
        Owns the model part: keep it alive as long as the part.
    mp : KratosMultiphysics.ModelPart
    carried : list of (int, int)
        (prescribed master, tied node) of every rigid hinge at a prescribed node
        (:func:`add_hinges`).
    loaded : (l,) int
        The nodes with a point-load condition (:func:`add_load_conditions`).

    Raises
    ------
    FEError
        Orthotropic plates (no law in the Kratos wheels), or a rigid hinge between two
        prescribed nodes.
    """
    model = KM.Model()
    mp = model.CreateModelPart("ccu")
    mp.SetBufferSize(2)
    for var in (
        KM.DISPLACEMENT,
        KM.ROTATION,
        KM.REACTION,
        KM.REACTION_MOMENT,
        SMA.POINT_LOAD,
        SMA.POINT_MOMENT,
    ):
        mp.AddNodalSolutionStepVariable(var)
    mp.ProcessInfo[KM.DOMAIN_SIZE] = 3
    for i, (x, y, z) in enumerate(problem.nodes):
        mp.CreateNewNode(i + 1, float(x), float(y), float(z))
    add_dofs(KM, mp)
    add_shells(KM, SMA, mp, problem)
    carried = add_hinges(KM, SMA, mp, problem)
    loaded = add_load_conditions(mp, problem)
    fix_rotations(KM, mp, problem)
    return model, mp, carried, loaded


def add_dofs(KM, mp) -> None:
    """The three translations and three rotations of every node, with their reactions."""
    for c in "XYZ":
        KM.VariableUtils().AddDof(
            getattr(KM, "DISPLACEMENT_" + c), getattr(KM, "REACTION_" + c), mp
        )
        KM.VariableUtils().AddDof(
            getattr(KM, "ROTATION_" + c), getattr(KM, "REACTION_MOMENT_" + c), mp
        )


def add_shells(KM, SMA, mp, p) -> None:
    """The shell elements (:data:`ELEMENT`) with a plane-stress linear elastic law; one
    property per offset value (its ``SHELL_OFFSET``) if the problem has offsets."""
    m = p.material_used
    props = mp.GetProperties()[1]
    props.SetValue(KM.THICKNESS, p.thickness)
    props.SetValue(KM.DENSITY, m.density)
    if p.orthotropic:
        raise FEError(
            "orthotropic plates are not available with the Kratos 10.4.4 wheels (no "
            "orthotropic plane-stress law is shipped); use engine 'opensees' for them"
        )
    props.SetValue(KM.YOUNG_MODULUS, m.E1)
    props.SetValue(KM.POISSON_RATIO, m.nu12)
    props.SetValue(KM.CONSTITUTIVE_LAW, SMA.LinearElasticPlaneStress2DLaw())
    chosen = [props] * len(p.elements)
    if p.offsets is not None:  # one property per offset value: the section's SHELL_OFFSET
        values, which = np.unique(np.round(p.offsets, 12), return_inverse=True)
        table = []
        for k, value in enumerate(values.tolist()):
            q = mp.GetProperties()[OFFSET_PROPERTIES + k]
            q.SetValue(KM.THICKNESS, p.thickness)
            q.SetValue(KM.DENSITY, m.density)
            q.SetValue(KM.YOUNG_MODULUS, m.E1)
            q.SetValue(KM.POISSON_RATIO, m.nu12)
            q.SetValue(KM.CONSTITUTIVE_LAW, SMA.LinearElasticPlaneStress2DLaw())
            q.SetValue(SMA.SHELL_OFFSET, value)
            table.append(q)
        chosen = [table[k] for k in which.tolist()]
    for e, quad in enumerate(p.elements):
        mp.CreateNewElement(ELEMENT, e + 1, [int(i) + 1 for i in quad], chosen[e])


def add_hinges(KM, SMA, mp, p) -> list:
    """The hinge ties (master–slave constraints on the translations if rigid, and spring
    elements for their translational and rotational stiffness) and the springs.

    Returns
    -------
    list of (int, int)
        (prescribed master, tied node) of every rigid tie at a prescribed node: the tied
        node's force is part of the master's reaction. A prescribed slave is made the master.
    """
    rigid = p.hinge_translational_stiffness is None
    comps = ("X", "Y", "Z")
    cid, eid = 1, len(p.elements) + 1
    prescribed = set(map(int, p.fixed))
    carried = []  # (prescribed master, tied node): its force is part of the reaction
    for t, (a, b) in enumerate(p.ties):
        if rigid and int(b) in prescribed:
            if int(a) in prescribed:
                raise FEError(
                    f"nodes {[int(a), int(b)]} are tied together (translations equal) and "
                    "all prescribed: prescribe one of them only"
                )
            a, b = b, a  # a prescribed slave would be overridden: make it the master
        if rigid and int(a) in prescribed:
            carried.append((int(a), int(b)))
        na, nb = mp.GetNode(int(a) + 1), mp.GetNode(int(b) + 1)
        if rigid:
            for c in comps:
                var = getattr(KM, "DISPLACEMENT_" + c)
                mp.CreateNewMasterSlaveConstraint(
                    "LinearMasterSlaveConstraint", cid, na, var, nb, var, 1.0, 0.0
                )
                cid += 1
        length = float(p.tie_lengths[t])
        kt = 0.0 if rigid else p.hinge_translational_stiffness * length
        kr = p.hinge_stiffness * length
        if kt > 0.0 or kr > 0.0:
            props = mp.GetProperties()[t + 2]
            el = mp.CreateNewElement("SpringDamperElement3D", eid, [int(a) + 1, int(b) + 1], props)
            # the spring element reads its stiffness from the element's own data
            el.SetValue(SMA.NODAL_DISPLACEMENT_STIFFNESS, KM.Array3([kt, kt, kt]))
            el.SetValue(SMA.NODAL_ROTATIONAL_STIFFNESS, KM.Array3([kr, kr, kr]))
            eid += 1
    for s, ((a, b), k) in enumerate(zip(p.springs, p.spring_stiffness)):
        props = mp.GetProperties()[len(p.ties) + 2 + s]
        el = mp.CreateNewElement("SpringDamperElement3D", eid, [int(a) + 1, int(b) + 1], props)
        el.SetValue(SMA.NODAL_DISPLACEMENT_STIFFNESS, KM.Array3([float(x) for x in k]))
        el.SetValue(SMA.NODAL_ROTATIONAL_STIFFNESS, KM.Array3([0.0, 0.0, 0.0]))
        eid += 1
    return carried


def add_load_conditions(mp, p) -> np.ndarray:
    """A point-load and a point-moment condition at every node loaded in any load pattern;
    returns those nodes, (l,) int."""
    loaded = np.zeros(len(p.nodes), dtype=bool)
    for pat in p.patterns:
        loaded |= np.any(pat.loads != 0.0, axis=1)
    loaded = np.flatnonzero(loaded)
    props = mp.GetProperties()[0]
    for c, i in enumerate(loaded):
        mp.CreateNewCondition("PointLoadCondition3D1N", 2 * c + 1, [int(i) + 1], props)
        mp.CreateNewCondition("PointMomentCondition3D1N", 2 * c + 2, [int(i) + 1], props)
    return loaded


def fix_rotations(KM, mp, p) -> None:
    """Fix the three rotations of the problem's ``fixed_rotations`` nodes."""
    for i in p.fixed_rotations:
        node = mp.GetNode(int(i) + 1)
        for c in "XYZ":
            node.Fix(getattr(KM, "ROTATION_" + c))


def newton_strategy(KM, LSA, mp, tolerance: float, max_iterations: int) -> tuple:
    """The Newton–Raphson strategy of the model part, initialised.

    Sparse LU; displacement criterion (``tolerance``, absolute ``tolerance * 1e-3``);
    incremental update static scheme with the old stiffness in the first iteration (Newton
    diverges in the first steps of prescribed motion otherwise); reactions not computed (summed
    from the element forces by the engine).

    Returns
    -------
    strategy, scheme, builder, criterion
    """
    solver = LSA.SparseLUSolver()
    scheme = KM.ResidualBasedIncrementalUpdateStaticScheme()
    criterion = KM.DisplacementCriteria(tolerance, tolerance * 1e-3)
    criterion.SetEchoLevel(0)
    builder = KM.ResidualBasedBlockBuilderAndSolver(solver)
    settings = KM.Parameters(
        json.dumps(
            {
                "max_iteration": int(max_iterations),
                "compute_reactions": False,  # summed from element forces, see nodal_forces
                "reform_dofs_at_each_step": False,
                "move_mesh_flag": True,
                "use_old_stiffness_in_first_iteration": True,
            }
        )
    )
    strategy = KM.ResidualBasedNewtonRaphsonStrategy(mp, scheme, criterion, builder, settings)
    strategy.SetEchoLevel(0)
    strategy.Initialize()
    return strategy, scheme, builder, criterion
