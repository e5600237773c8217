"""Values and outputs the CLI refuses before it writes anything (bad values,
unwritable outputs)."""

from __future__ import annotations

import pytest

from origami_cad.cli import main


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["emulate", "--ids", "1,1", "--seconds", "0.1"], "distinct"),
        (["emulate", "--ids", "1,x"], "comma-separated IDs"),
        (["emulate", "--ids", "300"], "0..252"),
        (["tg", "{fig2}", "-o", "{tmp}/x.txt"], "written as .png"),
        (["pattern", "{fig2}", "-o", "{tmp}/a.fold", "-o", "{tmp}/b.xyz"], "b.xyz"),
        (["pattern", "{fig2}", "-o", "{tmp}/a.fold", "-o", "{tmp}/a.fold"], "given twice"),
        (["fold", "{fig2}", "--frames", "1000000000", "-o", "{tmp}/f.fold"], "1..10000"),
        (["fold", "{fig2}", "--ratio", "nan", "-o", "{tmp}/f.fold"], "finite number"),
        (["check", "{fig2}", "--angle-tolerance", "inf"], "finite number"),
        (
            ["design-arm", "{task}", "-o", "{tmp}/arm", "--seed", "-3"],
            "--seed: expected an integer in 0..4294967295, got -3",
        ),
        (
            ["design-arm", "{task}", "-o", "{tmp}/arm", "--runs", "0"],
            "--runs: expected an integer in 1..10000, got 0",
        ),
        (["drive", "{seq}", "--dry-run", "--speed", "0", "--log", "{tmp}/l.csv"], "speed"),
        (["simulate", "{miura}", "{route}", "-o", "{tmp}/s", "--gravity", "nan"], "finite"),
        (["simulate", "{miura}", "{route}", "-o", "{tmp}/s", "--blocker", "9999:60"], "9999"),
        (["simulate", "{miura}", "{route}", "-o", "{tmp}/s", "--blocker", "x:60"], "EDGE:DEG"),
        (["simulate", "{miura}", "{route}", "-o", "{tmp}/s", "--steps", "0"], "steps"),
        (["fabricate", "{miura}", "-o", "{tmp}/f", "--bias", "2", "--p-max", "0.5"], "only one"),
        # the library's checks of FabricationParams, said in the option's words (issue 43)
        (
            ["fabricate", "{miura}", "-o", "{tmp}/f", "--thickness", "0.001"],
            "error: --thickness: expected a finite number in [0.01, 10000], got 0.001",
        ),
        (
            ["fabricate", "{miura}", "-o", "{tmp}/f", "--thickness", "3"],
            "error: --height: 2.2 mm must exceed the crease --thickness 3 mm",
        ),
        (  # the bias it gives is named by the option that gave it
            ["fabricate", "{miura}", "-o", "{tmp}/f", "--theta-max", "0.001"],
            "error: --theta-max: 0.001 deg needs an inner bias of 7.85e-06 mm (eq. 6); it must "
            "lie in [1.273, 179.99] deg",
        ),
    ],
)
def test_bad_values_exit_2_and_write_nothing(tmp_path, capsys, examples, argv, message):
    names = {
        "fig2": examples / "fig2_tg.toml",
        "miura": examples / "miura_6x4.toml",
        "route": examples / "miura_route.toml",
        "task": examples / "arm_task.toml",
        "seq": examples / "crawler_gait.toml",
        "tmp": tmp_path,
    }
    code = main([a.format(**names) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert message in err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []
