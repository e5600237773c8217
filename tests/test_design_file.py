"""Design files (TOML): every kind, and errors that name the key."""

from __future__ import annotations

from pathlib import Path

import pytest

from origami_cad.errors import DesignError
from origami_cad.pattern import write_pattern
from origami_cad.pattern.design import load_design, load_pattern_source, miura_design

TG = """
[pattern]
kind = "transition-graph"
unit_width = 36.0
copies = 3
entry_flag = 1
start = [0.0, 0.0]
fold_ratio = 0.5
vectors = [[40, 0], [30, 25], [30, -10], [40, 15], [30, 0]]
hypar_base = false
"""


def write(tmp_path, text, name="d.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_tg_from_vectors_and_from_design_variables_agree(tmp_path):
    a = load_design(write(tmp_path, TG))
    assert a.kind == "transition-graph" and a.tg is not None
    variables = f"""
[pattern]
kind = "transition-graph"
unit_width = 36.0
copies = 3
entry_flag = 1
lengths = {list(a.tg.lengths)}
shape_angles = {list(a.tg.shape_angles)}
"""
    b = load_design(write(tmp_path, variables, "v.toml"))
    assert b.pattern.same_graph(a.pattern, tolerance=1e-9)


def test_miura_and_file_kinds(tmp_path):
    m = load_design(
        write(
            tmp_path,
            '[pattern]\nkind = "miura"\nrows = 4\ncolumns = 6\npanel_length = 20.0\n'
            "panel_width = 30.0\nsector_angle = 60.0\n",
        )
    )
    assert m.pattern.same_graph(miura_design(4, 6, 20.0, 30.0, 60.0).pattern)
    write_pattern(m.pattern, tmp_path / "sub" / "m.fold")
    f = load_design(write(tmp_path, '[pattern]\nkind = "file"\npath = "sub/m.fold"\n', "f.toml"))
    assert f.tg is None and f.pattern.same_graph(m.pattern)
    assert load_pattern_source(tmp_path / "sub" / "m.fold").pattern.same_graph(m.pattern)


@pytest.mark.parametrize(
    "change, message",
    [
        (("copies = 3", "copies = 3\ncolour = 1"), "unknown key 'colour'"),
        (("copies = 3\n", ""), "missing key 'copies'"),
        (("copies = 3", 'copies = "three"'), "key 'copies': expected an integer"),
        (("unit_width = 36.0", "unit_width = -1.0"), "key 'unit_width': -1 is out of range"),
        (("entry_flag = 1", "entry_flag = 2"), "key 'entry_flag': 2 is out of range"),
        (("fold_ratio = 0.5", "fold_ratio = 0.0"), "key 'fold_ratio'"),
        (("[30, 25]", "[-30, 25]"), "key 'vectors': item 1: length must be > 0"),
        (('kind = "transition-graph"', 'kind = "kirigami"'), "key 'kind': 'kirigami' is not"),
        (("[30, -10]", "[30, 24]"), r"vectors\[2\]"),
        (("hypar_base = false", "hypar_base = 1"), "key 'hypar_base': expected true or false"),
    ],
)
def test_errors_name_the_file_and_key(tmp_path, change, message):
    path = write(tmp_path, TG.replace(*change))
    with pytest.raises(DesignError, match=message) as info:
        load_design(path)
    assert "d.toml" in str(info.value)


def test_other_bad_files(tmp_path):
    with pytest.raises(DesignError, match="no such file"):
        load_design(tmp_path / "none.toml")
    with pytest.raises(DesignError, match="not valid TOML"):
        load_design(write(tmp_path, "[pattern\nkind ="))
    with pytest.raises(DesignError, match=r"missing key 'pattern'$"):
        load_design(write(tmp_path, "[other]\n"))
    # another of the package's files given for a design says what it is
    examples = Path(__file__).resolve().parents[1] / "examples"
    for name, kind in [("crawler/crawler.toml", "a robot file"), ("arm_task.toml", "arm"),
                       ("miura_route.toml", "route"), ("arm_fold.toml", "sequence")]:  # fmt: skip
        with pytest.raises(DesignError, match=f"{name}: missing key 'pattern': it is .*{kind}"):
            load_design(examples / name)
    with pytest.raises(DesignError, match="either 'vectors'"):
        load_design(write(tmp_path, TG.replace("hypar_base = false", "lengths = [1.0]")))
    with pytest.raises(DesignError, match="no such file"):
        load_design(write(tmp_path, '[pattern]\nkind = "file"\npath = "gone.dxf"\n'))
