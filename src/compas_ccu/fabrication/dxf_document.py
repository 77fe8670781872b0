"""A DXF document in millimetres that depends on its drawing only: made, bounded and saved.

:func:`new_document` starts an R2010 document in millimetres with its layers and the
``COMPAS_CCU`` XDATA application; :func:`save_document` sets the header's ``$EXTMIN`` /
``$EXTMAX`` (and the model space's extents and initial view) to the bounding box of its entities
(``ezdxf.bbox.extents`` in its fast mode: exact for the polylines and lines, text estimated from
its height and length), so "zoom extents" works in every CAD tool (ezdxf leaves them at the
+-1e20 placeholders otherwise), and saves it with ezdxf's fixed metadata and a fixed order of
its CLASSES section: the same drawing, the same bytes (docs/robustness.md). Every DXF writer of
the package (plates, hinge strips, sheets) uses them. ezdxf is imported inside the functions
(``pip install ezdxf``).
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import numpy as np

__all__ = ["APPID", "MM", "new_document", "save_document", "xy_list"]

#: The XDATA application of every entity the package tags.
APPID = "COMPAS_CCU"
#: DXF units per metre.
MM = 1000.0


@contextmanager
def _fixed_metadata():
    """ezdxf's fixed metadata for the block (creation and update dates 2000-01-01, zero GUIDs,
    its marker without the clock), so a file depends on its drawing only."""
    import ezdxf

    fixed = ezdxf.options.write_fixed_meta_data_for_testing
    ezdxf.options.write_fixed_meta_data_for_testing = True
    try:
        yield
    finally:
        ezdxf.options.write_fixed_meta_data_for_testing = fixed


def new_document(layers: dict):
    """A new R2010 ezdxf document in millimetres with ``layers`` (name -> ACI colour) and
    ezdxf's fixed metadata (the same bytes every run)."""
    import ezdxf

    with _fixed_metadata():  # the marker of its creation: no clock either
        doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.MM  # $INSUNITS = 4
    doc.header["$MEASUREMENT"] = 1  # metric
    doc.header["$LUNITS"] = 2  # decimal
    for name, color in layers.items():
        doc.layers.add(name, color=color)
    doc.appids.add(APPID)
    return doc


def save_document(doc, path: Path) -> None:
    """Set the header / model space extents and the initial view from the entities, and save.

    The file depends on the drawing only: ezdxf's fixed metadata (creation and update dates
    2000-01-01, zero GUIDs, no clock in its marker) instead of the time of writing, so the same
    design and options write the same bytes (docs/robustness.md).
    """
    from ezdxf import bbox, zoom

    msp = doc.modelspace()
    box = bbox.extents(msp, fast=True)
    if box.has_data:
        lo, hi = box.extmin, box.extmax
        doc.header["$EXTMIN"] = (lo.x, lo.y, lo.z)
        doc.header["$EXTMAX"] = (hi.x, hi.y, hi.z)
        msp.reset_extents((lo.x, lo.y, lo.z), (hi.x, hi.y, hi.z))
        zoom.center(msp, box.center, box.size)
    _fixed_class_order(doc)
    with _fixed_metadata():
        doc.saveas(path)


def _fixed_class_order(doc) -> None:
    """The CLASSES section in a fixed order: ezdxf adds a CLASS for every entity type in use
    from a set, whose order follows Python's string hashing and so changes from one process to
    the next (the same drawing wrote other bytes in every run). Its required classes first, in
    its order, then the others by name; saving adds nothing more (ezdxf keeps a class once)."""
    from ezdxf.sections.classes import REQUIRED_CLASSES

    doc.commit_pending_changes()
    doc.classes.add_required_classes(doc.dxfversion)
    required = {n: k for k, n in enumerate(REQUIRED_CLASSES.get(doc.dxfversion, ()))}
    keys = sorted(doc.classes.classes, key=lambda key: (required.get(key[0], len(required)), key))
    doc.classes.classes = {key: doc.classes.classes[key] for key in keys}


def xy_list(points) -> list:
    """(m, 2) points as the list of tuples ezdxf's polylines take."""
    return [tuple(p) for p in np.asarray(points, dtype=float).tolist()]
