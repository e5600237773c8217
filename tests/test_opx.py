"""ORIPA's .opx: written and read back, ORIPA's conventions (types, y down, omitted zeros),
and hostile XML refused with one line."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest

from origami_cad.cli import main
from origami_cad.errors import PatternError
from origami_cad.pattern import CreasePattern, miura_pattern, read_pattern, write_pattern
from origami_cad.pattern.formats.opx import MAX_DEPTH

HEAD = (
    '<?xml version="1.0" encoding="UTF-8"?>\n<java version="1.8.0" class="java.beans.XMLDecoder">'
)


def line(kind: int | None, x0=None, y0=None, x1=None, y1=None) -> str:
    """One OriLineProxy as XMLEncoder writes it: properties at their default left out."""
    props = ""
    for name, value in (("type", kind), ("x0", x0), ("x1", x1), ("y0", y0), ("y1", y1)):
        if value is not None:
            tag = "int" if name == "type" else "double"
            props += f'<void property="{name}"><{tag}>{value}</{tag}></void>'
    return f'<void index="0"><object class="oripa.OriLineProxy">{props}</object></void>'


def opx(tmp_path, *lines: str, head: str = HEAD) -> str:
    body = "".join(lines)
    p = tmp_path / "cp.opx"
    p.write_text(
        f'{head}<object class="oripa.DataSet"><void property="lines"><array '
        f'class="oripa.OriLineProxy" length="{len(lines)}">{body}</array></void>'
        '<void property="mainVersion"><int>1</int></void></object></java>',
        encoding="utf-8",
    )
    return str(p)


# ORIPA's unit square of side 200 centred on the origin, y down, with a valley diagonal and a
# mountain from the centre; x0 = 0 and y0 = 0 are left out, as XMLEncoder does
SHEET = [
    line(1, -100, -100, 100, -100),
    line(1, 100, -100, 100, 100),
    line(1, 100, 100, -100, 100),
    line(1, -100, 100, -100, -100),
    line(3, -100, -100, 100, 100),
    line(2, None, None, 100, -100),  # from (0, 0), both left out
    line(0, -100, 100, None, None),  # an auxiliary line: flat
]


def test_oripa_conventions(tmp_path):
    cp = read_pattern(opx(tmp_path, *SHEET))
    letters = {str(a): int((cp.assignments == a).sum()) for a in "BCMVF"}
    assert letters == {"B": 4, "C": 0, "M": 1, "V": 2, "F": 1}  # outline cuts are border
    assert cp.bounds == (-100.0, -100.0, 100.0, 100.0)
    # y down in ORIPA: its (100, -100) is our (100, 100)
    m = np.flatnonzero(cp.assignments == "M")[0]
    ends = {tuple(cp.vertices[v].tolist()) for v in cp.edges[m]}
    assert ends == {(0.0, 0.0), (100.0, 100.0)}
    assert "ORIPA unit" in cp.metadata["source_unit"]


def test_written_and_read_back(tmp_path):
    miura = miura_pattern(4, 6, 20.0, 30.0, 60.0).with_metadata(title="Miura & <co>")
    write_pattern(miura, tmp_path / "m.opx")
    back = read_pattern(tmp_path / "m.opx")
    assert back.same_graph(miura) and back.title == "Miura & <co>"
    # interior cuts stay cuts, facets and free hinges keep their letters
    verts = np.vstack([[[0, 0], [100, 0], [100, 100], [0, 100]], [[50, 20], [50, 80]]])
    edges = [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2], [4, 5], [1, 3]]
    cp = CreasePattern(verts, edges, "BBBBFCU")
    write_pattern(cp, tmp_path / "c.opx")
    again = read_pattern(tmp_path / "c.opx")
    assert again.same_graph(cp)
    # what ORIPA reads: y turned over, the types as numbers
    root = ET.parse(tmp_path / "c.opx").getroot()
    assert root.tag == "java" and root[0].get("class") == "oripa.DataSet"
    proxies = [o for o in root.iter("object") if o.get("class") == "oripa.OriLineProxy"]
    kinds = sorted(int(o.find("void[@property='type']/int").text) for o in proxies)
    n = {a: int((cp.assignments == a).sum()) for a in "BCFU"}
    assert kinds.count(1) == n["B"] + n["C"] and n["C"] > 0  # the outline and the slit: cuts
    assert kinds.count(0) == n["F"] > 0 and kinds.count(4) == n["U"] > 0


def test_a_join_edge_has_no_oripa_type(tmp_path):
    cp = CreasePattern([[0, 0], [10, 0], [10, 10]], [[0, 1], [1, 2], [2, 0]], "BJB")
    with pytest.raises(PatternError, match="edge 1 is a join"):
        write_pattern(cp, tmp_path / "j.opx")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize(
    "make, fragment",
    [
        (lambda t: opx(t, *SHEET, head=HEAD.replace("<java", "<!DOCTYPE j []><java")),
         "DOCTYPE"),
        (lambda t: opx(t, *SHEET[:4], line(7, 0, 0, 1, 1)), "type 7 is not an ORIPA line type"),
        (lambda t: opx(t, *SHEET[:4], line(2, 0, 0, "NaN", 1)), "x1 = nan is not finite"),
        (lambda t: opx(t, *SHEET[:4], line(2, 0, 0, "1e400", 1)), "x1 = inf is not finite"),
        (lambda t: opx(t, *SHEET[:4], line(2, 0, 0, "one", 1)), "x1 'one' is not a number"),
        (lambda t: opx(t, line(9, 0, 0, 1, 1)), "no crease lines"),
        (lambda t: opx(t, *SHEET, line(2, 0, 0, 1, 1).replace("<void index", "<g>" * (
            MAX_DEPTH) + "<void index")), "deeper than the limit"),
    ],
)  # fmt: skip
def test_bad_files_are_refused_in_one_line(tmp_path, capsys, make, fragment):
    p = make(tmp_path)
    if fragment == "deeper than the limit":  # the nesting closes, so the file is XML
        text = open(p).read().replace("</array>", "</void>" * 0 + "</g>" * MAX_DEPTH + "</array>")
        open(p, "w").write(text)
    assert main(["convert", p, str(tmp_path / "out.fold")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cp.opx" in err[0] and fragment in err[0], err
    assert not (tmp_path / "out.fold").exists()


def test_not_an_oripa_file(tmp_path):
    p = tmp_path / "x.opx"
    p.write_text("<svg/>")
    with pytest.raises(PatternError, match="not <java>"):
        read_pattern(p)
    p.write_text("<java><object class='x'/></java>")
    with pytest.raises(PatternError, match=r"oripa\.DataSet"):
        read_pattern(p)
