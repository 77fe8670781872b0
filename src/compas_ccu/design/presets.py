"""Design templates to start from: ``ccu new --preset vault|dome|funnel|cone|quadrants NAME.toml``.

Every preset is a commented design file in the package (``compas_ccu/data/presets``): each key
has a comment on what it does, and the header points to ``docs/design-files.md``. Every preset
loads, deploys and passes its collision and bending checks as written.

>>> sorted(PRESETS)
['cone', 'dome', 'funnel', 'quadrants', 'vault']
>>> [line for line in preset_text("dome", name="my-dome").splitlines() if "name =" in line]
['name = "my-dome"              # used in file names and reports']
"""

from __future__ import annotations

import re
from pathlib import Path

from compas_ccu.design.document import Design, parse_toml
from compas_ccu.errors import OptionError

__all__ = ["PRESETS", "PRESET_DIR", "preset_text", "write_preset"]

#: The folder of the preset design files.
PRESET_DIR = Path(__file__).resolve().parents[1] / "data" / "presets"

#: Preset name -> what it is.
PRESETS = {
    "vault": "corrugated vault, 10 plates, arc creases in parallel planes (paper Fig. 1)",
    "dome": "radial half dome, 12 plates turned by 15 deg about a vertical axis (Fig. 12b)",
    "funnel": "funnel column, 12 radial plates, profile rising outwards (Fig. 12c)",
    "cone": "one circular crease with radial rulings: two cones (the cone case)",
    "quadrants": "the four quadrants of one crease: CCU and CCF (Fig. 2)",
}

_NAME_LINE = re.compile(r'^(name = "[^"\n]*")( *)', re.MULTILINE)


def _check(preset: str) -> None:
    if preset not in PRESETS:
        raise OptionError(f"--preset must be one of {', '.join(PRESETS)}, got {preset!r}")


def preset_text(preset: str, *, name: str | None = None) -> str:
    """The commented TOML text of a preset, with ``[design] name`` set to ``name``.

    Raises
    ------
    OptionError
        ``preset`` is not one of :data:`PRESETS`.
    """
    _check(preset)
    text = (PRESET_DIR / f"{preset}.toml").read_text(encoding="utf-8")
    if name is not None:
        text = _NAME_LINE.sub(lambda m: _named(m, name), text, count=1)
    return text


def _named(match, name: str) -> str:
    """The name line with the new name, its comment kept in its column."""
    line = f"name = {_toml_string(name)}"
    width = len(match.group(1)) + len(match.group(2))
    return line + " " * max(width - len(line), 1 if match.group(2) else 0)


def _toml_string(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def write_preset(preset: str, path, *, force: bool = False) -> Design:
    """Write the preset ``preset`` to ``path`` (named after the file) and return its design.

    Parameters
    ----------
    preset : str
        One of :data:`PRESETS`.
    path : path-like
        The new design file, ``NAME.toml``.
    force : bool, optional
        Overwrite an existing file.

    Raises
    ------
    OptionError
        An unknown preset, a path that does not end in ``.toml``, or an existing file without
        ``force``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "hall.toml"
    >>> design = write_preset("vault", path)
    >>> design.name, design.layout.plates, design.plates.thickness
    ('hall', 10, 0.006)
    """
    _check(preset)
    path = Path(path)
    if path.suffix != ".toml":
        raise OptionError(f"the new design file must end in .toml, got {str(path)!r}")
    if path.exists() and not force:
        raise OptionError(f"{str(path)!r} exists: not overwritten (--force overwrites it)")
    text = preset_text(preset, name=path.stem)
    design = Design(parse_toml(text), name=path.stem)
    path.write_text(text, encoding="utf-8")
    return design
