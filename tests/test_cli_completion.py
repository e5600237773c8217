"""Shell completion in one command: ``origami-cad completion bash|zsh|fish`` prints a
script naming every command, its flags and the values of flags with choices."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from origami_cad.cli import completion_script, main
from origami_cad.commands import COMMANDS

SHOWN = [n for n, c in COMMANDS.items() if not c.HIDDEN]


@pytest.mark.parametrize("shell", ["bash", "zsh", "fish"])
def test_the_command_prints_a_script_naming_every_command(shell, capsys):
    assert main(["completion", shell]) == 0
    script = capsys.readouterr().out
    assert script == completion_script(shell)
    for name in SHOWN:
        assert f" {name}" in script, name
    assert "--hole-diameter" in script.replace("-l hole-diameter", "--hole-diameter")
    assert "prusa bambu orca" in script
    assert not [n for n, c in COMMANDS.items() if c.HIDDEN and f" {n})" in script]


def test_an_unknown_shell_is_refused(capsys):
    assert main(["completion", "tcsh"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "bash" in err and "fish" in err


def _complete(line: str) -> list[str]:
    """What bash offers for ``line`` (the cursor at its end), through the script."""
    script = completion_script("bash")
    words = line.split(" ")
    driver = (
        f"{script}\nCOMP_WORDS=({' '.join(repr(w) for w in words)})\n"
        f"COMP_CWORD={len(words) - 1}\n_origami_cad\nprintf '%s\\n' \"${{COMPREPLY[@]}}\"\n"
    )
    done = subprocess.run(["bash", "-c", driver], capture_output=True, text=True, timeout=30)
    assert done.returncode == 0, done.stderr
    return done.stdout.split()


@pytest.mark.skipif(shutil.which("bash") is None, reason="no bash")
def test_bash_completes_commands_flags_and_choices():
    assert _complete("origami-cad fab") == ["fabricate"]
    assert set(_complete("origami-cad d")) == {"design-arm", "drive", "design-gait", "demo"}
    assert _complete("origami-cad fabricate x.toml --sli") == ["--slicer"]
    assert _complete("origami-cad fabricate x.toml --slicer ") == ["prusa", "bambu", "orca"]
    assert _complete("origami-cad emulate --protocol ") == ["dynamixel", "serial"]
    assert "--ratio" in _complete("origami-cad fold x.fold --r")


@pytest.mark.parametrize("shell", ["zsh", "fish"])
def test_the_script_parses_in_its_shell(shell):
    if shutil.which(shell) is None:
        pytest.skip(f"no {shell}")
    done = subprocess.run([shell, "-n"], input=completion_script(shell), text=True,
                          capture_output=True, timeout=30)  # fmt: skip
    assert done.returncode == 0, done.stderr
