"""A target or a scan uploaded from the studio's page, kept in the design folder.

The browser sends the file's name and bytes (viser's upload button). :func:`save_upload`
writes them only inside the design folder, into its :data:`UPLOAD_FOLDER` (``targets/``):
the name is checked (:func:`upload_name`: no folders, no ``..``, no hidden name, a target
format's suffix), a name in use gets a number (an existing file is never replaced), the size
is at most :data:`UPLOAD_BYTES`, and the bytes go to a temporary file linked to the name (the
file appears whole or not at all). :func:`read_upload` reads it with
:func:`~compas_ccu.studio.target.load_target` (the studio runs it in a background process)
and removes a file that does not read.
"""

from __future__ import annotations

import errno
import os
import tempfile
from pathlib import Path

from compas_ccu.errors import LimitError, OptionError
from compas_ccu.fit.points import FORMATS
from compas_ccu.studio.target import load_target

__all__ = ["UPLOAD_BYTES", "UPLOAD_FOLDER", "upload_name", "save_upload", "read_upload"]
__all__ += ["discard_upload"]

#: The largest target or scan the page takes as an upload, bytes (200 MB).
UPLOAD_BYTES = 200_000_000
#: The folder of the design folder uploaded targets are written into.
UPLOAD_FOLDER = "targets"
#: Characters a file name may not hold (besides control characters and folders).
_BAD_CHARACTERS = '<>:"|?*'


def upload_name(name) -> str:
    """The checked name of an uploaded target (the browser sends the file's own name).

    >>> upload_name(" scan.XYZ ")
    'scan.XYZ'

    Raises
    ------
    OptionError
        One line naming the value: empty, a folder in it (``/``, ``\\``, ``..``), a hidden
        name (``.scan.xyz``), a character a file name cannot hold, longer than 100
        characters, or a suffix other than the target formats.
    """
    text = str(name).strip()
    if not text:
        raise OptionError("the uploaded file has no name")
    if "/" in text or "\\" in text or text in (".", ".."):
        raise OptionError(f"{text!r}: an uploaded file name has no folders ('/', '\\' or '..')")
    if text.startswith("."):
        raise OptionError(f"{text!r}: a hidden file name (starting with '.') is not taken")
    if len(text) > 100 or any(c in _BAD_CHARACTERS or ord(c) < 32 or ord(c) == 127 for c in text):
        raise OptionError(f"{text!r}: give the file a plain name of at most 100 characters")
    if Path(text).suffix.lower() not in FORMATS:
        raise OptionError(f"{text!r}: a target is one of {', '.join(FORMATS)}")
    return text


def _claim(tmp: str, path: Path) -> bool:
    """Give the complete file ``tmp`` the name ``path`` unless that name is in use (False)."""
    try:
        os.link(tmp, path)  # atomic, and never replaces a file
        return True
    except FileExistsError:
        return False
    except OSError as exc:
        if exc.errno not in (errno.EPERM, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EMLINK):
            raise
    # a file system without hard links: reserve the name, then rename the whole file onto it
    try:
        os.close(os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
    except FileExistsError:
        return False
    os.replace(tmp, path)
    return True


def save_upload(files, name, content: bytes, *, limit: int = UPLOAD_BYTES) -> str:
    """Write an uploaded target into the design folder's :data:`UPLOAD_FOLDER` under its
    checked name (:func:`upload_name`); a name in use gets ``-2``, ``-3``, ...

    Parameters
    ----------
    files : StudioFiles
        The studio's folders (the file is written inside the design folder only).
    name : str
        The name the browser sent.
    content : bytes
    limit : int
        The most bytes taken (:data:`UPLOAD_BYTES`).

    Returns
    -------
    str
        The name relative to the design folder (``targets/scan.xyz``), as
        :func:`~compas_ccu.studio.target.load_target` takes it.

    Raises
    ------
    LimitError
        More than ``limit`` bytes, or none.
    OptionError
        A refused name, a folder leading out of the design folder, or the file cannot be
        written (one line; nothing is left behind).
    """
    checked = upload_name(name)
    size = len(content)
    if size > limit:
        raise LimitError(
            f"{checked!r} is {size / 1e6:,.1f} MB; an uploaded target may have at most "
            f"{limit / 1e6:,.0f} MB (copy a larger one into the design folder and Load it)"
        )
    if size == 0:
        raise LimitError(f"{checked!r} is empty (0 bytes)")
    stem, suffix = Path(checked).stem, Path(checked).suffix
    folder = files.inside(f"{UPLOAD_FOLDER}/{checked}", suffix=None).parent
    tmp = None
    try:
        folder.mkdir(exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".upload-", suffix=".tmp", dir=folder)
        with os.fdopen(fd, "wb") as f:
            f.write(content)
            f.flush()
            os.fsync(f.fileno())
        for n in range(1, 1000):
            rel = f"{UPLOAD_FOLDER}/{stem}{'' if n == 1 else f'-{n}'}{suffix}"
            if _claim(tmp, files.inside(rel, suffix=None)):
                return rel
        raise OptionError(f"{checked!r}: {folder} holds 999 files of that name; rename it")
    except OSError as exc:
        raise OptionError(
            f"{checked!r} cannot be written into {folder}: {exc.strerror or exc}"
        ) from None
    finally:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)


def read_upload(files, name: str) -> dict:
    """Read the uploaded target ``name`` with :func:`~compas_ccu.studio.target.load_target`
    (what the background process runs); a file that does not read is removed.

    Returns
    -------
    dict
        ``target`` (a :class:`~compas_ccu.studio.target.StudioTarget`) or ``error`` (one line
        naming the file and the cause).
    """
    try:
        return {"target": load_target(files, name)}
    except Exception as exc:  # noqa: BLE001 - any reader failure is the file's fault
        discard_upload(files, name)
        cause = " ".join(str(exc).split()) or type(exc).__name__
        return {"error": f"{name!r} is not a target and was removed: {cause}"}


def discard_upload(files, name: str) -> None:
    """Remove the uploaded target ``name`` (a file of :data:`UPLOAD_FOLDER` only)."""
    path = files.inside(name, suffix=None)
    if path.parent == (files.design_folder / UPLOAD_FOLDER).resolve():
        path.unlink(missing_ok=True)
