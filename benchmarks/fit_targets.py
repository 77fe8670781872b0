"""Targets no CCU design matches exactly: the achievable deviation against the number of plates
(issue 30, docs/fit.md "Targets no design matches").

Run from the repository root::

    .venv/bin/python benchmarks/fit_targets.py [--plates 4,6,8,10,14] [--quick]

1. **Barrel vault** (analytic): the circular cylinder through a 2.5 m chord with 1.0 m rise
   (radius 1.28125 m, axis along world y at height rise - radius), 1.2 m long (|y| <= 0.6 m),
   20,000 points drawn evenly over its area with their exact normals. Fitted with
   examples/vault.toml (parallel layout, arc crease) at each plate count: free ``crease.span``
   2:3 m, ``crease.rise`` 0.7:1.3 m and ``layout.spacing`` 0.6:1.4 x 1.2 m / plates (the start
   1.2 m / plates: the vault as long as the target).
2. **Funicular dome** (compas_tna, an independent form finding, where it installs): the thrust
   network of a circular radial form diagram (radius 1.9 m, 16 hoops, 48 parallels, supports
   on the rim, horizontal equilibrium by ``horizontal_nodal_numpy``, self-weight, highest point
   1.2 m by ``vertical_from_zmax``), its half x >= 0 without the crown disc r < 0.25 m (a radial
   CCU dome's creases cannot reach its axis) sampled 20,000 points over its triangles. Fitted
   with the radial dome preset (``ccu new --preset dome``): the spline crease through 7 points
   of the network's meridian (so the leading crease lies on the target), the half turn split
   into ``layout.angle`` = 180 deg / plates. Without
   compas_tna the dome rows are left out (the script says so); the project's own funicular
   curves are not used: they are not independent of the designs fitted.

Both are fitted twice: with the deployment angle held at 30 deg (the examples' corrugation)
and with it free within 10:60 deg (:data:`FREE_ALPHA`). Each row: rms, max (every target point
to the fitted plates) and Hausdorff distance in mm, the fitted α and the fitted design's first
collision along its deployment (``collision_free_alpha``), the other fitted values, models built
and CPU seconds (one core). ``--quick`` uses 5,000 target points.
"""

import os

os.environ["OMP_NUM_THREADS"] = "1"
os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import subprocess  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from compas_ccu.design import Design, load_design  # noqa: E402
from compas_ccu.design.presets import PRESET_DIR  # noqa: E402
from compas_ccu.fit import PointSet, fit_design, free_keys  # noqa: E402
from compas_ccu.model import CCUModel  # noqa: E402

VAULT = "examples/vault.toml"
#: Barrel vault target: chord, rise and length, m.
SPAN, RISE, LENGTH = 2.5, 1.0, 1.2
#: Dome target: rim radius, crown height, the crown disc left out, m.
DOME_RADIUS, DOME_HEIGHT, DOME_HOLE = 1.9, 1.2, 0.25
#: The deployment angle of the held rows, deg (the examples' corrugation).
HELD = 30.0
#: Bounds of the deployment angle where it is free, deg: below the first collision of every
#: design in the table (each row prints its fitted design's first collision; the dome with 4
#: plates designed at 65 deg or more collides at once).
FREE_ALPHA = (10.0, 60.0)


def barrel_vault(count: int, seed: int = 0) -> PointSet:
    """The analytic barrel vault (module docstring), ``count`` points evenly over its area."""
    radius = (SPAN**2 / 4.0 + RISE**2) / (2.0 * RISE)
    centre_z = RISE - radius
    half = np.arcsin(SPAN / 2.0 / radius)  # the half angle of the arc above z = 0
    rng = np.random.default_rng(seed)
    theta = rng.uniform(-half, half, count)  # even in angle = even over the cylinder's area
    y = rng.uniform(-LENGTH / 2.0, LENGTH / 2.0, count)
    normals = np.column_stack([np.sin(theta), np.zeros(count), np.cos(theta)])
    points = np.column_stack([radius * np.sin(theta), y, centre_z + radius * np.cos(theta)])
    return PointSet(points, normals, "barrel vault", "mesh")


def tna_dome():
    """The compas_tna thrust network (module docstring): its vertices (n, 3) and triangles
    (m, 3), or None where compas_tna does not import."""
    try:
        from compas_tna.diagrams import ForceDiagram, FormDiagram
        from compas_tna.equilibrium import horizontal_nodal_numpy, vertical_from_zmax
    except ImportError:
        return None
    form = FormDiagram.create_circular_radial(
        center=(0.0, 0.0), radius=DOME_RADIUS, n_hoops=16, n_parallels=48
    )
    form.update_boundaries()
    force = ForceDiagram.from_formdiagram(form)
    horizontal_nodal_numpy(form, force, kmax=500)
    vertical_from_zmax(form, DOME_HEIGHT)
    keys = list(form.vertices())
    index = {k: i for i, k in enumerate(keys)}
    xyz = np.array([form.vertex_coordinates(k) for k in keys], dtype=float)
    tris = []
    for f in form.faces():
        ids = [index[k] for k in form.face_vertices(f)]
        tris += [[ids[0], ids[i], ids[i + 1]] for i in range(1, len(ids) - 1)]
    return xyz, np.array(tris)


def dome_target(xyz, tris, count: int, seed: int = 0) -> PointSet:
    """The half x >= 0 of the network without the crown disc, ``count`` points over its
    triangles by area (each with its triangle's normal, pointing up)."""
    a, b, c = (xyz[tris[:, i]] for i in range(3))
    n = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(n, axis=1)
    rng = np.random.default_rng(seed)
    pts, nrm = [], []
    while sum(len(p) for p in pts) < count:
        t = rng.choice(len(tris), size=2 * count, p=area / area.sum())
        u, v = rng.random(2 * count), rng.random(2 * count)
        flip = u + v > 1.0
        u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
        p = a[t] + u[:, None] * (b[t] - a[t]) + v[:, None] * (c[t] - a[t])
        keep = (p[:, 0] >= 0.0) & (np.hypot(p[:, 0], p[:, 1]) >= DOME_HOLE)
        pts.append(p[keep])
        nrm.append(n[t][keep])
    points = np.concatenate(pts)[:count]
    normals = np.concatenate(nrm)[:count]
    normals = normals / np.linalg.norm(normals, axis=1)[:, None]
    normals *= np.sign(normals[:, 2:3] + 1e-12)
    return PointSet(points, normals, "funicular dome", "mesh")


def meridian(xyz, count: int = 7):
    """``count`` points [r, z] of the network's meridian from the crown disc's edge to the
    rim (z interpolated over the radius of the vertices on the +x radial line)."""
    on = (np.abs(xyz[:, 1]) < 1e-9) & (xyz[:, 0] >= -1e-9)
    r, z = xyz[on, 0], xyz[on, 2]
    order = np.argsort(r)
    radii = np.linspace(DOME_HOLE, DOME_RADIUS, count)
    return [[float(x), float(np.interp(x, r[order], z[order]))] for x in radii]


def vault_base(plates: int, alpha=None) -> tuple:
    """examples/vault.toml with ``plates`` plates as long as the target, and its free keys:
    span, rise, spacing and (``alpha`` None) the deployment angle within :data:`FREE_ALPHA`,
    else the angle held at ``alpha``."""
    doc = load_design(VAULT).metric_document()
    doc["layout"]["plates"] = plates
    spacing = LENGTH / plates
    doc["layout"]["spacing"] = spacing
    free = {
        "crease.span": [2.0, 3.0],
        "crease.rise": [0.7, 1.3],
        "layout.spacing": [0.6 * spacing, 1.4 * spacing],
    }
    return _with_alpha(doc, f"vault-{plates}", free, alpha)


def dome_base(plates: int, profile, alpha=None) -> tuple:
    """The radial dome preset with the crease through ``profile``, ``plates`` plates turning
    180 deg in all, and its free key: the deployment angle (as :func:`vault_base`)."""
    doc = load_design(Path(PRESET_DIR) / "dome.toml").metric_document()
    doc["crease"]["points"] = profile
    doc["layout"]["plates"] = plates
    doc["layout"]["angle"] = 180.0 / plates
    return _with_alpha(doc, f"dome-{plates}", {}, alpha)


def _with_alpha(doc: dict, name: str, free: dict, alpha) -> tuple:
    if alpha is None:
        free["deployment.alpha"] = list(FREE_ALPHA)
    else:
        # held: the fit needs a free key; +-0.005 deg changes nothing measurable
        doc["deployment"]["alpha"] = alpha
        free["deployment.alpha"] = [alpha - 0.005, alpha + 0.005]
    return Design(doc, name=name), free_keys(free)


def fit_row(label: str, plates: int, base: Design, free, target: PointSet) -> dict:
    """Fit ``base`` to ``target``, print the table row and return its numbers."""
    t = time.process_time()
    r = fit_design(base, target, free, max_evaluations=200)
    cpu = time.process_time() - t
    collides = CCUModel(r.design).collision_free_alpha
    alpha = r.parameters["deployment.alpha"]
    values = ", ".join(
        f"{k.split('.')[1]} {v:.4g}" for k, v in r.parameters.items() if k != "deployment.alpha"
    )
    bound = (
        " (bound)" if alpha >= free[-1].upper - 1e-3 and free[-1].upper - free[-1].lower > 1 else ""
    )
    print(
        f"| {label} | {plates} | {1000 * r.rms:.1f} | {1000 * r.max:.1f} | "
        f"{1000 * r.hausdorff:.1f} | {alpha:.2f}{bound} (collides at {collides:.1f}) | "
        f"{values or '-'} | {r.evaluations} | {cpu:.1f} |",
        flush=True,
    )
    return {
        "plates": plates,
        "rms": r.rms,
        "max": r.max,
        "hausdorff": r.hausdorff,
        "alpha": alpha,
        "status": r.status,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plates", default="4,6,8,10,14")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    counts = [int(p) for p in args.plates.split(",")]
    points = 5_000 if args.quick else 20_000
    print("load before:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())
    print(
        "| target | plates | rms (mm) | max (mm) | Hausdorff (mm) | alpha (deg) | fitted "
        "| models | CPU (s) |"
    )
    print("|---|---:|---:|---:|---:|---|---|---:|---:|")
    vault = barrel_vault(points)
    for alpha in (None, HELD):
        label = "barrel vault" + ("" if alpha is None else ", alpha held")
        for n in counts:
            fit_row(label, n, *vault_base(n, alpha), vault)
    dome = tna_dome()
    if dome is None:
        print("compas_tna does not import here: the dome rows are left out")
    else:
        xyz, tris = dome
        target = dome_target(xyz, tris, points)
        profile = meridian(xyz)
        for alpha in (None, HELD):
            label = "funicular dome" + ("" if alpha is None else ", alpha held")
            for n in counts:
                fit_row(label, n, *dome_base(n, profile, alpha), target)
    print("load after:", subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip())


if __name__ == "__main__":
    main()
