"""The materials file: read and written back, its crease stiffness law, and the commands
that read it (``simulate``, ``route``, ``crawl``, ``mjcf`` ``--materials``)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from origami_cad.errors import SimulationError
from origami_cad.simulation import SimulationParams
from origami_cad.simulation.materials import (
    Materials,
    dump_materials,
    load_materials,
    parse_materials,
)

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "materials.toml"
MOUNTAIN = ROOT / "tests" / "data" / "pygamix" / "descriptionData" / "f-mountain-big-fix-new.json"


def test_the_example_is_the_defaults_and_reads_back(tmp_path: Path) -> None:
    m = load_materials(EXAMPLE)
    assert m == Materials()
    # the defaults are the simulation's own, so a file changes nothing unless it says so
    defaults, with_file = (
        SimulationParams(),
        m.simulation_params(fold_limit=SimulationParams().fold_limit),
    )
    assert with_file.crease_stiffness == pytest.approx(defaults.crease_stiffness, rel=1e-12)
    assert with_file.panel_bending == pytest.approx(defaults.panel_bending, rel=1e-12)
    other = Materials(crease_thickness=0.12, hole_friction=0.15, crease_stiffness_given=0.002)
    path = tmp_path / "m.toml"
    path.write_text(dump_materials(other))
    assert load_materials(path) == other
    assert dump_materials(load_materials(path)) == path.read_text()


def test_crease_stiffness_is_cubic_in_the_thickness() -> None:
    m = Materials()
    assert m.crease_stiffness() == pytest.approx(26.0 * 0.4**3 / (12 * 7.0))
    assert m.crease_stiffness(0.8) == pytest.approx(8 * m.crease_stiffness())
    given = Materials(crease_stiffness_given=0.05, crease_thickness=0.2)
    assert given.crease_stiffness() == 0.05 and given.crease_stiffness(0.4) == pytest.approx(0.4)
    assert given.simulation_params().crease_stiffness == pytest.approx(0.05)
    assert given.dcqc_stiffness()["crease_stiffness"] == pytest.approx(0.05)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("[crease]\nmodulus = -3\n", r"modulus"),
        ("[crease]\nthickness = 'thin'\n", r"thickness"),
        ("[string]\nhole_friction = -0.1\n", r"hole_friction"),
        ("[panel]\ncolour = 'red'\n", r"colour"),
        ("[glue]\n", r"glue"),
    ],
)
def test_bad_materials_name_the_key(text: str, match: str) -> None:
    with pytest.raises(SimulationError, match=match) as err:
        parse_materials(text, "bad.toml")
    assert "bad.toml" in str(err.value) and "\n" not in str(err.value)


def _cli(*args: str):
    run = [sys.executable, "-m", "origami_cad.cli", *args]
    return subprocess.run(run, capture_output=True, text=True, check=False, cwd=ROOT)


def test_simulate_pull_reads_the_materials(tmp_path: Path) -> None:
    stiff = tmp_path / "stiff.toml"
    stiff.write_text(dump_materials(Materials(crease_modulus=260.0)))
    peaks = []
    for name, extra in (("soft", []), ("stiff", ["--materials", str(stiff)])):
        out = tmp_path / name
        args = ["simulate", str(MOUNTAIN), "--pull", "4", "--pull-step", "2", "-o", str(out)]
        done = _cli(*args, *extra)
        assert done.returncode == 0, done.stderr
        peaks.append(json.loads((out / "simulation.json").read_text())["peak_tension_N"])
    assert peaks[1] > 5 * peaks[0]  # ten times the crease modulus


def test_a_bad_materials_file_is_one_line_and_nothing_written(tmp_path: Path) -> None:
    bad = tmp_path / "bad.toml"
    bad.write_text("[crease]\nmodulus = 0\n")
    out = tmp_path / "out"
    for args in (
        ["simulate", str(MOUNTAIN), "--pull", "2", "--materials", str(bad), "-o", str(out)],
        ["mjcf", "examples/miura_6x4.toml", "examples/miura_route.toml", "--materials",
         str(bad), "-o", str(tmp_path / "m.xml")],
        ["route", "examples/miura_6x4.toml", "examples/miura_route.toml", "--materials",
         str(bad), "-o", str(out)],
        ["crawl", "examples/crawler/crawler.toml", "--materials", str(bad), "-o", str(out)],
    ):  # fmt: skip
        done = _cli(*args)
        assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1
        assert "bad.toml" in done.stderr and "modulus" in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]
