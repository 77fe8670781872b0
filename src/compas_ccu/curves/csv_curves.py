"""The curve of a CSV / TXT file: one point a line, ``x, y`` or ``x, y, z`` (NumPy only).

Fields are separated by commas, semicolons, tabs or spaces; ``#`` starts a comment and a first
line that is not numbers is a header. A regular file is parsed by NumPy in one call; a ragged,
malformed or non-finite one is read line by line, and the message names the line.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from compas_ccu import limits
from compas_ccu.curves.candidates import Candidate
from compas_ccu.errors import ProfileError

__all__ = ["csv_candidates"]

_SPLIT = re.compile(r"[,;\s]+")


_COMMENT = re.compile(r"#[^\n]*")
_TO_SPACE = str.maketrans({",": " ", ";": " ", "\t": " ", "\r": "\n", "\f": " ", "\v": " "})


def csv_candidates(path: Path):
    """The one curve of a CSV / TXT file, its units (``m``) and no unit factor.

    Returns
    -------
    candidates : list of Candidate
        One candidate: the points in file order.
    units : str
        ``"m"`` (the file holds no units).
    factor : None

    Raises
    ------
    ProfileError
        The file is unreadable, or a line is not 2 or 3 finite numbers (named by its number).

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> path = Path(tempfile.mkdtemp()) / "crease.csv"
    >>> _ = path.write_text("0,0\\n0.5,0.25\\n1,0\\n")
    >>> candidates, units, factor = csv_candidates(path)
    >>> len(candidates), units, factor, candidates[0].label
    (1, 'm', None, '3 points')
    >>> candidates[0].sample(None).tolist()
    [[0.0, 0.0, 0.0], [0.5, 0.25, 0.0], [1.0, 0.0, 0.0]]
    """
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ProfileError(f"cannot read {str(path)!r}: {exc}") from exc
    limits.check("points", text.count("\n"), what=f"lines of {path.name}")
    points = _csv_fast(text)
    if points is None:  # ragged, malformed or non-finite: the line-by-line reading names it
        points = _csv_lines(path, text)
    candidate = Candidate(f"{len(points)} points", None, None, lambda tol: points)
    return [candidate], "m", None


def _csv_fast(text: str):
    """The points of a CSV / TXT text whose rows all have 2 or all 3 finite numbers (after an
    optional header line), parsed by NumPy; None for anything else."""
    if "#" in text:
        text = _COMMENT.sub("", text)
    clean = text.translate(_TO_SPACE)
    clean = clean.lstrip()  # leading blank lines
    end = clean.find("\n")
    first = clean if end < 0 else clean[:end]
    try:
        [float(f) for f in first.split()]
    except ValueError:  # a header line
        clean = "" if end < 0 else clean[end + 1 :]
    data = clean.split()
    try:
        values = np.array(data, dtype=float)
    except ValueError:
        return None
    if not len(values) or not np.isfinite(values).all():
        return None
    # the fields of every non-empty line: a field starts where a blank is followed by a non-blank
    b = np.frombuffer(clean.encode("utf-8"), dtype=np.uint8)
    blank = (b == 32) | (b == 10)
    starts = np.flatnonzero(~blank & np.r_[True, blank[:-1]])
    line = np.searchsorted(np.flatnonzero(b == 10), starts)  # ascending line numbers
    counts = np.diff(np.r_[0, np.flatnonzero(np.diff(line)) + 1, len(line)])
    width = int(counts[0])
    if width not in (2, 3) or (counts != width).any():
        return None
    points = values.reshape(-1, width)
    return np.c_[points, np.zeros(len(points))] if width == 2 else points


def _csv_lines(path: Path, text: str):
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f for f in _SPLIT.split(line) if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            if not rows:  # a header
                continue
            raise ProfileError(f"{str(path)!r} line {number}: not numbers: {line[:60]!r}") from None
        if len(values) not in (2, 3) or not all(map(math.isfinite, values)):
            raise ProfileError(
                f"{str(path)!r} line {number}: a point is 2 or 3 finite numbers, got {line[:60]!r}"
            )
        rows.append(values + [0.0] * (3 - len(values)))
    return np.array(rows, dtype=float).reshape(-1, 3)
