"""The crawler in MuJoCo: simulated seconds per wall second, beside the quasi-static crawl."""

from __future__ import annotations

from pathlib import Path

from clock import Clock, cpu_row

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
    clock = Clock()
    xml = to_mjcf(robot, timestep=1e-3)
    export = clock.lap()
    model, data = load_model(xml)
    body = model.body(robot.body).id
    play_gait(model, data, robot, 3.0)
    x0 = data.xipos[body, 0]
    clock.lap()
    play_gait(model, data, robot, float(robot.gait_t[-1]), start=3.0)
    cycle_wall, cycle_cpu = clock.lap()
    quasi = simulate_gait(robot, cycles=1, steps=3)
    crawl = clock.lap()
    cycle = float(robot.gait_t[-1])
    return [
        ("export the crawler to MJCF, wall s", export[0], ""),
        cpu_row(export[1]),
        ("MuJoCo: simulated s per wall s (1 ms steps)", cycle / cycle_wall, "> 1 (real time)"),
        ("  simulated s per CPU s of this process", cycle / cycle_cpu, "> 1"),
        ("MuJoCo: one 32 s gait cycle, wall s", cycle_wall, ""),
        cpu_row(cycle_cpu),
        ("MuJoCo: forward per cycle, mm", (data.xipos[body, 0] - x0) * 1e3, ""),
        ("quasi-static crawl: one cycle (3 steps), wall s", crawl[0], ""),
        cpu_row(crawl[1]),
        ("quasi-static crawl: forward per cycle, mm", quasi.displacement_per_cycle()[0], ""),
    ]
