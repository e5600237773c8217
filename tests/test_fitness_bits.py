"""A population's eq. 5 fitness has the same bits with and without numpy's AVX-512 kernels,
and the compiled trigonometry gives math's bits."""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from origami_cad import _libm

TASK = Path(__file__).resolve().parents[1] / "examples" / "arm_task.toml"
FITNESS = """
import sys
import numpy as np
from origami_cad.design import arm_fitness, decode, load_task
task, _ = load_task(sys.argv[1])
x = np.random.default_rng(5).uniform(size=(300, task.dimension))
lengths, beta = decode(task, x)
r = arm_fitness(task, lengths, beta, np.arange(300) % 2)
print(np.concatenate([r.fitness, r.tips.ravel(), r.fold_ratio_end]).tobytes().hex())
"""


def _fitness_bits(disable: str | None) -> str:
    env = {k: v for k, v in os.environ.items() if k != "NPY_DISABLE_CPU_FEATURES"}
    if disable:
        env["NPY_DISABLE_CPU_FEATURES"] = disable
    done = subprocess.run(
        [sys.executable, "-c", FITNESS, str(TASK)],
        env=env, capture_output=True, text=True, timeout=300, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return done.stdout.strip().splitlines()[-1]


def test_a_populations_fitness_has_the_same_bits_without_avx512():
    a = _fitness_bits(None)
    b = _fitness_bits("X86_V4 AVX512_ICL")
    assert len(a) > 1000 and a == b


def test_the_compiled_trigonometry_gives_maths_bits():
    rng = np.random.default_rng(2)
    x = rng.uniform(-7.0, 7.0, 20000)
    u = rng.uniform(-1.1, 1.1, 20000)
    cases = [(_libm.sin, math.sin, x), (_libm.cos, math.cos, x), (_libm.tan, math.tan, x),
             (_libm.arctan, math.atan, x)]  # fmt: skip
    for f, g, v in cases:
        assert f(v).tolist() == [g(e) for e in v.tolist()], f.__name__
    inside = u[np.abs(u) <= 1.0]
    assert _libm.arccos(inside).tolist() == [math.acos(e) for e in inside.tolist()]
    assert np.isnan(_libm.arccos(np.array([1.5, -2.0]))).all()
    assert _libm.arctan2(x, u).tolist() == [math.atan2(p, q) for p, q in zip(x, u, strict=True)]
