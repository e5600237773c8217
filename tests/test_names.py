"""Names from input files never become paths or markup.

Each escaper of :mod:`origami_cad._names` is fed arbitrary unicode (quotes, control
characters, ``/``, ``..``, NUL, bidirectional controls, lone surrogates) and its output
read back by the parser of its kind; then hostile names go through the command line:
leg names of a robot file, a FOLD ``file_title`` and a design file's name in
``print.3mf``, names in the HTML report.
"""

from __future__ import annotations

import dataclasses
import html.parser
import json
import re
import tomllib
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import lib3mf
import pytest
from conftest import gait_file_text
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from origami_cad._names import (
    html_text,
    one_line,
    path_component,
    plot_text,
    slicer_value,
    toml_key,
    toml_string,
    xml_text,
)
from origami_cad.cli import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
HOSTILE = ["../../x", "a/b", "..", ".", "front\nleft", '"\n[evil]', "x\x00y", "\u202eevil", ""]
# the characters that break outputs, mixed into arbitrary text
NASTY = st.sampled_from(
    list("/\\.\"'<>&\n\r\t\x00\x1b\x7f\u0085\u2028\u2029\u202e\u200b\ufeff\ud800\udfff=[]#;")
)
TEXT = st.lists(st.one_of(st.characters(), NASTY), max_size=40).map("".join) | st.sampled_from(
    HOSTILE
)
SETTINGS = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _no_surrogates(text: str, replacement: str = "\ufffd") -> str:
    return re.sub("[\ud800-\udfff]", replacement, text)


@SETTINGS
@given(TEXT)
def test_a_path_component_is_one_plain_file_in_its_folder(tmp_path_factory, name):
    try:
        got = path_component(name)
    except ValueError as exc:
        assert "cannot be a file name" in str(exc) and "\n" not in str(exc)
        return
    assert got == name
    folder = tmp_path_factory.mktemp("component")
    target = folder / f"{got}.stl"
    assert target.parent == folder and target.resolve().parent == folder.resolve()
    target.write_bytes(b"x")  # the file system takes it
    assert [p.name for p in folder.iterdir()] == [f"{got}.stl"]
    assert not got.startswith(".") and got not in (".", "..")


@pytest.mark.parametrize("name", [*HOSTILE, "CON", "nul.txt", " a", "a.", "x" * 101, "é" * 101])
def test_hostile_names_are_refused_as_file_names(name):
    with pytest.raises(ValueError, match="cannot be a file name"):
        path_component(name)


@SETTINGS
@given(TEXT)
def test_a_toml_string_reads_back_as_the_text_and_only_the_text(text):
    quoted = toml_string(text)
    assert "\n" not in quoted and "\r" not in quoted
    doc = tomllib.loads(f"name = {quoted}\n[next]\nk = 1\n")
    assert doc == {"name": _no_surrogates(text), "next": {"k": 1}}
    key = toml_key(text) if text else '""'
    assert tomllib.loads(f"{key} = 1\n") == {_no_surrogates(text): 1}


@SETTINGS
@given(TEXT)
def test_one_line_cannot_start_a_new_line_or_a_toml_table(text):
    line = one_line(text)
    assert len(line.splitlines()) <= 1 and line.isprintable()
    assert tomllib.loads(f"# {line}\nk = 1\n") == {"k": 1}
    if text.isprintable():
        assert line == text


@SETTINGS
@given(TEXT)
def test_xml_text_reads_back_in_content_and_in_either_quote(text):
    safe = xml_text(text)
    root = ET.fromstring(f"<a one='{safe}' two=\"{safe}\">{safe}</a>")
    expected = re.sub("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]", "\ufffd", text)
    expected = expected.replace("\r\n", "\n").replace("\r", "\n")  # XML's line ends
    attribute = re.sub("[\t\n]", " ", expected)  # and its attribute-value normalisation
    assert root.attrib == {"one": attribute, "two": attribute}
    assert (root.text or "") == expected
    assert len(root) == 0


class _Tags(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.tags, self.text = [], ""

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, attrs))

    def handle_data(self, data):
        self.text += data


@SETTINGS
@given(TEXT)
def test_html_text_reads_back_in_content_and_attributes(text):
    safe = html_text(text)
    parser = _Tags()
    parser.feed(f"<p title='{safe}' data-x=\"{safe}\">{safe}</p>")
    parser.close()
    expected = re.sub("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f\ud800-\udfff]", "\ufffd", text)
    assert parser.tags == [("p", [("title", expected), ("data-x", expected)])]
    assert parser.text == expected


def _slicer_unescape(value: str) -> str:
    table = {"\\\\": "\\", "\\n": "\n", "\\r": "\r", "\\t": "\t"}
    return re.sub(r"\\[\\nrt]", lambda m: table[m.group()], value)


@SETTINGS
@given(TEXT)
def test_a_slicer_value_stays_on_its_line(text):
    value = slicer_value(text)
    config = f"; name = {value}\n; layer_height = 0.2\n"
    lines = config.splitlines()
    assert [line.split(" = ")[0] for line in lines] == ["; name", "; layer_height"]
    if all(c.isprintable() or c in "\n\r\t" for c in text):
        assert _slicer_unescape(lines[0].split(" = ", 1)[1]) == text


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(TEXT)
def test_plot_text_is_drawn_as_itself(text):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(2, 1))
    ax = fig.subplots()
    ax.set_title(plot_text(text))
    shown = plot_text(text)
    ax.plot([0, 1], label=shown or "empty")
    legend = ax.legend()
    fig.canvas.draw()  # mathtext would fail on an unbalanced or bad $...$
    assert len(legend.get_texts()) == 1  # a leading "_" does not hide the entry
    assert "\n" not in shown and shown.count("$") == shown.count(r"\$")


def test_a_title_and_labels_from_a_fold_file_are_drawn_as_text(tmp_path, capsys):
    fold = _title_pattern(tmp_path, r"$\frac$ _x $")
    data = json.loads(fold.read_text())
    data["faces_label"] = [r"$\frac$", "_a", "b$", "c\nd"]
    fold.write_text(json.dumps(data))
    assert main(["convert", str(fold), str(tmp_path / "cp.png"), "--labels"]) == 0, (
        capsys.readouterr().err
    )
    assert (tmp_path / "cp.png").stat().st_size > 1000


# ----------------------------------------------------------------- through the commands


def _robot_with_leg_name(tmp_path: Path, name: str) -> Path:
    folder = tmp_path / "crawler"
    folder.mkdir()
    for f in (EXAMPLES / "crawler").iterdir():
        (folder / f.name).write_bytes(f.read_bytes())
    robot = folder / "crawler.toml"
    text = robot.read_text(encoding="utf-8")
    robot.write_text(text.replace('name = "front left"', f"name = {toml_string(name)}", 1))
    return robot


@pytest.mark.parametrize(
    "name", ["../../x", "legs/front", "front\nleft", '"\n[evil]', "..", "", "  ", " left"]
)
@pytest.mark.parametrize("command", ["robot", "crawl"])
def test_a_leg_name_that_cannot_be_a_file_name_is_refused(tmp_path, capsys, name, command):
    robot = _robot_with_leg_name(tmp_path, name)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    out = robot.parent / "out"
    assert main([command, str(robot), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"{robot} [[leg]] #1: key 'name'" in err and "cannot be a file name" in err
    after = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert after == before  # nothing written anywhere, nothing replaced


def test_two_legs_whose_files_would_clash_are_refused(tmp_path, capsys):
    robot = _robot_with_leg_name(tmp_path, "Front_Right")  # the second leg is "front right"
    assert main(["crawl", str(robot), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "[[leg]] #2: key 'name'" in err and "same files as [[leg]] #1" in err


def test_gait_sequence_holds_any_leg_name_as_text(tmp_path):
    """The TOML writer escapes what the loader would refuse (a library caller's names)."""
    from origami_cad.crawler.robot import load_robot

    robot = load_robot(EXAMPLES / "crawler" / "crawler.toml")
    names = ['"\n[evil]', "a\\b\u202e", "x\x00y\r\n[[tsa]]", "# not a comment"]
    legs = tuple(dataclasses.replace(leg, name=n) for leg, n in zip(robot.legs, names, strict=True))
    hostile = dataclasses.replace(robot, legs=legs)
    text = gait_file_text(hostile, command="origami-cad crawl 'a\nb' -o \"\n[evil]\"")
    doc = tomllib.loads(text)
    assert set(doc) == {"sequence", "tsa", "keyframe"}
    assert [t["name"] for t in doc["tsa"]] == names
    assert len(doc["tsa"]) == 4


def _title_pattern(tmp_path: Path, title: str) -> Path:
    fold = tmp_path / "cp.fold"
    design = tmp_path / "d.toml"
    design.write_text(
        '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
        "panel_width = 25.0\nsector_angle = 65.0\n"
    )
    assert main(["pattern", str(design), "-o", str(fold)]) == 0
    data = json.loads(fold.read_text())
    data["file_title"] = title
    fold.write_text(json.dumps(data))
    return fold


@pytest.mark.parametrize(
    ("source", "title"),
    [
        ("fold", "' onload='alert(1)\" x=\"<b>&amp;\x01\x1b\n\u202e"),
        ("toml", "it's \"q\" <&> ' onload='alert(1)"),
    ],
)
def test_print_3mf_is_well_formed_whatever_the_title(tmp_path, capsys, source, title):
    if source == "fold":
        design = _title_pattern(tmp_path, title)
    else:  # the title is the design file's name
        design = tmp_path / f"{title}.toml"
        design.write_text(
            '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
            "panel_width = 25.0\nsector_angle = 65.0\n"
        )
    out = tmp_path / "fab"
    assert main(["fabricate", str(design), "-o", str(out)]) == 0, capsys.readouterr().err
    shown = re.sub("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]", "\ufffd", title)
    ns = "{http://schemas.microsoft.com/3dmanufacturing/core/2015/02}"
    with zipfile.ZipFile(out / "print.3mf") as zf:
        xml_names = [n for n in zf.namelist() if n.endswith(("model", "rels", ".xml"))]
        xml_names += ["Metadata/Slic3r_PE_model.config", "Metadata/model_settings.config"]
        xml_parts = {n: ET.fromstring(zf.read(n)) for n in xml_names}  # all well-formed
        config = zf.read("Metadata/Slic3r_PE.config").decode()
    model = xml_parts["3D/3dmodel.model"]
    (obj,) = model.iter(f"{ns}object")
    assert set(obj.attrib) == {"id", "type", "name", "pid", "pindex"}  # nothing injected
    assert obj.attrib["name"] == re.sub("[\t\n]", " ", shown)
    titles = [m.text for m in model.iter(f"{ns}metadata") if m.get("name") == "Title"]
    assert titles == [shown]
    for name in ("Metadata/Slic3r_PE_model.config", "Metadata/model_settings.config"):
        names = [m.get("value") for m in xml_parts[name].iter("metadata") if m.get("key") == "name"]
        assert names[0] == re.sub("[\t\n]", " ", shown)
        keys = [set(m.attrib) for m in xml_parts[name].iter("metadata")]
        assert all(k <= {"type", "key", "value"} for k in keys)
    lines = [line for line in config.splitlines() if line]
    assert all(re.fullmatch(r"; [a-z_]+ = \S.*", line) for line in lines[1:]), lines
    # lib3mf, strict, reads it with the same name
    model3 = lib3mf.get_wrapper().CreateModel()
    reader = model3.QueryReader("3mf")
    reader.SetStrictModeActive(True)
    reader.ReadFromFile(str(out / "print.3mf"))
    objects = model3.GetMeshObjects()
    assert objects.MoveNext() and "onload" in objects.GetCurrentMeshObject().GetName()


def test_the_report_escapes_every_name(tmp_path):
    from origami_cad.viz.report import StepReport, write_report

    evil = "</h2><script>alert(1)</script>' onload='alert(2)\" x=\"\x00\u202e"
    step = StepReport(
        evil, evil, summary=evil, numbers=[(evil, evil)], files=[evil], images=[(evil, evil)],
        error=evil,
    )  # fmt: skip
    page = write_report(tmp_path / "index.html", [step], title=evil, subtitle=evil)
    parser = _Tags()
    parser.feed(page.read_text(encoding="utf-8"))
    tags = [t for t, _ in parser.tags]
    assert "script" not in tags
    attrs = {name for _, a in parser.tags for name, _ in a}
    assert attrs <= {"lang", "charset", "id", "href", "class", "src", "alt"}, attrs


_HOSTILE = "' onload='alert(1)\" x=\"<b>&amp;\x01\x1b\x00\n\u202e]]>"


def test_mjcf_is_well_formed_whatever_the_title_and_panel_labels(tmp_path):
    import mujoco

    from origami_cad.simulation.mjcf import to_mjcf

    fold = _title_pattern(tmp_path, _HOSTILE)
    data = json.loads(fold.read_text())
    labels = [f"{_HOSTILE}{i}" for i in range(len(data["faces_vertices"]))]
    data["faces_origami_cad:labels"] = labels
    fold.write_text(json.dumps(data))
    text = to_mjcf(fold)
    root = ET.fromstring(text)  # well-formed
    assert set(root.attrib) == {"model"} and "onload" in root.attrib["model"]
    bodies = [b.get("name") for b in root.iter("body")]
    assert sorted(bodies) == sorted(
        _no_surrogates(re.sub("[\x00-\x08\x0b-\x1f]", "\ufffd", n)).replace("\n", " ")
        for n in labels
    )
    model = mujoco.MjModel.from_xml_string(text)  # meshes and bodies resolve by name
    assert model.nbody == len(labels) + 1


def test_bambu_model_settings_are_well_formed_whatever_the_names():
    from origami_cad.fabrication.exports.bambu3mf import model_settings_config

    lines = model_settings_config(5, [(1, _HOSTILE, 1), (2, "shells", 2)], _HOSTILE)
    root = ET.fromstring("\n".join(lines))
    names = [m.get("value") for m in root.iter("metadata") if m.get("key") == "name"]
    assert names[0] == names[1] and "onload" in names[0] and names[2] == "shells"
    assert all(set(m.attrib) == {"key", "value"} for m in root.iter("metadata"))
