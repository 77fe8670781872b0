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

The recovery copies are :mod:`compas_ccu.studio.recovery` (a part of :class:`StudioSession`),
the documents' values and their :class:`Problem` :mod:`compas_ccu.studio.documents`.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path

from compas_ccu.catalog import catalog_entries, catalog_path
from compas_ccu.design import Design
from compas_ccu.errors import OptionError
from compas_ccu.model import CCUModel
from compas_ccu.model.self_intersection import adopt_limits
from compas_ccu.studio.controls import UNSET
from compas_ccu.studio.documents import (
    Problem,
    changed_keys,
    clone_document,
    parse_document,
    problem_of,
)
from compas_ccu.studio.files import StudioFiles, decode_upload, sha256
from compas_ccu.studio.recovery import Recovery, SessionRecovery
from compas_ccu.studio.toml_text import document_text

__all__ = ["Problem", "Recovery", "StudioSession", "document_text", "DEFAULT_DESIGN"]

#: The catalog design the studio opens when no design file is given.
DEFAULT_DESIGN = "fig09a-arc"
#: Edits of the same key closer than this (s) are one undo step (typing a number).
COALESCE = 1.5
#: Undo steps kept.
HISTORY = 500


class StudioSession(SessionRecovery):
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
        document = parse_document(name, text)
        self.write_recovery()  # a change not yet in the last design's copy goes there first
        self.source = text
        self._source_values = clone_document(document)
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
            parse_document(name, text)
            self._load(text, name=name, origin=f"upload: {name}", saved=False)
            self._recover()

    # -- editing -------------------------------------------------------------------------------
    @property
    def document(self) -> dict:
        """A copy of the design the fields show: the valid design with the pending values."""
        return clone_document(self._fields)

    @property
    def valid_document(self) -> dict:
        """A copy of the last valid design (what Save writes)."""
        return clone_document(self._document)

    @property
    def _fields(self) -> dict:
        return self._document if self._draft is None else self._draft

    @property
    def pending(self) -> list:
        """``section.name`` of the fields whose values are not in the valid design."""
        return [] if self._draft is None else changed_keys(self._draft, self._document)

    def value(self, section: str, name: str):
        """The value of ``section.name`` in the fields (UNSET if the key is not given)."""
        table = self._fields.get(section)
        if not isinstance(table, dict) or name not in table:
            return UNSET
        return clone_document(table[name])

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
            document = clone_document(document)
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
            return None, problem_of(exc)
        return model, None

    def _set_model(self, model, document: dict) -> None:
        # a new material, load or name: the path limits of the last model still hold
        adopt_limits(model, self.model)
        self.model = model
        self.model_document = clone_document(document)
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
            self._recovery_due = False  # the file holds the valid design now
            self.source = text
            self._source_values = clone_document(self._document)
            self.base_sha256 = sha256(text)
            self.name = str(path.relative_to(self.files.design_folder))
            self.origin = self.name
            self.saved = True
            return path

    @property
    def path(self) -> Path:
        """Where :meth:`save` writes (the design file the recovery copy belongs to)."""
        return self.files.design_folder / self.name
