"""Measured force curves read for calibration: PyGamiX's bench files and headed CSV files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from origami_cad.errors import SimulationError
from origami_cad.simulation.calibrate import nrmse, read_force_curve
from origami_cad.simulation.materials import Materials


def test_pygamix_runs_read_quoted_or_not(tmp_path: Path) -> None:
    plain = tmp_path / "run.csv"
    plain.write_text("0,0.1,0,1.1\n0.02,0.12,0.5,2.5\n0.04,0.14,1.0,5.0\n")
    quoted = tmp_path / "quoted.csv"
    quoted.write_text('"0","0.1","0","1.1"\n"0.02","0.12","0.5","2.5"\n"0.04","0.14","1.0","5.0"\n')
    for path in (plain, quoted):
        pull, force = read_force_curve(path)
        assert pull.tolist() == [0.0, 0.5, 1.0] and force.tolist() == [1.1, 2.5, 5.0]


def test_a_headed_csv_reads_its_named_columns(tmp_path: Path) -> None:
    path = tmp_path / "pull.csv"
    path.write_text("time_s,tension_N,pull_mm\n0,0,0\n0.1,2,1.5\n0.2,3,3\n")
    pull, force = read_force_curve(path)
    assert pull.tolist() == [0.0, 1.5, 3.0] and force.tolist() == [0.0, 2.0, 3.0]


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("0,0.1,0,1\n0.02,0.12,2,x\n", r"row 2, column 4"),
        ("0,0.1,0,1\n0.02,0.12\n", r"row 2: no column 3"),
        ("0,0.1,0,1\n0.02,0.12,2,1\n0.04,0.14,1.5,1\n", r"row 3: the pull decreases"),
        ("time,force_N\n0,1\n", r"pull_mm"),
        ("0,0.1,0,1\n", r"two rows"),
    ],
)
def test_bad_runs_name_the_row_and_column(tmp_path: Path, text: str, match: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(SimulationError, match=match) as err:
        read_force_curve(path)
    assert "bad.csv" in str(err.value)


def test_nrmse_is_the_rms_error_over_the_peak() -> None:
    measured = np.array([0.0, 10.0, 5.0])
    assert nrmse(measured, measured) == 0.0
    assert nrmse(measured + 1.0, measured) == pytest.approx(0.1)


def test_oc_calibrate_takes_files_and_returns_a_typed_result(tmp_path: Path) -> None:
    import origami_cad as oc
    from origami_cad.simulation.calibrate import Calibration

    mountain = Path(__file__).parent / "data" / "pygamix" / "descriptionData"
    cp = oc.read_pattern(mountain / "f-mountain-big-fix-new.json")
    run = tmp_path / "run.csv"
    run.write_text("pull_mm,tension_N\n0,0\n3,0.5\n6,0.9\n")
    fit = oc.calibrate(cp, None, [run], fit=("hole_friction",), step=3.0, max_evaluations=2)
    assert isinstance(fit, Calibration) and fit.names == ["run.csv"]
    assert fit.grid.tolist() == [0.0, 3.0, 6.0] and 0.0 <= fit.values["hole_friction"] <= 1.0
    assert fit.error <= fit.error_before
    with pytest.raises(SimulationError, match="no tendons"):
        oc.calibrate(oc.miura_design(2, 2, 20.0, 20.0, 60.0).pattern, None, [run])


EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pygamix"


def test_the_vendored_mountain_files_are_the_sources_bytes() -> None:
    sizes = {"experiment/mountain/1_2.csv": 6164, "experiment/mountain/2_2.csv": 6184,
             "experiment/mountain/3_2.csv": 6189,
             "descriptionData/f-mountain-big-fix-new.json": 39142}  # fmt: skip
    for name, size in sizes.items():
        assert (EXAMPLE / name).stat().st_size == size, name
    assert "MIT License" in (EXAMPLE / "LICENSE").read_text()


def test_the_calibrated_mountain_materials_give_the_error_the_readme_reports() -> None:
    import re

    from origami_cad.simulation.calibrate import compare_materials
    from origami_cad.simulation.materials import load_materials

    reported = float(
        re.search(r"NRMSE ([0-9.]+)", (EXAMPLE / "materials_mountain.toml").read_text())[1]
    )
    runs = sorted((EXAMPLE / "experiment" / "mountain").glob("*.csv"))
    design = EXAMPLE / "descriptionData" / "f-mountain-big-fix-new.json"
    calibrated = load_materials(EXAMPLE / "materials_mountain.toml")
    fit = compare_materials(design, runs, Materials(), calibrated, step=3.0, tendons=(2,))
    assert fit.error == pytest.approx(reported, abs=0.01)
    assert fit.error_before > 3 * fit.error and fit.names == ["1_2.csv", "2_2.csv", "3_2.csv"]
