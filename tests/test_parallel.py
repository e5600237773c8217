"""The local process pool: workers that run OpenCascade after the parent has.

build123d runs OCC's booleans and meshing on OCC's thread pool; a worker forked after that
pool started inherits it without its threads and waits for ever at its first parallel
operation. Each scenario runs in a fresh interpreter, killed at a timeout, so a regression
fails here instead of hanging the suite.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap

import pytest

#: a script that builds, cuts and checks a solid in this process, then in two pool workers
SCRIPT = textwrap.dedent(
    """
    from origami_cad.parallel import local_pool, start_context


    def cut_volume(offset):
        from build123d import Box, Cylinder, Pos

        solid = Box(10, 10, 10) - Pos(offset, 0, 0) * Cylinder(2, 20)
        assert solid.is_valid
        return round(solid.volume, 6)


    if __name__ == "__main__":
        here = cut_volume(0.0)
        with local_pool(2) as pool:
            there = list(pool.map(cut_volume, [0.0, 1.0, 2.0]))
        print(start_context().get_start_method(), here, *there)
    """
)


def _run(code: str, tmp_path, timeout: float = 240.0) -> str:
    """The output of ``code`` run as a script in a fresh interpreter; fails at the timeout."""
    script = tmp_path / "scenario.py"
    script.write_text(code)
    proc = subprocess.Popen(
        [sys.executable, str(script)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        pytest.fail(f"the pool's workers hung ({timeout:g} s) after OCC ran in the parent")
    assert proc.returncode == 0, err
    return out


def test_workers_run_occ_after_the_parent_has(tmp_path):
    method, here, *there = _run(SCRIPT, tmp_path).split()
    assert method != "fork"  # OCP is loaded: a forked worker would hang
    assert float(here) == pytest.approx(1000 - 3.14159265 * 4 * 10, rel=1e-6)
    assert [float(v) for v in there] == [float(here)] * 3  # the hole stays inside the box


@pytest.mark.skipif(
    "fork" not in __import__("multiprocessing").get_all_start_methods(),
    reason="no fork on this platform",
)
def test_fork_while_occ_is_not_loaded(tmp_path):
    code = (
        "import sys\n"
        "from origami_cad.parallel import occ_loaded, start_context\n"
        "import origami_cad.design.search, origami_cad.strings.plan\n"
        "print(occ_loaded(), start_context().get_start_method())\n"
        "import OCP\n"
        "print(occ_loaded(), start_context().get_start_method())\n"
    )
    assert _run(code, tmp_path).split() == ["False", "fork", "True", "forkserver"]
