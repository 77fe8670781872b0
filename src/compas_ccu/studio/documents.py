"""The design documents of the studio's session: TOML values parsed, copied and compared.

A design being edited is a document of TOML values (``{section: {key: value}}``):
:func:`parse_document` reads one from text with a one-line error, :func:`clone_document` copies
one (fast), :func:`changed_keys` names the keys two documents differ in, and a document that
does not build has a :class:`Problem` (:func:`problem_of` its exception): the message ``ccu``
prints for the same file and the key it names.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

from compas_ccu.design.document import parse_toml
from compas_ccu.errors import CCUError, DesignError, OptionError

__all__ = ["Problem", "problem_of", "parse_document", "clone_document", "changed_keys"]

log = logging.getLogger("compas_ccu.studio.session")  # one log for the session


@dataclass(frozen=True)
class Problem:
    """Why the current document has no model.

    ``message`` is what ``ccu`` prints after ``ccu: error:`` for the same design file (without
    the file name); ``key`` is the design key it names (``crease.rise``) or None.
    """

    message: str
    key: str | None
    kind: str


def problem_of(exc: BaseException) -> Problem:
    """The :class:`Problem` of an exception raised while building a design: a
    :class:`~compas_ccu.errors.CCUError` says what is wrong (and a
    :class:`~compas_ccu.errors.DesignError` which key); anything else is a bug, logged."""
    if isinstance(exc, CCUError):
        key = getattr(exc, "key", None) if isinstance(exc, DesignError) else None
        return Problem(str(exc), key, type(exc).__name__)
    log.exception("studio: unexpected error while building a design")
    return Problem(
        f"internal error {type(exc).__name__}: {exc} (this is a bug in compas_ccu; "
        "please report it with the design file)",
        None,
        "bug",
    )


def parse_document(name: str, text: str) -> dict:
    """The TOML values of ``text``; OptionError ``NAME: not valid TOML: ...`` (its first line)
    if it is not TOML."""
    try:
        return parse_toml(text)
    except (ValueError, RecursionError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise OptionError(f"{name}: not valid TOML: {first}") from None


def clone_document(value):
    """A deep copy of a TOML document or value (dicts, lists and scalars; several times faster
    than :func:`copy.deepcopy` on a 10,000-point list)."""
    if isinstance(value, dict):
        return {k: clone_document(v) for k, v in value.items()}
    if isinstance(value, list):
        return [clone_document(v) if isinstance(v, (dict, list)) else v for v in value]
    return value


def changed_keys(a: dict, b: dict) -> list:
    """``section.name`` of every key whose value differs between documents ``a`` and ``b``."""
    out = []
    for section in sorted(set(a) | set(b)):
        x, y = a.get(section), b.get(section)
        if isinstance(x, dict) and isinstance(y, dict):
            out += [f"{section}.{k}" for k in sorted(set(x) | set(y)) if x.get(k) != y.get(k)]
        elif x != y:
            out.append(section)
    return out
