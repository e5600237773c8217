"""The size of an imported pattern: declared units, overrides, and implausible sizes.

ORIPA writes every DXF 6 inches wide with no unit; ezdxf's new documents declare metres
($INSUNITS = 6). The declared unit is honoured by default; ``unit``, ``scale`` and
``width`` (``--unit``, ``--scale``, ``--width``) override it; a pattern over 5 m or under
1 mm across gets a warning that names those options.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from origami_cad.cli import main
from origami_cad.errors import DesignError, PatternError
from origami_cad.pattern import (
    Hole,
    miura_pattern,
    read_fold,
    read_fold_frames,
    read_pattern,
    size_warnings,
    write_pattern,
)
from origami_cad.pattern.design import load_design, load_pattern_source

DATA = Path(__file__).resolve().parent / "data"
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def width_height(cp) -> tuple[float, float]:
    x0, y0, x1, y1 = cp.bounds
    return x1 - x0, y1 - y0


def ezdxf_default_file(path: Path) -> Path:
    """A Miura drawn in mm-sized numbers in a new ezdxf document (which declares metres)."""
    cp = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    doc = ezdxf.new("R2010")
    assert doc.header["$INSUNITS"] == 6  # ezdxf's default: metres
    msp = doc.modelspace()
    for (a, b), letter in zip(cp.edges, cp.assignments, strict=True):
        layer = {"M": "Mountain", "V": "Valley"}.get(str(letter), "Border")
        msp.add_line(tuple(cp.vertices[a]), tuple(cp.vertices[b]), dxfattribs={"layer": layer})
    doc.saveas(path)
    return path


def oripa_file(path: Path, paper: float = 400.0) -> Path:
    """A DXF the way ORIPA's CreasePatternExporterDXF writes one: 6 in wide, no unit."""
    scale, centre = 6.0 / paper, 4.0
    h = paper / 2
    lines = [("CUT", (-h, -h), (h, -h)), ("CUT", (h, -h), (h, h)), ("CUT", (h, h), (-h, h))]
    lines += [("CUT", (-h, h), (-h, -h)), ("VALLEY", (-h, -h), (h, h))]
    layer = {"CUT": "CutLine", "VALLEY": "ValleyLine"}
    colour = {"CUT": 3, "VALLEY": 5}
    out = ["0", "SECTION", "2", "HEADER", "9", "$ACADVER", "1", "AC1009", "0", "ENDSEC"]
    out += ["0", "SECTION", "2", "ENTITIES"]
    for kind, (x0, y0), (x1, y1) in lines:
        out += ["0", "LINE", "8", layer[kind], "6", "CONTINUOUS", "62", str(colour[kind])]
        out += ["10", repr(x0 * scale + centre), "20", repr((h - y0) * scale + centre)]
        out += ["11", repr(x1 * scale + centre), "21", repr((h - y1) * scale + centre)]
    out += ["0", "ENDSEC", "0", "EOF"]
    path.write_text("\n".join(out) + "\n")
    return path


# --------------------------------------------------------------------------- library
def test_declared_metres_are_honoured_and_warned_about(tmp_path):
    path = ezdxf_default_file(tmp_path / "m.dxf")
    cp = read_pattern(path)
    mm = read_pattern(path, unit="mm")
    assert width_height(cp) == pytest.approx(tuple(1000 * v for v in width_height(mm)))
    (warning,) = size_warnings(cp)
    assert "over 5 m" in warning and "$INSUNITS = 6" in warning
    assert "--unit" in warning and "--scale" in warning and "--width" in warning
    assert width_height(mm) == pytest.approx(width_height(miura_pattern(4, 6, 20.0, 30.0, 60.0)))
    assert size_warnings(mm) == []
    assert read_pattern(path, unit=1.0).same_graph(mm)  # a number: mm per drawing unit


def test_scale_width_and_unit_combine_as_documented(tmp_path):
    path = ezdxf_default_file(tmp_path / "m.dxf")
    mm = read_pattern(path, unit="mm")
    w, h = width_height(mm)
    assert width_height(read_pattern(path, unit="cm", scale=0.5)) == pytest.approx((5 * w, 5 * h))
    wide = read_pattern(path, width=300.0)
    assert width_height(wide) == pytest.approx((300.0, 300.0 * h / w))
    assert wide.same_graph(mm.scaled(300.0 / w), tolerance=1e-9)
    for bad in ({"width": 1.0, "scale": 2.0}, {"width": 1.0, "unit": "mm"}):
        with pytest.raises(PatternError, match="not both"):
            read_pattern(path, **bad)
    for bad, message in (
        ({"scale": 0.0}, r"scale: expected a finite number in \(0"),
        ({"width": -3.0}, r"width: expected a finite number in \(0"),
        ({"unit": "furlong"}, "'furlong' is not one of mm, cm, m, in"),
        ({"unit": -2.0}, "a unit must be a length > 0 mm"),
    ):
        with pytest.raises(PatternError, match=message):
            read_pattern(path, **bad)


def test_scaled_keeps_the_graph_labels_holes_and_angles():
    cp = miura_pattern(2, 2, 20.0, 30.0, 60.0).with_holes([Hole(30.0, 15.0, 2.0)])
    cp = cp.with_face_labels(["a", "b", "c", "d"])
    big = cp.scaled(2.5)
    np.testing.assert_allclose(big.vertices, 2.5 * cp.vertices)
    assert big.face_labels == cp.face_labels and big.holes == (Hole(75.0, 37.5, 5.0),)
    np.testing.assert_array_equal(big.fold_angles, cp.fold_angles)
    assert [f.tolist() for f in big.faces] == [f.tolist() for f in cp.faces]
    assert big.notes[-1].code == "scaled" and big.tolerance == pytest.approx(2.5 * cp.tolerance)
    for factor in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(PatternError, match="finite number > 0"):
            cp.scaled(factor)


def test_a_tiny_pattern_is_warned_about(tmp_path):
    tiny = write_pattern(miura_pattern(2, 2, 2.0, 3.0, 60.0), tmp_path / "tiny.fold")
    (warning,) = size_warnings(read_pattern(tiny))
    assert "under 10 mm across" in warning and "--width" in warning
    assert size_warnings(read_pattern(tiny, scale=10.0)) == []


def test_a_job_failing_on_a_tiny_pattern_says_its_size(tmp_path, capsys):
    # the FOLD project's diagonal-cp.fold is 1 x 1 with no frame_unit: read as 1 mm, its
    # panels are too small to print, and the error says why and how to size it
    out = tmp_path / "fab"
    assert main(["fabricate", str(DATA / "fold" / "diagonal-cp.fold"), "-o", str(out)]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "too small" in line and "under 10 mm across" in line and "--width" in line
    assert not out.exists()
    assert (
        main(
            ["fabricate", str(DATA / "fold" / "diagonal-cp.fold"), "--width", "100", "-o", str(out)]
        )
        == 0
    )
    assert (out / "print.3mf").is_file()


def test_oripa_files_are_6_inches_of_no_unit(tmp_path):
    path = oripa_file(tmp_path / "oripa.dxf")
    cp = read_pattern(path)
    assert width_height(cp) == pytest.approx((6.0, 6.0))  # no unit declared: taken as mm
    (warning,) = size_warnings(cp)
    assert "ORIPA" in warning and "--width" in warning and "oripa.dxf" in warning
    sized = read_pattern(path, width=150.0)
    assert width_height(sized) == pytest.approx((150.0, 150.0))
    assert size_warnings(sized) == []
    assert sorted(sized.assignments.tolist()) == ["B"] * 4 + ["V"]  # the outline: border
    inches = read_pattern(path, unit="in")
    assert width_height(inches) == pytest.approx((6 * 25.4, 6 * 25.4))


def test_fold_and_svg_units_can_be_overridden(tmp_path):
    cp = miura_pattern(2, 2, 20.0, 30.0, 60.0)
    data = json.loads(write_pattern(cp, tmp_path / "m.fold").read_text())
    data["frame_unit"] = "m"
    (tmp_path / "m.fold").write_text(json.dumps(data))
    assert width_height(read_fold(tmp_path / "m.fold")) == pytest.approx(
        tuple(1000 * v for v in width_height(cp))
    )
    assert read_pattern(tmp_path / "m.fold", unit="mm").same_graph(cp, tolerance=1e-9)
    # Origami Simulator's own sample: width/height in px against its viewBox (96 px per in)
    sample = DATA / "origami-simulator" / "mapfold.svg"
    declared = read_pattern(sample)
    as_mm = read_pattern(sample, unit="mm")  # one user unit taken as one millimetre
    assert width_height(as_mm) == pytest.approx(
        tuple(v * 96 / 25.4 for v in width_height(declared))
    )
    assert read_pattern(sample, unit="px").same_graph(declared, tolerance=1e-6)


def test_design_files_take_the_size_keys_and_only_imports_can_be_sized(tmp_path):
    ezdxf_default_file(tmp_path / "m.dxf")
    toml = tmp_path / "d.toml"
    toml.write_text('[pattern]\nkind = "file"\npath = "m.dxf"\nunit = "mm"\n')
    mm = miura_pattern(4, 6, 20.0, 30.0, 60.0)
    assert load_design(toml).pattern.same_graph(mm, tolerance=1e-9)
    assert width_height(load_design(toml, width=60.0).pattern)[0] == pytest.approx(60.0)
    toml.write_text('[pattern]\nkind = "file"\npath = "m.dxf"\nwidth = 0\n')
    with pytest.raises(DesignError, match="width"):
        load_design(toml)
    with pytest.raises(DesignError, match="the scale option sizes only imported patterns"):
        load_pattern_source(EXAMPLES / "miura_6x4.toml", scale=2.0)


# ------------------------------------------------------------------------------- CLI
def test_convert_warns_and_the_unit_option_fixes_it(tmp_path, capsys):
    path = ezdxf_default_file(tmp_path / "m.dxf")
    out = tmp_path / "out.fold"
    assert main(["convert", str(path), str(out)]) == 0
    printed = capsys.readouterr()
    assert "warning" not in printed.out  # the summary alone on stdout, the warning on stderr
    printed = printed.err
    assert "warning:" in printed and "over 5 m" in printed and "--unit" in printed
    assert max(width_height(read_fold(out))) > 5000
    assert main(["convert", str(path), str(out), "--unit", "mm"]) == 0
    assert "warning" not in str(capsys.readouterr())
    w, h = width_height(read_fold(out))
    assert main(["convert", str(path), str(out), "--width", "240"]) == 0
    assert width_height(read_fold(out)) == pytest.approx((240.0, 240.0 * h / w))
    assert main(["convert", str(path), str(out), "--unit", "furlong"]) == 2
    assert "furlong" in capsys.readouterr().err


def test_fold_reads_the_size_option(tmp_path, capsys):
    path = ezdxf_default_file(tmp_path / "m.dxf")
    out = tmp_path / "f.fold"
    args = ["fold", str(path), "--ratio", "0.3", "--frames", "2", "-o", str(out)]
    assert main([*args, "--unit", "cm"]) == 0
    assert "warning" not in str(capsys.readouterr())
    cp = read_fold(out)
    assert width_height(cp) == pytest.approx(
        tuple(10 * v for v in width_height(miura_pattern(4, 6, 20.0, 30.0, 60.0)))
    )
    folded = read_fold_frames(out)[-1]
    assert np.ptp(folded[:, 0]) > 600  # folded at 10x the size, not 1000x or 1x
    assert main(args) == 0  # declared metres: folds, and says so
    assert "over 5 m" in capsys.readouterr().err  # a warning: on stderr


@pytest.mark.parametrize("command", ["fabricate", "route", "simulate", "plan-route"])
def test_every_pattern_reading_command_takes_the_size_options(tmp_path, capsys, command):
    shutil.copy(EXAMPLES / "miura_route.toml", tmp_path / "route.toml")
    route = [str(tmp_path / "route.toml")] if command in ("route", "simulate") else []
    out = tmp_path / "out" / "route.toml" if command == "plan-route" else tmp_path / "out"
    design = str(EXAMPLES / "miura_6x4.toml")
    code = main([command, design, *route, "--scale", "2", "-o", str(out)])
    assert code == 2
    err = capsys.readouterr().err
    assert "the scale option sizes only imported patterns" in err and "'miura'" in err
    assert not (tmp_path / "out").exists()


def test_fabricate_builds_the_sized_import(tmp_path, capsys):
    small = miura_pattern(2, 2, 20.0, 25.0, 65.0)
    write_pattern(small, tmp_path / "small.dxf")
    doc = ezdxf.readfile(tmp_path / "small.dxf")
    doc.header["$INSUNITS"] = 6  # the numbers are mm, the header says metres
    doc.saveas(tmp_path / "small_m.dxf")
    out = tmp_path / "fab"
    assert main(["fabricate", str(tmp_path / "small_m.dxf"), "--unit", "mm", "-o", str(out)]) == 0
    assert "over 5 m" not in capsys.readouterr().out
    built = read_fold(out / "pattern_with_holes.fold")
    assert width_height(built) == pytest.approx(width_height(small))
