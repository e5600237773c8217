"""Outputs checked against the inputs through the real CLI, before any work is done.

Each test is one root cause: a folder command's own file names are checked against the
inputs (and the files they name) before any work, not only when the files are put in place.
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

import origami_cad as oc
from origami_cad.cli import main
from origami_cad.commands import COMMANDS, execute
from origami_cad.errors import OutputError

EXAMPLES = Path(__file__).parent.parent / "examples"
BASELINE = json.loads((Path(__file__).parent / "data" / "commands_baseline.json").read_text())


def _project(tmp_path: Path, pattern_name: str) -> Path:
    """A design whose ``[pattern] path`` is ``pattern_name``, beside it."""
    design = tmp_path / "d.toml"
    design.write_text(
        '[pattern]\nkind = "miura"\nrows = 2\ncolumns = 2\npanel_length = 20.0\n'
        "panel_width = 25.0\nsector_angle = 65.0\n"
    )
    assert main(["pattern", str(design), "-o", str(tmp_path / pattern_name)]) == 0
    design.write_text(f'[pattern]\nkind = "file"\npath = "{pattern_name}"\n')
    return design


@pytest.mark.parametrize(
    ("command", "name"),
    [("fabricate", "pattern_with_holes.fold"), ("simulate", "states.fold")],
)
def test_a_folder_output_over_a_named_pattern_is_refused_before_any_work(tmp_path, command, name):
    design = _project(tmp_path, name)
    before = (tmp_path / name).read_bytes()
    route = tmp_path / "route.toml"
    shutil.copy(EXAMPLES / "miura_route.toml", route)
    inputs = (design, route) if command == "simulate" else (design,)
    # refused by the checks before any work, which name the file (the check when the
    # files are put in place, after the work, names the folder)
    with pytest.raises(OutputError, match=f"^{tmp_path / name}: the output would overwrite"):
        execute(command, *inputs, tmp_path)
    assert (tmp_path / name).read_bytes() == before


def test_a_crawl_over_the_robot_folder_that_names_gait_sequence_is_refused_up_front(tmp_path):
    robot = tmp_path / "crawler"
    shutil.copytree(EXAMPLES / "crawler", robot)
    (robot / "route_fl.toml").rename(robot / "gait_sequence.toml")
    toml = robot / "crawler.toml"
    toml.write_text(toml.read_text().replace("route_fl.toml", "gait_sequence.toml"))
    with pytest.raises(OutputError, match=r"^\S*gait_sequence.toml: .*key 'leg\[0\].route'"):
        execute("crawl", toml, robot)


@pytest.mark.parametrize(
    "case", ["fabricate", "robot", "route", "crawl", "simulate", "arm-scene", "design-arm"]
)
def test_a_folder_commands_declared_files_are_the_files_it_writes(case):
    """``FILES`` (checked before any work) names every fixed file the baseline run wrote;
    the rest are the robot's parts, named by its legs and checked when put in place."""
    written = {Path(f).name for f in BASELINE[case]["files"]}
    declared = set(COMMANDS[case].FILES)
    rest = written - declared
    assert all(n.startswith(("tsa_module_", "blocker_")) for n in rest), rest
    assert (written & declared) or not written


def _link(tmp_path: Path, kind: str) -> tuple[Path, Path]:
    """An output path through a symbolic link of ``kind``, and where the link points."""
    if kind == "dangling":
        target = tmp_path / "elsewhere" / "x.fold"
        (tmp_path / "out.fold").symlink_to(target)
        return tmp_path / "out.fold", target
    if kind == "dangling folder on the way":
        target = tmp_path / "elsewhere"
        (tmp_path / "sub").symlink_to(target)
        return tmp_path / "sub" / "out.fold", target
    if kind == "to a folder":
        target = tmp_path / "folder"
        target.mkdir()
        (tmp_path / "out.fold").symlink_to(target)
        return tmp_path / "out.fold", target
    target = tmp_path / "real.fold"
    target.write_text("old")
    (tmp_path / "out.fold").symlink_to(target)
    return tmp_path / "out.fold", target


@pytest.mark.parametrize(
    "kind", ["dangling", "dangling folder on the way", "to a folder", "to a file"]
)
def test_an_output_through_a_symbolic_link(tmp_path, capsys, kind):
    """A link to a file is written through (the file replaced, the link kept); a link to
    nothing is refused, naming it (writing would create whatever it points to, wherever
    that is), and so is a link to a folder: exit 2, one line, nothing created."""
    out, target = _link(tmp_path, kind)
    code = main(["pattern", str(EXAMPLES / "fig2_tg.toml"), "-o", str(out)])
    err = capsys.readouterr().err
    if kind == "to a file":
        assert code == 0 and out.is_symlink() and target.read_text().startswith("{")
        return
    lines = [line for line in err.splitlines() if "warning:" not in line]
    assert code == 2 and len(lines) == 1 and str(out) in lines[0], err
    why = "is a folder" if kind == "to a folder" else "is a symbolic link to .*does not exist"
    assert re.search(why, lines[0]), err
    assert not (tmp_path / "elsewhere").exists()
    if kind == "to a folder":
        assert list(target.iterdir()) == []
    with pytest.raises(OutputError, match=why):  # the library's writers too
        oc.write_fold(oc.load_design(EXAMPLES / "fig2_tg.toml").pattern, out)


def test_a_folder_output_holding_a_link_to_nothing_is_refused_before_any_work(tmp_path):
    folder = tmp_path / "fab"
    folder.mkdir()
    (folder / "panels.png").symlink_to(tmp_path / "elsewhere" / "p.png")
    with pytest.raises(OutputError, match=r"panels.png: is a symbolic link to .*elsewhere"):
        execute("fabricate", EXAMPLES / "miura_6x4.toml", folder)
    assert not (tmp_path / "elsewhere").exists() and len(list(folder.iterdir())) == 1
    (tmp_path / "gone").symlink_to(tmp_path / "elsewhere")
    with pytest.raises(OutputError, match=r"gone: is a symbolic link to .*elsewhere"):
        execute("fabricate", EXAMPLES / "miura_6x4.toml", tmp_path / "gone")
    assert not (tmp_path / "elsewhere").exists()
