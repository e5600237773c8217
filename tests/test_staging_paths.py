"""No error names a staging file.

Commands write through a staging file or folder (``.oc-*``) and put the outputs in place
once complete; a check that fails on a staged file used to name that temporary path, gone
by the time the user reads it ("failed: out/fig8/.oc-uc8l5shx.toml ..."). Here a fault is
injected into one writer or check of each command, raising the error it would raise on
the staged path; the command's one line must name the user's path instead.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from origami_cad.cli import main
from origami_cad.errors import DriveError, OutputError

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


WARNING = "origami-cad: warning: "


def _fails_naming(capsys, argv, user_path: Path) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    # the design's own warnings may come first; the failure is one line
    assert len([s for s in err.splitlines() if not s.startswith(WARNING)]) == 1, err
    assert ".oc-" not in err, err
    assert str(user_path) in err, err
    return err


def test_sequence_readback_error_names_the_users_file(tmp_path, monkeypatch, capsys):
    import origami_cad.drive.sequence as sequence

    def refuse(path):  # the reader refusing the staged file
        raise DriveError(f"{path} [[tsa]] #1: key 'mapping': fold ratios must increase")

    monkeypatch.setattr(sequence, "load_sequence", refuse)
    out = tmp_path / "fig8" / "arm_fold.toml"
    argv = [
        "sequence", str(EXAMPLES / "arm_design.toml"), str(EXAMPLES / "arm_route.toml"),
        "-o", str(out), "--keyframes", "0:0", "20:0.3", "40:0",
    ]  # fmt: skip
    err = _fails_naming(capsys, argv, out)
    assert "key 'mapping'" in err
    assert not out.exists() and not list(out.parent.glob(".oc-*"))


# (module, function, its arguments, argv, the file it writes): a writer of each folder command
FOLDER_WRITERS = [
    (
        "origami_cad.viz.gltf", "write_parts_glb", ("folder", "path"),
        ["fabricate", str(EXAMPLES / "miura_6x4.toml")], "parts.glb",
    ),
    (
        "origami_cad.viz.design_plots", "save_convergence_png", ("results", "path"),
        ["design-arm", str(EXAMPLES / "arm_task.toml"), "--runs", "2", "--max-generations", "20"],
        "convergence.png",
    ),
]  # fmt: skip


@pytest.mark.parametrize(
    ("module", "function", "params", "argv", "name"),
    FOLDER_WRITERS,
    ids=["fabricate", "design-arm"],
)
def test_an_error_in_a_staged_file_names_the_users_folder(
    tmp_path, monkeypatch, capsys, module, function, params, argv, name
):
    import importlib

    def full(*args):
        assert len(args) == len(params)
        raise OutputError(f"{args[-1]}: no space left on device")

    monkeypatch.setattr(importlib.import_module(module), function, full)
    out = tmp_path / "out"
    err = _fails_naming(capsys, [*argv, "-o", str(out)], out / name)
    assert "no space left" in err
    assert not out.exists()


@pytest.mark.parametrize("trailing", ["", "/"])
def test_atomic_directory_says_the_users_folder(tmp_path, trailing):
    from origami_cad._fileio import atomic_directory

    shown = f"{tmp_path / 'out'}{trailing}"
    with pytest.raises(OutputError) as info, atomic_directory(shown) as stage:
        raise OutputError(f"{stage / 'a.json'}: bad")
    assert str(info.value) == f"{tmp_path / 'out' / 'a.json'}: bad"
