"""compas_ccu: curved-crease unfolding (CCU) toolkit.

Exact geometry and one-degree-of-freedom kinematics of stacked flat plates joined along planar
curved creases (Scheder-Bieschin, Van Mele & Block 2023).

Importing this package is cheap: it imports neither COMPAS nor SciPy. Subpackages are imported
where used::

    from compas_ccu.model import load_model

    model = load_model("examples/vault.toml")   # design file -> the deployable model
    structure = model.deploy(30.0)               # reference reflection angle, degrees

The layers and what flows between them: docs/architecture.md.
"""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]

# COMPAS plugin discovery imports every ``compas*`` package: keep this module free of side effects.
__all_plugins__ = ["compas_ccu.scene"]
