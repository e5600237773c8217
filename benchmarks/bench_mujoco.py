"""The crawler in MuJoCo: simulated seconds per wall second, beside the quasi-static crawl."""

from __future__ import annotations

import time
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run() -> list[tuple[str, float, str]]:
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return [("mujoco not installed (pip install origami-cad[mujoco]): skipped", 0.0, "")]
    from origami_cad.crawler.robot import load_robot
    from origami_cad.crawler.walk import simulate_gait
    from origami_cad.simulation.mjcf import to_mjcf
    from origami_cad.simulation.mujoco_run import load_model, play_gait

    robot = load_robot(EXAMPLES / "crawler" / "crawler.toml")
    t0 = time.perf_counter()
    xml = to_mjcf(robot, timestep=1e-3)
    t1 = time.perf_counter()
    model, data = load_model(xml)
    body = model.body(robot.body).id
    play_gait(model, data, robot, 3.0)
    x0, t2 = data.xipos[body, 0], time.perf_counter()
    play_gait(model, data, robot, float(robot.gait_t[-1]), start=3.0)
    t3 = time.perf_counter()
    quasi = simulate_gait(robot, cycles=1, steps=3)
    t4 = time.perf_counter()
    cycle = float(robot.gait_t[-1])
    return [
        ("export the crawler to MJCF, s", t1 - t0, ""),
        ("MuJoCo: simulated s per wall s (1 ms steps)", cycle / (t3 - t2), "> 1 (real time)"),
        ("MuJoCo: one 32 s gait cycle, wall s", t3 - t2, ""),
        ("MuJoCo: forward per cycle, mm", (data.xipos[body, 0] - x0) * 1e3, ""),
        ("quasi-static crawl: one cycle (3 steps), wall s", t4 - t3, ""),
        ("quasi-static crawl: forward per cycle, mm", quasi.displacement_per_cycle()[0], ""),
    ]
