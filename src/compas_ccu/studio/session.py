"""The studio's editing session: one design document, its history and its last valid model.

:class:`StudioSession` is the whole state of the studio without any user interface (the web app
in :mod:`compas_ccu.studio.app` only shows it and forwards edits), so everything a designer does
is testable in Python:

* an edit sets one key (:meth:`StudioSession.edit`) or replaces the document; the document is
  validated and the model rebuilt; a design that fails keeps the **last valid model** and
  records the :class:`Problem` with the message the ``ccu`` command prints for the same file;
* undo / redo over every document change (edits of one key in quick succession are one step);
* open a design file from the design folder, a catalog design or an uploaded file; save and
  save as (atomically, keeping the file's comments); every change is written to a recovery copy
  in the output folder, restored when the studio is started again on the same design.
"""

from __future__ import annotations

import copy
import hashlib
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
from compas_ccu.studio.files import StudioFiles, decode_upload

__all__ = ["Problem", "StudioSession", "document_text", "DEFAULT_DESIGN"]

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


def document_text(document: dict, source: str | None = None) -> str:
    """TOML text of ``document``; with ``source`` (the text it was read from) the comments,
    order and layout of the unchanged keys are kept (tomlkit).

    Raises
    ------
    DesignError
        A value TOML cannot hold (None, an object), naming its key.
    """
    for section, values in document.items():
        for name, value in values.items() if isinstance(values, dict) else [("", values)]:
            if not _writable(value):
                key = f"{section}.{name}" if name else f"[{section}]"
                raise DesignError(
                    f"a {type(value).__name__} cannot be written to a TOML file", key=key
                )
    return _document_text(document, source)


def _writable(value) -> bool:
    if isinstance(value, (list, tuple)):
        return all(map(_writable, value))
    if isinstance(value, dict):
        return all(map(_writable, value.values()))
    return isinstance(value, (str, int, float, bool))


def _document_text(document: dict, source: str | None) -> str:
    import tomlkit

    doc = tomlkit.parse(source) if source else tomlkit.document()
    for section in list(doc.keys()):
        if section not in document:
            del doc[section]
    for section, values in document.items():
        if not isinstance(values, dict):
            doc[section] = values
            continue
        if section not in doc or not isinstance(doc[section], dict):
            doc[section] = tomlkit.table()
        table = doc[section]
        for name in list(table.keys()):
            if name not in values:
                del table[name]
        for name, value in values.items():
            if name not in table or not _identical(_unwrap(table[name]), value):
                table[name] = value
    return tomlkit.dumps(doc)


def _identical(a, b) -> bool:
    """Equal values of equal types all the way down (1 and 1.0 differ in a TOML file)."""
    if isinstance(a, (list, tuple)):
        return isinstance(b, (list, tuple)) and len(a) == len(b) and all(map(_identical, a, b))
    return type(a) is type(b) and a == b


def _unwrap(item):
    return item.unwrap() if hasattr(item, "unwrap") else item


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


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
    document : dict
        The design as TOML values (what a file would hold).
    model : CCUModel or None
        The model of the last valid document.
    problem : Problem or None
        Why the current document has no model (the model shown is then the last valid one).
    generation : int
        Incremented whenever ``model`` changes.
    """

    def __init__(self, files: StudioFiles, text: str, *, name: str, origin: str, saved: bool):
        self.files = files
        self.lock = threading.RLock()
        self.model = None
        self.model_document = None
        self.problem = None
        self.generation = 0
        self.notice = ""
        self._undo: list = []
        self._redo: list = []
        self._last_edit = (None, 0.0)
        self._load(text, name=name, origin=origin, saved=saved)

    # -- opening -------------------------------------------------------------------------------
    @classmethod
    def start(cls, design=None, *, out) -> StudioSession:
        """The session of ``ccu studio [DESIGN] --out OUT``.

        The design folder is the folder of ``design`` (or ``out`` without one). An unsaved
        recovery copy of the same design in ``out`` is restored (``notice`` says so).

        Raises
        ------
        OptionError
            ``design`` is not a readable design file.
        """
        if design is not None:
            path = Path(design).expanduser().resolve()
            if not path.is_file():
                raise OptionError(f"{design}: no such design file")
            files = StudioFiles(path.parent, out)
            text, name, origin = files.read(path.name), path.name, path.name
        else:
            files = StudioFiles(out, out)
            name = f"{DEFAULT_DESIGN}.toml"
            text = decode_upload(name, catalog_path(DEFAULT_DESIGN).read_bytes())
            origin = f"catalog: {DEFAULT_DESIGN}"
        session = cls(files, text, name=name, origin=origin, saved=design is not None)
        recovery = files.load_recovery()
        if recovery is not None and recovery[1].get("name") == name:
            rtext, meta = recovery
            if rtext != text:
                session._load(rtext, name=name, origin=meta.get("origin", origin), saved=False)
                session.notice = (
                    f"restored unsaved edits of {name} from {files.recovery_folder} "
                    f"(saved {meta.get('time', 'earlier')})"
                )
        return session

    def _load(self, text: str, *, name: str, origin: str, saved: bool) -> None:
        try:
            document = parse_toml(text)
        except ValueError as exc:
            raise OptionError(f"{name}: not valid TOML: {exc}") from None
        self.source = text
        self.name = name
        self.origin = origin
        self.saved = saved
        self._undo.clear()
        self._redo.clear()
        self._last_edit = (None, 0.0)
        self._apply(document)

    def open_file(self, name: str) -> None:
        """Open design file ``name`` from the design folder (replaces the session's design)."""
        with self.lock:
            text = self.files.read(name)
            self._load(text, name=Path(name).name, origin=str(name), saved=True)

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
        """Open an uploaded design file (saved under its name in the design folder)."""
        with self.lock:
            name = Path(str(filename).replace("\\", "/")).name or "design.toml"
            if not name.lower().endswith(".toml"):
                raise OptionError(f"{filename!r}: open a design file ending with .toml")
            self.files.inside(name)  # a name that can be saved
            text = decode_upload(name, content)
            self._load(text, name=name, origin=f"upload: {name}", saved=False)
            self._recover()

    # -- editing -------------------------------------------------------------------------------
    @property
    def document(self) -> dict:
        """A copy of the design as TOML values."""
        return copy.deepcopy(self._document)

    def value(self, section: str, name: str):
        """The document's value of ``section.name`` (UNSET if the key is not given)."""
        table = self._document.get(section)
        if not isinstance(table, dict) or name not in table:
            return UNSET
        return copy.deepcopy(table[name])

    def edit(self, section: str, name: str, value) -> Problem | None:
        """Set ``section.name`` to ``value`` (:data:`UNSET` removes it) and rebuild.

        Returns the :class:`Problem` of the new document, or None if it builds.
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
            merge = key == (section, name) and now - when < COALESCE and self._undo
            self._last_edit = ((section, name), now)
            return self.replace(document, merge=merge)

    def replace(self, document: dict, *, merge: bool = False) -> Problem | None:
        """Replace the whole document (one undo step) and rebuild."""
        with self.lock:
            if document == self._document:
                return self.problem
            if not merge:
                self._undo.append(self._document)
                del self._undo[:-HISTORY]
            self._redo.clear()
            self._apply(copy.deepcopy(document))
            self.saved = False
            self._recover()
            return self.problem

    def undo(self) -> bool:
        """Go back one document change; False if there is none."""
        with self.lock:
            if not self._undo:
                return False
            self._redo.append(self._document)
            self._apply(self._undo.pop())
            self._last_edit = (None, 0.0)
            self.saved = False
            self._recover()
            return True

    def redo(self) -> bool:
        """Redo an undone change; False if there is none."""
        with self.lock:
            if not self._redo:
                return False
            self._undo.append(self._document)
            self._apply(self._redo.pop())
            self._last_edit = (None, 0.0)
            self.saved = False
            self._recover()
            return True

    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    def _apply(self, document: dict) -> None:
        self._document = document
        try:
            model = CCUModel(
                Design(document, name=Path(self.name).stem, base=self.files.design_folder)
            )
        except Exception as exc:  # the studio shows every failure and keeps the last model
            self.problem = _problem(exc)
            return
        self.problem = None
        self.model = model
        self.model_document = copy.deepcopy(document)
        self.generation += 1

    # -- saving --------------------------------------------------------------------------------
    def text(self) -> str:
        """TOML text of the document (the comments of the file it came from are kept)."""
        with self.lock:
            return document_text(self._document, self.source)

    def save(self) -> Path:
        """Write the design to its name in the design folder (atomically)."""
        return self.save_as(self.name)

    def save_as(self, name: str) -> Path:
        """Write the design to ``name`` in the design folder and make it the session's name.

        Raises
        ------
        OptionError
            ``name`` is not a ``.toml`` name inside the design folder.
        """
        with self.lock:
            path = self.files.inside(name)
            text = self.text()
            self.files.write(path.relative_to(self.files.design_folder), text)
            self.files.clear_recovery()
            self.source = text
            self.name = str(path.relative_to(self.files.design_folder))
            self.origin = self.name
            self.saved = True
            return path

    @property
    def path(self) -> Path:
        """Where :meth:`save` writes."""
        return self.files.design_folder / self.name

    def _recover(self) -> None:
        """Keep the current text in the recovery copy (a killed server loses no edit)."""
        try:
            text = self.text()
            meta = {
                "name": self.name,
                "origin": self.origin,
                "time": time.strftime("%Y-%m-%d %H:%M:%S"),
                "sha256": _sha(text),
            }
            self.files.save_recovery(text, meta)
        except (OSError, CCUError) as exc:  # the page says so; the edit itself is not lost
            self.notice = f"could not write the recovery copy: {exc}"
