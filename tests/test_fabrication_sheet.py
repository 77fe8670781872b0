"""The assembly sheet: SVG and PDF written, with the plate ids, stack order and assembly text."""

from __future__ import annotations

import re

import pytest

matplotlib = pytest.importorskip("matplotlib")

from compas_ccu.fabrication.sheet import write_assembly_sheet, write_assembly_sheets  # noqa: E402


@pytest.fixture(scope="module")
def data(vault_fab_data):
    return vault_fab_data


@pytest.fixture(scope="module")
def svg_text(data, tmp_path_factory):
    path = tmp_path_factory.mktemp("sheet") / "assembly.svg"
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        out = write_assembly_sheet(data, path)
    assert out == path
    assert path.stat().st_size > 10_000
    return path.read_text(encoding="utf-8")


def _texts(svg: str) -> list:
    return [t.strip() for t in re.findall(r"<text[^>]*>([^<]*)</text>", svg)]


def test_svg_has_every_plate_and_its_stack_position(data, svg_text):
    texts = _texts(svg_text)
    p = len(data.plate_ids)
    assert len(texts) > 2 * p
    for i, pid in enumerate(data.plate_ids):
        assert f"P{pid}" in texts  # the plate id in large type on its pattern (and the section)
        assert texts.count(f"P{pid}") >= 2
        assert f"stack {data.stack_position[i] + 1} of {p}" in texts
    joined = " ".join(texts)
    assert "stack" in joined.lower()


def test_svg_title_and_assembly(data, svg_text):
    joined = " ".join(_texts(svg_text))
    assert data.name in joined and data.material in joined
    p = len(data.plate_ids)
    assert f"t = {data.thickness * 1000:g} mm" in joined
    assert f"stack height \u03a3t = {p * data.thickness * 1000:g} mm" in joined
    assert "face up" in joined
    # bottom-to-top order, each plate with the hinge strips joining it to the plates below:
    # the vault's ids follow the stack, so plate k + 1 comes with crease k
    text = re.sub(r"\s+", " ", joined)
    assert data.plate_ids == data.stack_position == list(range(p))
    faces = data.metadata["pairing"]
    # without steps the sheet has those of the plates whole: lay, then glue (steps 1, 2-3, ...)
    assert f"1. lay P0 UP face up on the table (stack 1 of {p})" in text
    for k in range(1, p):
        assert (
            f"{2 * k}-{2 * k + 1}. lay P{k} UP face up on P{k - 1} (stack {k + 1} of {p}); "
            f"glue hinge C{k - 1} P{k - 1}/P{k} {faces[k - 1][:3]}"
        ) in text
    for c in data.creases:
        assert sorted(c["plates"]) == [c["id"], c["id"] + 1]
        assert f"c{c['id']}" in _texts(svg_text)  # the crease marker in the stack section


def test_pdf(data, tmp_path, svg_text):
    path = write_assembly_sheet(data, tmp_path / "assembly.pdf")
    blob = path.read_bytes()
    assert blob.startswith(b"%PDF")
    assert len(blob) > 10_000
    assert blob.rstrip().endswith(b"%%EOF")
    # the page drawn once for both files gives the bytes of one drawing per file
    both = write_assembly_sheets(data, [tmp_path / "once.svg", str(tmp_path / "once.pdf")])
    assert both == [tmp_path / "once.svg", tmp_path / "once.pdf"]
    assert both[1].read_bytes() == blob
    assert both[0].read_text(encoding="utf-8") == svg_text
    # re-read by pypdf: DejaVu Sans and its bold, each embedded once (matplotlib 3.11 embeds the
    # regular face again, a fontTools subsetting more, for α, β, − and the "fl" ligature unless
    # told otherwise), and the text holds the Greek letters and the "fl" the sheet writes
    pypdf = pytest.importorskip("pypdf")
    page = pypdf.PdfReader(str(path)).pages[0]
    fonts = page["/Resources"]["/Font"]
    names = sorted(str(fonts[key].get_object()["/BaseFont"]).split("+")[-1] for key in fonts)
    assert names == ["DejaVuSans", "DejaVuSans-Bold"]
    text = page.extract_text()
    assert "α" in text and "fl" in text


def test_bad_suffix(data, tmp_path):
    with pytest.raises(ValueError, match=r"\.docx"):
        write_assembly_sheet(data, tmp_path / "assembly.docx")
    with pytest.raises(ValueError, match=r"\.docx"):  # before anything is written
        write_assembly_sheets(data, [tmp_path / "a.svg", tmp_path / "a.docx"])
    assert list(tmp_path.iterdir()) == []
