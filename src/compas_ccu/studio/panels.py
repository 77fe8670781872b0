"""The HTML of the studio's panels: the status line, the checks table, inline messages.

Pure functions from the session's and the checks' values to HTML strings (escaped), so what the
page says is testable without a browser. The element ids (``ccu-readout``, ``ccu-state``,
``ccu-problem``, ``ccu-checks``) are what the browser tests and the benchmark read.
"""

from __future__ import annotations

import html

from compas_ccu.model.self_intersection import measured_collision_free_alpha

__all__ = ["STATUS_COLORS", "message_html", "status_html", "checks_html", "patterns_html"]

#: Text colours of the four check states.
STATUS_COLORS = {"ok": "#1e7b34", "warn": "#a86400", "fail": "#c0262d", "info": "#444444"}


def message_html(text: str, status: str = "fail", *, size: str = "0.85em", id: str = "") -> str:
    """One line of text in the colour of ``status``."""
    ident = f" id='{id}'" if id else ""
    return (
        f"<div{ident} style='color:{STATUS_COLORS[status]};font-size:{size}'>"
        f"{html.escape(text)}</div>"
    )


def _beyond_html(model, alpha: float) -> str:
    """What the read-out says of the state at ``alpha`` degrees: beyond the first crossing or
    overlap, nothing, or that the path is still being checked (its limits not measured yet)."""
    free = measured_collision_free_alpha(model)
    if free is None:
        return " <span style='color:#777777'>· checking the path …</span>"
    if alpha <= free:
        return ""
    if free < model.overlap_alpha:
        text = f"beyond {free:.4g}°: two plates pass through each other"
    else:
        text = f"beyond the overlap angle {model.overlap_alpha:.4g}°: a crease overlaps itself"
    return f" <span style='color:{STATUS_COLORS['fail']}'>{text}</span>"


def status_html(session, view, *, state: str, message: str = "", failed=()) -> str:
    """The status block above the slider.

    Parameters
    ----------
    session : StudioSession
    view : ViewState or None
        The state drawn last (α, span, rise read-out).
    state : str
        What is drawn: exact kinematics, relaxing, relaxed.
    message : str
        An error of a worker, if any.
    failed : sequence of Check
        The failing checks of the current model.
    """
    name = html.escape(session.name)
    if not session.saved:
        name += f" <span style='color:{STATUS_COLORS['warn']}'>● unsaved</span>"
    out = [
        f"<div style='font-size:0.95em'><b>{name}</b> <span style='color:#777'>"
        f"({html.escape(session.origin)})</span></div>"
    ]
    model = session.model
    if model is not None and view is not None:
        over = _beyond_html(model, view.alpha)
        out.append(
            f"<div id='ccu-readout'>α = <b>{view.alpha:.2f}°</b> · span <b>{view.span:.3f} m</b>"
            f" · rise <b>{view.rise:.3f} m</b>{over}</div>"
        )
    tone = (
        "warn" if state.startswith("relaxing") else ("ok" if state.startswith("relaxed") else None)
    )
    color = STATUS_COLORS[tone] if tone else "#777777"
    out.append(
        f"<div id='ccu-state' style='color:{color};font-size:0.85em'>{html.escape(state)}</div>"
    )
    if session.notice:
        out.append(message_html(session.notice, "warn"))
    if message:
        out.append(message_html(message, "fail"))
    if session.problem is not None:
        out.append(message_html(session.problem.message, "fail", id="ccu-problem"))
    for check in failed:
        out.append(message_html(f"{check.name}: {check.reason}", "fail"))
    return "".join(out)


def checks_html(checks) -> str:
    """The checks table and the bending utilisation of every plate."""
    c = STATUS_COLORS
    rows = "".join(
        f"<tr><td style='padding:2px 6px'>{html.escape(r.name)}</td>"
        f"<td style='padding:2px 6px;text-align:right;color:{c[r.status]}'><b>"
        f"{html.escape(r.value)}</b></td>"
        f"<td style='padding:2px 6px;color:{c[r.status]};font-size:0.85em'>"
        f"{html.escape(r.reason)}</td></tr>"
        for r in checks.rows
    )
    plates = "".join(
        f"<tr><td style='padding:1px 6px'>plate {pid}</td><td style='padding:1px 6px;"
        f"color:{c['fail' if u > 1 else 'ok']}'>{u:.3f}</td></tr>"
        for pid, u in checks.plate_utilisation.items()
    )
    per_plate = (
        "<div style='font-size:0.85em;margin-top:6px'><b>bending utilisation per plate</b>"
        f" (along the path to the design state)<table>{plates}</table></div>"
        if plates
        else ""
    )
    return (
        f"<table id='ccu-checks' style='font-size:0.85em;border-collapse:collapse'>{rows}</table>"
        + per_plate
        + f"<div style='color:#777;font-size:0.8em'>measured in {checks.seconds * 1000:.0f} ms"
        "</div>"
    )


def patterns_html(svg: str, too_large) -> str:
    """The cut-pattern drawing with a warning naming the plates larger than the stock sheet."""
    note = (
        message_html(
            "plates larger than the stock sheet (to be split, or cut from larger sheets): "
            + ", ".join(map(str, too_large)),
            "warn",
        )
        if too_large
        else ""
    )
    return note + svg
