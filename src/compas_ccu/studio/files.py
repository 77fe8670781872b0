"""The studio's file access: two folders, atomic writes and the recovery copies.

The studio reads and writes only inside the folder of the design it opened (the *design
folder*) and the output folder the user chose. Every name that comes from the page (a file to
open, a "save as" name) is resolved by :meth:`StudioFiles.inside`, which refuses absolute paths,
``..`` components, the studio's own folder ``.ccu-studio/`` and symbolic links that lead out of
the folder, naming the value. Curve files named by a design are read only inside the design
folder or a folder named on the command line (:meth:`StudioFiles.check_curve_files`).

The recovery copy belongs to one design file: ``OUT/.ccu-studio/<hash of its absolute
path>/``, with the hash of the file's content it was made from, so two folders with a
``vault.toml`` sharing one output folder never exchange edits, and a copy older than the file
on disk is offered rather than restored.
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import tempfile
from pathlib import Path

from compas_ccu.design.schema import CURVE_FILE_PLACES
from compas_ccu.errors import DesignError, LimitError, OptionError
from compas_ccu.limits import LIMITS

__all__ = ["StudioFiles", "atomic_write", "MAX_DEPTH", "decode_upload", "nesting_depth", "sha256"]

#: The deepest nesting of arrays and tables a design file may have (a design needs 4).
MAX_DEPTH = 32


def sha256(text: str) -> str:
    """Hex SHA-256 of ``text`` (UTF-8)."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _new_file_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def atomic_write(path: Path, text: str) -> Path:
    """Write ``text`` to ``path`` through a temporary file in the same folder and a rename.

    A reader sees the old file or the new one, never a part; if anything fails the old file is
    left as it was (nothing is removed but the temporary file). The new file keeps the
    permission bits of the file it replaces (a new file gets the umask's).
    """
    path = Path(path)
    try:
        mode = stat.S_IMODE(os.stat(path).st_mode)
    except FileNotFoundError:
        mode = _new_file_mode()
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def nesting_depth(text: str) -> int:
    """The deepest nesting of ``[`` / ``{`` brackets in TOML ``text`` outside strings and
    comments (a linear scan: a file nested 10⁵ deep is measured, not parsed).

    >>> nesting_depth("a = [[1, 2], [3]]  # [[[")
    2
    """
    depth = deepest = 0
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if c in "\"'":
            triple = text.startswith(c * 3, i)
            end = text.find(c * 3, i + 3) if triple else i + 1
            if not triple:
                while end < n and text[end] != c and text[end] != "\n":
                    end += 2 if (c == '"' and text[end] == "\\") else 1
            i = (end + (3 if triple else 1)) if end >= 0 else n
            at_line_start = False
            continue
        if c == "#":
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        if c == "\n":
            at_line_start = True
        elif c in "[{" and not (at_line_start and depth == 0 and c == "["):
            depth += 1
            deepest = max(deepest, depth)
        elif c in "]}" and depth > 0:
            depth -= 1
        elif c == "=" or not c.isspace():
            at_line_start = at_line_start and c == "["
        i += 1
    return deepest


def decode_upload(name: str, content: bytes) -> str:
    """The text of a design file (an upload or a file of the design folder).

    Raises
    ------
    LimitError
        The file is larger than ``compas_ccu.limits.LIMITS.upload_bytes`` (1 MB).
    OptionError
        Not UTF-8 text (a binary file), or nested deeper than :data:`MAX_DEPTH`.
    """
    limit = LIMITS.upload_bytes
    if len(content) > limit:
        raise LimitError(
            f"{name!r} is {len(content):,} bytes; a design file may have at most {limit:,} "
            f"bytes (the limit upload_bytes; raise it with --limit upload_bytes={len(content)})"
        )
    try:
        text = content.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise OptionError(
            f"{name!r} is not a text file (byte {exc.start} is not UTF-8): open a design TOML"
        ) from None
    if "\x00" in text:
        raise OptionError(f"{name!r} is not a text file (it holds NUL bytes): open a design TOML")
    depth = nesting_depth(text)
    if depth > MAX_DEPTH:
        raise OptionError(
            f"{name!r} nests arrays or tables {depth} deep; a design file nests at most "
            f"{MAX_DEPTH} deep"
        )
    return text


def _is_inside(path: Path, root: Path) -> bool:
    return path == root or root in path.parents


class StudioFiles:
    """The design folder and the output folder, and the only ways the studio touches files.

    Parameters
    ----------
    design_folder : path
        Folder of the opened design; designs are opened from and saved into it.
    out : path
        Output folder: exports and the recovery copies (``.ccu-studio/``).
    allowed : sequence of path, optional
        Further folders curve files may be read from (``ccu studio --allow-dir``).
    """

    RECOVERY = ".ccu-studio"

    def __init__(self, design_folder, out, allowed=()):
        self.design_folder = Path(design_folder).expanduser().resolve()
        self.out = Path(out).expanduser().resolve()
        self.allowed = tuple(Path(a).expanduser().resolve() for a in allowed)

    def inside(self, name, *, folder: str = "design", suffix: str | None = ".toml") -> Path:
        """The path of ``name`` inside the design (or output) folder.

        Raises
        ------
        OptionError
            ``name`` is empty, absolute, has a ``..`` component, has the wrong suffix, lies in
            the studio's own folder ``.ccu-studio/``, or resolves (through a symbolic link) to
            a place outside the folder.
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
        if not _is_inside(path, root):
            raise OptionError(
                f"{text!r} leads outside the {folder} folder {root} (a symbolic link?)"
            )
        if self.RECOVERY in rel.parts or _is_inside(path, self.recovery_folder):
            raise OptionError(
                f"{text!r}: {self.RECOVERY}/ is the studio's own folder (recovery copies); "
                "give a name outside it"
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

    def check_curve_files(self, document: dict) -> None:
        """Refuse a document whose curve files lie outside the design folder and the allowed
        folders (a design opened in the studio may come from anyone).

        Raises
        ------
        DesignError
            Naming the key, the file and the folders it may be in.
        """
        roots = (self.design_folder,) + self.allowed
        for place in CURVE_FILE_PLACES:
            section, key = place.split(".")
            table = document.get(section)
            value = table.get(key) if isinstance(table, dict) else None
            if isinstance(value, dict):
                value = value.get("file")
            if not isinstance(value, str):
                continue
            path = Path(value).expanduser()
            path = (path if path.is_absolute() else self.design_folder / path).resolve()
            if not any(_is_inside(path, root) for root in roots):
                where = " or ".join(str(r) for r in roots)
                raise DesignError(
                    f"curve file {value!r} ({path}) is outside the design folder {where}; the "
                    "studio reads curve files only there (name another folder with "
                    "ccu studio --allow-dir DIR)",
                    key=place,
                )

    # -- the recovery copies -------------------------------------------------------------------
    @property
    def recovery_folder(self) -> Path:
        return self.out / self.RECOVERY

    def recovery_of(self, path) -> Path:
        """The folder of the recovery copy of design file ``path`` (absolute)."""
        key = sha256(str(Path(path).resolve()))[:24]
        return self.recovery_folder / key

    def save_recovery(self, path, text: str, meta: dict) -> None:
        """Keep ``text`` (the design being edited) and ``meta`` so a restart restores it."""
        folder = self.recovery_of(path)
        folder.mkdir(parents=True, exist_ok=True)
        meta = {**meta, "path": str(Path(path).resolve())}
        atomic_write(folder / "recovery.toml", text)
        atomic_write(folder / "recovery.json", json.dumps(meta, indent=1) + "\n")

    def load_recovery(self, path, kind: str = "recovery"):
        """``(text, meta)`` of the recovery copy of ``path`` (``kind="offered"``: the copy set
        aside because the file changed since), or None."""
        folder = self.recovery_of(path)
        try:
            text = (folder / f"{kind}.toml").read_text("utf-8")
            meta = json.loads((folder / f"{kind}.json").read_text("utf-8"))
        except (OSError, ValueError):
            return None
        if not isinstance(meta, dict) or meta.get("path") != str(Path(path).resolve()):
            return None
        return text, meta

    def set_aside(self, path) -> None:
        """Keep the recovery copy of ``path`` as the *offered* one (the file changed since it
        was made: the user chooses)."""
        folder = self.recovery_of(path)
        for suffix in (".toml", ".json"):
            os.replace(folder / f"recovery{suffix}", folder / f"offered{suffix}")

    def clear_recovery(self, path, kind: str = "recovery") -> None:
        folder = self.recovery_of(path)
        for suffix in (".toml", ".json"):
            (folder / f"{kind}{suffix}").unlink(missing_ok=True)
        try:
            folder.rmdir()
        except OSError:  # not empty (the other kind) or gone
            pass
