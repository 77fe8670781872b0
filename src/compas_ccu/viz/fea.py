"""Pictures of the finite-element shell: one deformed state, and every load case.

:func:`plot_fe_shape` paints a deformed quad mesh coloured by a per-element field, either the
signed bending stress (paper Fig. 7: tension blue, compression red, white at zero) or the
deviation from the kinematic model; it uses the cameras of :mod:`compas_ccu.viz.camera` and the
shading of :mod:`compas_ccu.viz.render`. :func:`plot_load_cases` draws the deflected shape of
every load case on one colour scale. The curves against the reflection angle α
(:func:`plot_fe_curves`, the deviation and the load–deployment curve) are
:mod:`compas_ccu.viz.fea_curves`, importable from here too.
"""

from __future__ import annotations

import numpy as np

from compas_ccu.tolerances import DIVISION_FLOOR
from compas_ccu.viz import colors as C
from compas_ccu.viz.camera import camera
from compas_ccu.viz.colour_scale import add_colorbar, value_range
from compas_ccu.viz.fea_curves import plot_fe_curves
from compas_ccu.viz.render import shade

__all__ = ["plot_fe_shape", "plot_fe_curves", "plot_load_cases", "FE_MODES"]

FE_MODES = ("stress", "deviation")

_LABELS = {
    "stress": "bending stress, top surface [MPa]",
    "deviation": "deviation from kinematic model [% of span]",
}
_NAN_RGB = np.array([0.78, 0.78, 0.78])


def _check_mesh(positions, elements, values) -> tuple:
    """Validated ``(positions (N, 3), elements (E, 4) int, element values (E,))``."""
    positions = np.asarray(positions, dtype=float)
    if positions.ndim != 2 or positions.shape[1] != 3:
        raise ValueError(f"positions must have shape (N, 3), got {positions.shape}")
    elements = np.asarray(elements)
    if elements.ndim != 2 or elements.shape[1] != 4:
        raise ValueError(f"elements must have shape (E, 4) (quads), got {elements.shape}")
    if elements.size and not np.issubdtype(elements.dtype, np.integer):
        if not np.issubdtype(elements.dtype, np.number) or np.any(elements != np.round(elements)):
            raise ValueError(f"elements must hold integer node indices, got dtype {elements.dtype}")
    elements = elements.astype(np.intp)
    n, e = len(positions), len(elements)
    if e == 0:
        raise ValueError("elements must hold at least one quad, got shape (0, 4)")
    if elements.min() < 0 or elements.max() >= n:
        raise ValueError(
            f"element node indices must lie in [0, {n}) for positions of shape {positions.shape}, "
            f"got [{elements.min()}, {elements.max()}]"
        )
    values = np.asarray(values, dtype=float)
    if values.shape == (e,):
        return positions, elements, values
    if values.shape == (n,):
        return positions, elements, values[elements].mean(axis=1)
    raise ValueError(
        f"values must have shape ({e},) (per element) or ({n},) (per node) for elements of shape "
        f"{elements.shape} and positions of shape {positions.shape}, got {values.shape}"
    )


def _as_segments(edges) -> np.ndarray:
    edges = np.asarray(edges, dtype=float)
    if edges.size == 0:
        return np.zeros((0, 2, 3))
    if edges.ndim != 3 or edges.shape[1:] != (2, 3):
        raise ValueError(f"edges must have shape (K, 2, 3) (line segments), got {edges.shape}")
    return edges


def plot_fe_shape(
    positions,
    elements,
    values,
    *,
    mode: str = "stress",
    view="perspective",
    title: str | None = None,
    label: str | None = None,
    vmin: float | None = None,
    vmax: float | None = None,
    ax=None,
    edges=None,
    cmap=None,
    figsize=(8.0, 5.6),
    note: str | None = None,
):
    """A deformed finite-element mesh coloured by a stress or deviation field.

    Parameters
    ----------
    positions : (N, 3) float
        Deformed node coordinates, metres.
    elements : (E, 4) int
        Quad elements as node indices into ``positions``.
    values : (E,) or (N,) float
        One value per element, or per node (averaged over each element's four nodes). When
        ``N == E`` the values are taken per element. NaN elements are painted grey.
    mode : {"stress", "deviation"}
        ``stress``: signed stresses in Pa, shown in MPa on a diverging map symmetric about zero,
        tension (positive) blue, compression (negative) red, near zero white (paper Fig. 7).
        ``deviation``: non-negative values (e.g. % of the span) on a sequential map from 0.
    view : str or Camera
        ``perspective``, ``plan``, ``elevation``, ``side`` or a
        :class:`~compas_ccu.viz.render.Camera`.
    title : str, optional
        Axes title.
    label : str, optional
        Colour bar label (default by mode).
    vmin, vmax : float, optional
        Colour range in the displayed unit (MPa for ``stress``). Stress defaults to
        ``±max |value|``; giving only one of the two mirrors it about zero. Deviation defaults
        to ``[0, max]``.
    ax : matplotlib.axes.Axes, optional
        Draw into this axes (a colour bar is added to its figure); default: a new figure.
    edges : (K, 2, 3) float, optional
        Line segments (e.g. the creases) drawn as dark lines, in the same depth order as the
        faces so that faces in front hide them.
    cmap : str or Colormap, optional
        Default: the project's diverging (``stress``) or sequential (``deviation``) map.
    figsize : (float, float)
        Size of a new figure, inches.
    note : str, optional
        The line of numbers under the picture; default: the extremes of the painted values.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        For shapes other than the above (the message names the shape), an unknown mode or view,
        or negative deviation values.

    Notes
    -----
    Faces and edge segments are one ``PolyCollection`` (segments as degenerate quads), painted
    back to front; its attribute ``element_index`` gives, for each of its polygons, the element
    it draws (``-1`` for an edge segment).

    Examples
    --------
    >>> import numpy as np
    >>> u, v = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 3), indexing="ij")
    >>> positions = np.c_[u.ravel(), v.ravel(), 0.1 * np.sin(np.pi * u.ravel())]
    >>> i = (np.arange(3)[:, None] * 3 + np.arange(2)).ravel()
    >>> elements = np.c_[i, i + 3, i + 4, i + 1]
    >>> fig = plot_fe_shape(positions, elements, np.linspace(-2e6, 1e6, 6))
    >>> [float(x) for x in fig.axes[-1].get_ylim()]  # symmetric about zero, in MPa
    [-2.0, 2.0]
    """
    if mode not in FE_MODES:
        raise ValueError(f"mode must be one of {FE_MODES}, got {mode!r}")
    positions, elements, values = _check_mesh(positions, elements, values)
    segments = _as_segments(edges) if edges is not None else np.zeros((0, 2, 3))
    cam = camera(view)
    shown, mappable, rgb = _colour_field(values, mode, vmin, vmax, cmap)
    collection, xy = _mesh_collection(positions, elements, rgb, segments, cam)

    fig, ax = _framed_axes(ax, figsize, collection, xy)
    add_colorbar(fig, mappable, ax, label or _LABELS[mode])
    note = note if note is not None else _extremes(shown, mode)
    if note is not None:
        ax.text(0.0, 0.0, note, transform=ax.transAxes, fontsize=8, color="#444444", va="bottom")
    if title:
        ax.set_title(title, fontsize=11)
    return fig


def _framed_axes(ax, figsize, collection, xy) -> tuple:
    """The axes of :func:`plot_fe_shape` (a new figure's without ``ax``) holding ``collection``,
    framed around the projected quads ``xy`` (E, 4, 2) at an equal scale, without axis lines.

    Returns
    -------
    fig : matplotlib.figure.Figure
    ax : matplotlib.axes.Axes
    """
    if ax is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=figsize, layout="constrained")
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure
    ax.add_collection(collection)
    allxy = xy.reshape(-1, 2)
    plo, phi = allxy.min(axis=0), allxy.max(axis=0)
    pad = 0.04 * float(max(phi - plo)) or 1.0
    ax.set_xlim(plo[0] - pad, phi[0] + pad)
    ax.set_ylim(plo[1] - pad, phi[1] + pad)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return fig, ax


def _colour_field(values: np.ndarray, mode: str, vmin, vmax, cmap) -> tuple:
    """The values as painted, their colour mapping and the colours of the elements.

    Returns
    -------
    shown : (E,) float
        The values in the displayed unit (MPa for ``stress``).
    mappable : matplotlib.cm.ScalarMappable
    rgb : (E, 3) float
        The element colours, grey where a value is NaN (not yet shaded).
    """
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    finite = np.isfinite(values)
    if mode == "stress":
        shown = values / 1e6
        peak = float(np.abs(shown[finite]).max()) if finite.any() else 0.0
        if vmin is None and vmax is None:
            vmin, vmax = -peak, peak
        elif vmin is None:
            vmin = -abs(vmax)
        elif vmax is None:
            vmax = abs(vmin)
        cmap = cmap or C.DIVERGING_CMAP
    else:
        shown = values
        if np.any(shown[finite] < 0.0):
            raise ValueError(
                f"deviation values must be >= 0, got a minimum of {float(shown[finite].min())!r}"
            )
        vmin = 0.0 if vmin is None else vmin
        cmap = cmap or C.SEQUENTIAL_CMAP
    mappable = ScalarMappable(norm=Normalize(*value_range(shown, vmin, vmax)), cmap=cmap)
    rgb = np.tile(_NAN_RGB, (len(shown), 1))
    rgb[finite] = mappable.to_rgba(shown[finite])[:, :3]
    return shown, mappable, rgb


def _mesh_collection(positions, elements, rgb, segments, cam) -> tuple:
    """The shaded faces and the edge segments as one ``PolyCollection``, back to front.

    Returns
    -------
    collection : matplotlib.collections.PolyCollection
        With ``element_index``: the element of each polygon, ``-1`` for an edge segment.
    xy : (E, 4, 2) float
        The projected quads (for the axes limits).
    """
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import to_rgba

    quads = positions[elements]  # (E, 4, 3)
    normals = np.cross(quads[:, 2] - quads[:, 0], quads[:, 3] - quads[:, 1])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), DIVISION_FLOOR)
    rgb = shade(rgb, normals, cam.axes())

    lo, hi = positions.min(axis=0), positions.max(axis=0)
    centre = 0.5 * (lo + hi)
    size = float(np.linalg.norm(hi - lo)) or 1.0
    xy, depth = cam.project(quads, centre, size)  # (E, 4, 2), (E, 4)
    e = len(elements)

    # mesh lines: a darker tone of each face (closes the seams between faces, reads as a mesh
    # on coarse meshes and fades on fine ones)
    dark = 0.82 if e <= 3000 else 0.92
    face_rgba = np.c_[rgb, np.ones(e)]
    edge_rgba = np.c_[rgb * dark, np.ones(e)]
    widths = np.full(e, 0.25 if e <= 3000 else 0.15)
    polys, order_depth = xy, depth.mean(axis=1)
    index = np.arange(e)
    if len(segments):
        # segments as degenerate quads a-b-b-a, nudged towards the eye by a third of a quad so
        # they win against the faces they lie on
        bias = 0.3 * float(np.median(np.linalg.norm(quads[:, 2] - quads[:, 0], axis=1)))
        sxy, sd = cam.project(segments, centre, size)
        k = len(segments)
        polys = np.concatenate([polys, sxy[:, [0, 1, 1, 0]]])
        order_depth = np.concatenate([order_depth, sd.mean(axis=1) + bias])
        face_rgba = np.concatenate([face_rgba, np.zeros((k, 4))])
        edge_rgba = np.concatenate([edge_rgba, np.tile(to_rgba(C.FREE_EDGE_COLOR), (k, 1))])
        widths = np.concatenate([widths, np.full(k, 1.8)])
        index = np.concatenate([index, np.full(k, -1)])

    order = np.argsort(order_depth, kind="stable")
    collection = PolyCollection(
        polys[order],
        facecolors=face_rgba[order],
        edgecolors=edge_rgba[order],
        linewidths=widths[order],
        closed=True,
        joinstyle="round",
        capstyle="round",
    )
    collection.element_index = index[order]
    return collection, xy


def _extremes(shown: np.ndarray, mode: str):
    """The default note under the picture: the extremes of the painted values (None if none)."""
    finite = np.isfinite(shown)
    if not finite.any():
        return None
    if mode == "stress":
        return (
            f"max tension {max(float(shown[finite].max()), 0.0):.3g} MPa, "
            f"max compression {max(-float(shown[finite].min()), 0.0):.3g} MPa"
        )
    return f"max {float(shown[finite].max()):.3g}, mean {float(shown[finite].mean()):.3g}"


def plot_load_cases(
    deployed,
    displacements,
    elements,
    titles,
    *,
    magnify: float | None = None,
    view="perspective",
    figsize: tuple | None = None,
):
    """The deflected shape of every load case, coloured by its deflection.

    Parameters
    ----------
    deployed : (N, 3) float
        The deployed node positions (before the loads), m.
    displacements : (C, N, 3) float
        The displacement of every node from the deployed state under each case's
        characteristic loads, m.
    elements : (E, 4) int
    titles : sequence of str
        One title per case (the case's name and numbers).
    magnify : float, optional
        Scale of the drawn displacements; default: the largest deflection of all cases drawn
        as 5 % of the structure's size (the factor is printed on every panel).
    view : str or Camera
    figsize : (float, float), optional

    Returns
    -------
    matplotlib.figure.Figure
        One panel per case, all on one colour scale (deflection in mm, from 0 to the largest of
        all cases), so equal colours mean equal deflections across the panels.

    Examples
    --------
    >>> import numpy as np
    >>> u, v = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 3), indexing="ij")
    >>> x = np.c_[u.ravel(), v.ravel(), 0.0 * u.ravel()]
    >>> i = (np.arange(3)[:, None] * 3 + np.arange(2)).ravel()
    >>> e = np.c_[i, i + 3, i + 4, i + 1]
    >>> d = np.zeros((2, 12, 3)); d[1, :, 2] = -0.002 * np.sin(np.pi * u.ravel())
    >>> fig = plot_load_cases(x, d, e, ["a", "b"])
    >>> len(fig.axes)  # two panels and one colour bar
    3
    """
    from matplotlib.figure import Figure

    x = np.asarray(deployed, dtype=float)
    d = np.asarray(displacements, dtype=float)
    if d.ndim != 3 or d.shape[1:] != x.shape or len(titles) != len(d):
        raise ValueError(
            f"displacements must be (cases, {len(x)}, 3) with one title per case, got "
            f"{d.shape} and {len(titles)} titles"
        )
    e = np.asarray(elements, dtype=int)
    size = float(np.linalg.norm(np.ptp(x, axis=0))) or 1.0
    magnitude = np.linalg.norm(d, axis=2) * 1e3  # mm
    peak = float(magnitude.max())
    if magnify is None:
        magnify = 0.05 * size / (peak / 1e3) if peak > 0.0 else 1.0
    cols = min(3, len(d))
    rows = -(-len(d) // cols)
    fig = Figure(figsize=figsize or (4.6 * cols, 3.6 * rows + 0.4), layout="constrained")
    axes = [fig.add_subplot(rows, cols, i + 1) for i in range(len(d))]
    for ax, disp, mm, title in zip(axes, d, magnitude, titles):
        _load_case_panel(ax, x + magnify * disp, e, mm, title, magnify, peak, view)
    # one colour bar for all panels: keep the last one plot_fe_shape added, drop the others
    bars = [a for a in fig.axes if a not in axes]
    for bar in bars[:-1]:
        bar.remove()
    return fig


def _load_case_panel(ax, deflected, elements, mm, title: str, magnify: float, peak: float, view):
    """One panel of :func:`plot_load_cases`: the ``deflected`` (N, 3) nodes coloured by the
    element means of the node deflections ``mm`` (N,) on the common scale 0 to ``peak`` mm,
    with its title and the magnification printed."""
    per_element = mm[elements].mean(axis=1)
    plot_fe_shape(
        deflected,
        elements,
        per_element,
        mode="deviation",
        view=view,
        ax=ax,
        vmin=0.0,
        vmax=peak or 1.0,
        label="deflection [mm]",
        note=f"largest at a node {mm.max():.3g} mm (colours: element means)",
    )
    ax.set_title(title, fontsize=9)
    ax.text(
        1.0,
        0.0,
        f"× {magnify:.3g}",
        transform=ax.transAxes,
        fontsize=7,
        ha="right",
        color="#444444",
        va="bottom",
    )
