"""The studio's file access: two folders, atomic writes and the recovery copy.

The studio reads and writes only inside the folder of the design it opened (the *design
folder*) and the output folder the user chose. Every name that comes from the page (a file to
open, a "save as" name) is resolved by :meth:`StudioFiles.inside`, which refuses absolute paths,
``..`` components and symbolic links that lead out of the folder, naming the value.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from compas_ccu.errors import OptionError

__all__ = ["StudioFiles", "atomic_write", "MAX_UPLOAD", "decode_upload"]

#: The largest design file the studio opens from an upload, bytes.
MAX_UPLOAD = 1_000_000


def atomic_write(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in the same folder and a rename, so
    a reader sees the old file or the new one, never a part."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def decode_upload(name: str, content: bytes) -> str:
    """The text of an uploaded design file.

    Raises
    ------
    OptionError
        The file is larger than :data:`MAX_UPLOAD`, or not UTF-8 text (a binary file).
    """
    if len(content) > MAX_UPLOAD:
        raise OptionError(
            f"{name!r} is {len(content):,} bytes; a design file may have at most "
            f"{MAX_UPLOAD:,} bytes"
        )
    try:
        text = content.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise OptionError(
            f"{name!r} is not a text file (byte {exc.start} is not UTF-8): open a design TOML"
        ) from None
    if "\x00" in text:
        raise OptionError(f"{name!r} is not a text file (it holds NUL bytes): open a design TOML")
    return text


class StudioFiles:
    """The design folder and the output folder, and the only ways the studio touches files.

    Parameters
    ----------
    design_folder : path
        Folder of the opened design; designs are opened from and saved into it.
    out : path
        Output folder: exports and the recovery copy (``.ccu-studio/``).
    """

    RECOVERY = ".ccu-studio"

    def __init__(self, design_folder, out):
        self.design_folder = Path(design_folder).expanduser().resolve()
        self.out = Path(out).expanduser().resolve()

    def inside(self, name, *, folder: str = "design", suffix: str | None = ".toml") -> Path:
        """The path of ``name`` inside the design (or output) folder.

        Raises
        ------
        OptionError
            ``name`` is empty, absolute, has a ``..`` component, has the wrong suffix, or
            resolves (through a symbolic link) to a place outside the folder.
        """
        root = self.design_folder if folder == "design" else self.out
        text = str(name).strip()
        if not text:
            raise OptionError("a file name is needed")
        rel = Path(text)
        if rel.is_absolute() or rel.drive or text.startswith(("/", "\\", "~")):
            raise OptionError(f"{text!r}: give a name inside the {folder} folder {root}")
        if any(part == ".." for part in rel.parts) or "\\" in text or "\x00" in text:
            raise OptionError(f"{text!r}: '..' and backslashes are not allowed in a file name")
        if suffix is not None and rel.suffix.lower() != suffix:
            raise OptionError(f"{text!r}: the file name must end with {suffix}")
        path = (root / rel).resolve()
        if path != root and root not in path.parents:
            raise OptionError(
                f"{text!r} leads outside the {folder} folder {root} (a symbolic link?)"
            )
        return path

    def designs(self) -> list:
        """Names of the design files (``*.toml``) in the design folder, sorted."""
        if not self.design_folder.is_dir():
            return []
        out = []
        for p in sorted(self.design_folder.glob("*.toml")):
            try:
                self.inside(p.name)
            except OptionError:  # a link out of the folder is not listed
                continue
            if p.is_file():
                out.append(p.name)
        return out

    def read(self, name) -> str:
        """The text of design file ``name`` in the design folder."""
        path = self.inside(name)
        if not path.is_file():
            raise OptionError(f"{str(name)!r}: no such design file in {self.design_folder}")
        return decode_upload(path.name, path.read_bytes())

    def write(self, name, text: str) -> Path:
        """Write design file ``name`` in the design folder atomically."""
        path = self.inside(name)
        path.parent.mkdir(parents=True, exist_ok=True)
        return atomic_write(path, text)

    # -- the recovery copy ---------------------------------------------------------------------
    @property
    def recovery_folder(self) -> Path:
        return self.out / self.RECOVERY

    def save_recovery(self, text: str, meta: dict) -> None:
        """Keep ``text`` (the design being edited) and ``meta`` so a restart restores it."""
        folder = self.recovery_folder
        folder.mkdir(parents=True, exist_ok=True)
        atomic_write(folder / "recovery.toml", text)
        atomic_write(folder / "recovery.json", json.dumps(meta, indent=1) + "\n")

    def load_recovery(self):
        """``(text, meta)`` of the recovery copy, or None."""
        folder = self.recovery_folder
        try:
            text = (folder / "recovery.toml").read_text("utf-8")
            meta = json.loads((folder / "recovery.json").read_text("utf-8"))
        except (OSError, ValueError):
            return None
        return (text, meta) if isinstance(meta, dict) else None

    def clear_recovery(self) -> None:
        for name in ("recovery.toml", "recovery.json"):
            (self.recovery_folder / name).unlink(missing_ok=True)
