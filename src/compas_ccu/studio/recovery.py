"""The recovery copies of the studio's session: every valid change kept, restored or offered.

Every valid change of a :class:`~compas_ccu.studio.session.StudioSession` is written to the
recovery copy of its design file in the output folder (:meth:`SessionRecovery._recover`, so a
killed server loses no edit). When the studio starts again on the same file, the copy is
restored if the file is as it was when the copy was made, and *offered* (:class:`Recovery`:
restore it or keep the file, :meth:`SessionRecovery.restore_recovery`,
:meth:`SessionRecovery.discard_recovery`) when the file changed since.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

from compas_ccu.errors import CCUError, OptionError
from compas_ccu.studio.documents import clone_document, parse_document
from compas_ccu.studio.files import sha256

__all__ = ["Recovery", "SessionRecovery"]


@dataclass(frozen=True)
class Recovery:
    """A recovery copy older than its design file on disk (the file changed since): offered,
    never restored silently. ``time`` is when it was written, ``text`` the design it holds."""

    path: Path
    text: str
    time: str


class SessionRecovery:
    """The recovery copy of a session's design file (a part of
    :class:`~compas_ccu.studio.session.StudioSession`)."""

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
            document = parse_document(f"the recovery copy of {self.name}", offer.text)
            model, problem = self._build(document)
            self.recovery = None
            self.files.clear_recovery(offer.path, "offered")
            self._draft = None
            self._undo.append(self._document)
            self._redo.clear()
            self._document, self.problem = document, problem
            self._valid_problem = problem
            self.source = offer.text
            self._source_values = clone_document(document)
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

    #: Write the recovery copy when :meth:`write_recovery` is called rather than at once (the
    #: studio writes it when the checks panel of the change is shown: it is not on the way
    #: there). Every valid change still reaches the copy.
    defer_recovery = False
    _recovery_due = False

    def _recover(self) -> None:
        """Keep the valid design in the recovery copy of its file (a killed server loses no
        edit); with :attr:`defer_recovery`, at the next :meth:`write_recovery`."""
        if self.defer_recovery:
            self._recovery_due = True
            return
        self._write_recovery()

    def write_recovery(self) -> bool:
        """Write the recovery copy of the valid design if a change since the last one is not
        in it yet (:attr:`defer_recovery`); True if it was written."""
        with self.lock:
            if not self._recovery_due:
                return False
            self._write_recovery()
            return True

    def _write_recovery(self) -> None:
        self._recovery_due = False
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
