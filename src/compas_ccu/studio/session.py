"""The studio's editing session: one design document, its history and its last valid model.

:class:`StudioSession` is the whole state of the studio without any user interface (the web app
in :mod:`compas_ccu.studio.app` only shows it and forwards edits), so everything a designer does
is testable in Python:

* an edit sets one key (:meth:`StudioSession.edit`) of the *fields* (:attr:`document`); when the
  fields make a design that builds, it becomes the session's **valid design** (one undo step,
  written to the recovery copy) and its model is shown. A value that fails stays in its field
  with the message the ``ccu`` command prints for the same file (:attr:`problem`,
  :attr:`pending`) and never reaches the history or the recovery copy; the last valid model
  stays on screen;
* undo / redo step through valid designs only (edits of one key in quick succession are one
  step; an undo first drops the pending fields);
* open a design file from the design folder, a catalog design or an uploaded file; save and
  save as (atomically, keeping the file's comments and permission bits); every valid change is
  written to the recovery copy of its design file in the output folder, restored when the studio
  is started again on the same file with the same content, and *offered* (restore or keep the
  file: :meth:`restore_recovery`, :meth:`discard_recovery`) when the file changed since.
"""

from __future__ import annotations

import logging
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from compas_ccu.catalog import catalog_entries, catalog_path
from compas_ccu.design import Design
from compas_ccu.design.document import parse_toml
from compas_ccu.errors import CCUError, DesignError, OptionError
from compas_ccu.model import CCUModel
from compas_ccu.studio.controls import UNSET
from compas_ccu.studio.files import StudioFiles, decode_upload, sha256
from compas_ccu.studio.toml_text import document_text

__all__ = ["Problem", "Recovery", "StudioSession", "document_text", "DEFAULT_DESIGN"]

log = logging.getLogger(__name__)

#: The catalog design the studio opens when no design file is given.
DEFAULT_DESIGN = "fig09a-arc"
#: Edits of the same key closer than this (s) are one undo step (typing a number).
COALESCE = 1.5
#: Undo steps kept.
HISTORY = 500


@dataclass(frozen=True)
class Problem:
    """Why the current document has no model.

    ``message`` is what ``ccu`` prints after ``ccu: error:`` for the same design file (without
    the file name); ``key`` is the design key it names (``crease.rise``) or None.
    """

    message: str
    key: str | None
    kind: str


@dataclass(frozen=True)
class Recovery:
    """A recovery copy older than its design file on disk (the file changed since): offered,
    never restored silently. ``time`` is when it was written, ``text`` the design it holds."""

    path: Path
    text: str
    time: str


def _problem(exc: BaseException) -> Problem:
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


def _parse(name: str, text: str) -> dict:
    try:
        return parse_toml(text)
    except (ValueError, RecursionError) as exc:
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise OptionError(f"{name}: not valid TOML: {first}") from None


def _clone(value):
    """A deep copy of a TOML document or value (dicts, lists and scalars; several times faster
    than :func:`copy.deepcopy` on a 10,000-point list)."""
    if isinstance(value, dict):
        return {k: _clone(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_clone(v) if isinstance(v, (dict, list)) else v for v in value]
    return value


def _keys(a: dict, b: dict) -> list:
    """``section.name`` of every key whose value differs between documents ``a`` and ``b``."""
    out = []
    for section in sorted(set(a) | set(b)):
        x, y = a.get(section), b.get(section)
        if isinstance(x, dict) and isinstance(y, dict):
            out += [f"{section}.{k}" for k in sorted(set(x) | set(y)) if x.get(k) != y.get(k)]
        elif x != y:
            out.append(section)
    return out


class StudioSession:
    """One design being edited.

    Parameters
    ----------
    files : StudioFiles
    text : str
        TOML text of the design.
    name : str
        File name it is saved under in the design folder (``vault.toml``).
    origin : str
        Where it came from, for the page (``vault.toml``, ``catalog: fig09a-arc``, ``upload``).
    saved : bool
        Whether ``name`` in the design folder holds this text.

    Attributes
    ----------
    valid_document : dict
        The design as TOML values: what Save writes and the recovery copy holds (the last
        design that built, or the file as opened).
    model : CCUModel or None
        The model of the last valid document.
    problem : Problem or None
        Why the fields (:attr:`document`) have no model (the model shown is the last valid one).
    generation : int
        Incremented whenever ``model`` changes.
    recovery : Recovery or None
        A recovery copy older than the file: the user restores it or keeps the file.
    """

    def __init__(self, files: StudioFiles, text: str, *, name: str, origin: str, saved: bool):
        self.files = files
        self.lock = threading.RLock()
        self.model = None
        self.model_document = None
        self.problem = None
        self.generation = 0
        self.notice = ""
        self.recovery = None
        self._draft = None
        self._undo: list = []
        self._redo: list = []
        self._last_edit = (None, 0.0)
        self._load(text, name=name, origin=origin, saved=saved)

    # -- opening -------------------------------------------------------------------------------
    @classmethod
    def start(cls, design=None, *, out, allowed=()) -> StudioSession:
        """The session of ``ccu studio [DESIGN] --out OUT [--allow-dir DIR ...]``.

        The design folder is the folder of ``design`` (or ``out`` without one). An unsaved
        recovery copy of the same design file in ``out`` is restored if the file is as it was
        when the copy was made (``notice`` says so), and offered (:attr:`recovery`) if it
        changed since.

        Raises
        ------
        OptionError
            ``design`` is not a readable design file.
        """
        if design is not None:
            path = Path(design).expanduser().resolve()
            if not path.is_file():
                raise OptionError(f"{design}: no such design file")
            files = StudioFiles(path.parent, out, allowed)
            text, name, origin = files.read(path.name), path.name, path.name
        else:
            files = StudioFiles(out, out, allowed)
            name = f"{DEFAULT_DESIGN}.toml"
            text = decode_upload(name, catalog_path(DEFAULT_DESIGN).read_bytes())
            origin = f"catalog: {DEFAULT_DESIGN}"
        session = cls(files, text, name=name, origin=origin, saved=design is not None)
        session._find_recovery()
        return session

    def _load(self, text: str, *, name: str, origin: str, saved: bool) -> None:
        document = _parse(name, text)
        self.source = text
        self._source_values = _clone(document)
        self.base_sha256 = sha256(text)  # the content the edits start from
        self.name = name
        self.origin = origin
        self.saved = saved
        self.recovery = None
        self._draft = None
        self._undo.clear()
        self._redo.clear()
        self._last_edit = (None, 0.0)
        self._document = document
        model, self.problem = self._build(document)
        self._valid_problem = self.problem
        if model is not None:
            self._set_model(model, document)

    def _find_recovery(self) -> None:
        """Restore the recovery copy of :attr:`path` made from the same content; set one made
        from other content aside and offer it."""
        path, files = self.path, self.files
        found = files.load_recovery(path)
        if found is not None:
            text, meta = found
            if text == self.source:
                files.clear_recovery(path)
            elif meta.get("base_sha256") == self.base_sha256:
                base = self.base_sha256
                self._load(text, name=self.name, origin=meta.get("origin", self.origin),
                           saved=False)  # fmt: skip
                self.base_sha256 = base
                self.notice = (
                    f"restored unsaved edits of {self.name} from {files.recovery_folder} "
                    f"(saved {meta.get('time', 'earlier')})"
                )
            else:
                files.set_aside(path)
        offered = files.load_recovery(path, "offered")
        if offered is not None:
            text, meta = offered
            if text == self.text():
                files.clear_recovery(path, "offered")
                return
            self.recovery = Recovery(path, text, str(meta.get("time", "earlier")))
            self.notice = (
                f"a recovery copy of {self.name} from {self.recovery.time} is older than the "
                f"file (it changed since): the file is shown; restore the recovery copy or "
                "keep the file"
            )

    def restore_recovery(self) -> None:
        """Open the offered recovery copy instead of the file (unsaved; one undo step back to
        the file). The copy is then the session's recovery copy.

        Raises
        ------
        OptionError
            No recovery copy is offered.
        """
        with self.lock:
            offer = self._offer()
            document = _parse(f"the recovery copy of {self.name}", offer.text)
            model, problem = self._build(document)
            self.recovery = None
            self.files.clear_recovery(offer.path, "offered")
            self._draft = None
            self._undo.append(self._document)
            self._redo.clear()
            self._document, self.problem = document, problem
            self._valid_problem = problem
            self.source = offer.text
            self._source_values = _clone(document)
            if model is not None:
                self._set_model(model, document)
            self.saved = False
            self.notice = f"restored the recovery copy of {self.name} from {offer.time}"
            self._recover()

    def discard_recovery(self) -> None:
        """Keep the file and delete the offered recovery copy.

        Raises
        ------
        OptionError
            No recovery copy is offered.
        """
        with self.lock:
            offer = self._offer()
            self.files.clear_recovery(offer.path, "offered")
            self.recovery = None
            self.notice = f"kept {self.name}; the recovery copy from {offer.time} is deleted"

    def _offer(self) -> Recovery:
        if self.recovery is None:
            raise OptionError(f"no recovery copy of {self.name} is waiting for a choice")
        return self.recovery

    def open_file(self, name: str) -> None:
        """Open design file ``name`` from the design folder (replaces the session's design;
        its recovery copy is restored or offered as at the start)."""
        with self.lock:
            text = self.files.read(name)
            self._load(text, name=str(self.files.inside(name).relative_to(
                self.files.design_folder)), origin=str(name), saved=True)  # fmt: skip
            self.notice = ""
            self._find_recovery()

    def open_catalog(self, name: str) -> None:
        """Open catalog design ``name`` (saved as ``NAME.toml`` in the design folder)."""
        with self.lock:
            names = [e.name for e in catalog_entries()]
            if name not in names:
                raise OptionError(f"unknown catalog design {name!r}; known: {', '.join(names)}")
            text = decode_upload(name, catalog_path(name).read_bytes())
            self._load(text, name=f"{name}.toml", origin=f"catalog: {name}", saved=False)
            self._recover()

    def open_upload(self, filename: str, content: bytes) -> None:
        """Open an uploaded design file (saved under its name in the design folder).

        Raises
        ------
        CCUError
            One line: a name that is not ``.toml``, a file too large (the limit
            ``upload_bytes``), binary, nested too deep or not TOML. Nothing changes.
        """
        with self.lock:
            name = Path(str(filename).replace("\\", "/")).name or "design.toml"
            if not name.lower().endswith(".toml"):
                raise OptionError(f"{filename!r}: open a design file ending with .toml")
            self.files.inside(name)  # a name that can be saved
            text = decode_upload(name, bytes(content))
            _parse(name, text)
            self._load(text, name=name, origin=f"upload: {name}", saved=False)
            self._recover()

    # -- editing -------------------------------------------------------------------------------
    @property
    def document(self) -> dict:
        """A copy of the design the fields show: the valid design with the pending values."""
        return _clone(self._fields)

    @property
    def valid_document(self) -> dict:
        """A copy of the last valid design (what Save writes)."""
        return _clone(self._document)

    @property
    def _fields(self) -> dict:
        return self._document if self._draft is None else self._draft

    @property
    def pending(self) -> list:
        """``section.name`` of the fields whose values are not in the valid design."""
        return [] if self._draft is None else _keys(self._draft, self._document)

    def value(self, section: str, name: str):
        """The value of ``section.name`` in the fields (UNSET if the key is not given)."""
        table = self._fields.get(section)
        if not isinstance(table, dict) or name not in table:
            return UNSET
        return _clone(table[name])

    def edit(self, section: str, name: str, value) -> Problem | None:
        """Set ``section.name`` to ``value`` (:data:`UNSET` removes it) and rebuild.

        Returns the :class:`Problem` of the fields, or None if they build (and are now the
        valid design).
        """
        with self.lock:
            document = self.document
            table = document.setdefault(section, {})
            if not isinstance(table, dict):
                table = document[section] = {}
            if value is UNSET:
                table.pop(name, None)
                if not table:
                    document.pop(section)
            else:
                table[name] = value
            key, when = self._last_edit
            now = time.monotonic()
            merge = key == (section, name) and now - when < COALESCE and bool(self._undo)
            problem = self.replace(document, merge=merge)
            self._last_edit = ((section, name), now) if problem is None else (None, 0.0)
            return problem

    def replace(self, document: dict, *, merge: bool = False) -> Problem | None:
        """Replace the fields by ``document`` and rebuild: one undo step if it builds (merged
        into the last one with ``merge``), else pending with its problem."""
        with self.lock:
            if document == self._fields:
                return self.problem
            document = _clone(document)
            if document == self._document:  # typed back to the valid design
                self._draft = None
                self.problem = self._valid_problem
                return self.problem
            model, problem = self._build(document)
            if model is None:
                self._draft, self.problem = document, problem
                return problem
            if not merge and self._valid_problem is None:  # valid designs only
                self._undo.append(self._document)
                del self._undo[:-HISTORY]
            self._redo.clear()
            self._draft, self._document = None, document
            self.problem = self._valid_problem = None
            self._set_model(model, document)
            self.saved = False
            self._recover()
            return None

    def undo(self) -> bool:
        """Drop the pending fields, or go back one valid design; False if there is neither."""
        with self.lock:
            if self._draft is not None:
                self._draft = None
                self.problem = self._valid_problem
                self._last_edit = (None, 0.0)
                return True
            if not self._undo:
                return False
            self._step(self._undo, self._redo)
            return True

    def redo(self) -> bool:
        """Redo an undone change; False if there is none."""
        with self.lock:
            if not self._redo:
                return False
            self._draft = None
            self._step(self._redo, self._undo)
            return True

    def _step(self, source: list, target: list) -> None:
        target.append(self._document)
        document = source.pop()
        model, self.problem = self._build(document)
        self._valid_problem = self.problem
        self._document = document
        if model is not None:
            self._set_model(model, document)
        self._last_edit = (None, 0.0)
        self.saved = False
        self._recover()

    @property
    def can_undo(self) -> bool:
        return bool(self._undo) or self._draft is not None

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    def _build(self, document: dict):
        """``(model, None)`` of ``document``, or ``(None, Problem)``."""
        try:
            self.files.check_curve_files(document)
            model = CCUModel(
                Design(document, name=Path(self.name).stem, base=self.files.design_folder)
            )
        except Exception as exc:  # the studio shows every failure and keeps the last model
            return None, _problem(exc)
        return model, None

    def _set_model(self, model, document: dict) -> None:
        self.model = model
        self.model_document = _clone(document)
        self.generation += 1

    # -- saving --------------------------------------------------------------------------------
    def text(self) -> str:
        """TOML text of the valid design (the comments of the file it came from are kept)."""
        with self.lock:
            return document_text(self._document, self.source, self._source_values)

    def fields_text(self) -> str:
        """TOML text of the fields (the valid design with the pending values)."""
        with self.lock:
            return document_text(self._fields, self.source, self._source_values)

    def save(self) -> Path:
        """Write the valid design to its name in the design folder (atomically)."""
        return self.save_as(self.name)

    def save_as(self, name: str) -> Path:
        """Write the valid design to ``name`` in the design folder and make it the session's
        name. The file is replaced atomically and keeps its permission bits; a failure leaves
        the old file as it was.

        Raises
        ------
        OptionError
            ``name`` is not a ``.toml`` name inside the design folder, or lies in the studio's
            own folder ``.ccu-studio/``.
        """
        with self.lock:
            path = self.files.inside(name)
            text = self.text()
            before = self.path
            self.files.write(path.relative_to(self.files.design_folder), text)
            self.files.clear_recovery(before)
            self.files.clear_recovery(path)
            self.source = text
            self._source_values = _clone(self._document)
            self.base_sha256 = sha256(text)
            self.name = str(path.relative_to(self.files.design_folder))
            self.origin = self.name
            self.saved = True
            return path

    @property
    def path(self) -> Path:
        """Where :meth:`save` writes (the design file the recovery copy belongs to)."""
        return self.files.design_folder / self.name

    def _recover(self) -> None:
        """Keep the valid design in the recovery copy of its file (a killed server loses no
        edit)."""
        try:
            text = self.text()
            meta = {
                "name": self.name,
                "origin": self.origin,
                "time": time.strftime("%Y-%m-%d %H:%M:%S"),
                "sha256": sha256(text),
                "base_sha256": self.base_sha256,
            }
            self.files.save_recovery(self.path, text, meta)
        except (OSError, CCUError) as exc:  # the page says so; the edit itself is not lost
            self.notice = f"could not write the recovery copy: {exc}"
