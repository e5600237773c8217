"""The legged robot in MuJoCo: its model (MJCF) and its gait played open loop.

The robot file's pattern, legs' routes, body, holes, blocker angle, point masses and
friction become an :class:`~origami_cad.simulation.mjcf.MjcfSource` (the body free on
the ground, each leg's crease limited to the blocker angle), which
:func:`~origami_cad.simulation.mjcf.to_mjcf` exports. Needs the optional ``mujoco``
package to run (``pip install origami-cad[mujoco]``). Units: mm, g, degrees and seconds
at this module's edges.
"""

from __future__ import annotations

import os

import numpy as np

from origami_cad.crawler.robot import Robot, is_robot_file, load_robot
from origami_cad.pattern.design import Design
from origami_cad.simulation.mjcf import MjcfError, MjcfSource, load_mjcf_source, to_mjcf
from origami_cad.simulation.mujoco_run import load_model, render_png, tsa_actuators, tsa_controls

__all__ = ["mjcf_source", "play_gait", "render_gait_frame", "robot_mjcf", "robot_mjcf_source"]


def robot_mjcf_source(robot: Robot | str | os.PathLike[str]) -> MjcfSource:
    """What :func:`~origami_cad.simulation.mjcf.to_mjcf` exports of a robot (file or
    :class:`~origami_cad.crawler.robot.Robot`): its legs' routes, its body free on the ground,
    each leg's crease limited to the blocker angle (degrees), its point masses (g, mm)."""
    robot = robot if isinstance(robot, Robot) else load_robot(robot)
    return MjcfSource(
        Design(robot.pattern, None, "file", robot.pattern_path),
        robot.pattern,
        tuple(leg.route for leg in robot.legs),
        body=robot.body,
        holes=robot.holes,
        crease_limits={leg.crease: robot.blocker_angle for leg in robot.legs},
        masses=tuple((m.name, m.grams, m.panel, m.at) for m in robot.masses),
        friction=robot.friction,
    )


def mjcf_source(source, routes=()) -> MjcfSource:
    """What ``origami-cad mjcf`` exports: a robot file's :func:`robot_mjcf_source`, else a
    design or pattern with its route files
    (:func:`~origami_cad.simulation.mjcf.load_mjcf_source`). A robot names its own routes:
    route files given with it are an :class:`~origami_cad.simulation.mjcf.MjcfError`."""
    if isinstance(source, Robot) or is_robot_file(source):
        if routes:
            raise MjcfError("a robot file names its own routes: give no route files with it")
        return robot_mjcf_source(source)
    return load_mjcf_source(source, routes)


def robot_mjcf(robot: Robot | str | os.PathLike[str], **options) -> str:
    """The MJCF text of a robot (file or :class:`~origami_cad.crawler.robot.Robot`);
    ``options`` are :func:`~origami_cad.simulation.mjcf.to_mjcf`'s keywords."""
    return to_mjcf(robot_mjcf_source(robot), **options)


def play_gait(model, data, robot: Robot, seconds: float, start: float = 0.0) -> None:
    """Step ``seconds`` of the robot file's gait (from gait time ``start``, s), open loop.

    Each leg's TSA follows the gait's turns (:func:`~origami_cad.crawler.walk.
    gait_turns`, the keyframes' fold ratios through the rigidly folded leg and the
    onboard TSA), interpolated linearly in time and repeated every cycle.
    """
    import mujoco

    from origami_cad.crawler.walk import gait_turns

    acts, keys, times = tsa_actuators(model), gait_turns(robot), robot.gait_t
    begin = data.time
    end = begin + seconds
    while data.time < end:
        tc = (data.time - begin + start) % float(times[-1])
        turns = [np.interp(tc, times, keys[:, k]) for k in range(len(robot.legs))]
        tsa_controls(model, data, turns, acts)
        mujoco.mj_step(model, data)


def render_gait_frame(robot, path: str | os.PathLike[str], at: float = 11.0, size=(640, 480)):
    """A PNG of a robot in MuJoCo ``at`` seconds into its gait (default: mid-stride).

    ``robot`` is a robot file or :class:`~origami_cad.crawler.robot.Robot`.
    Renders off-screen (:func:`~origami_cad.simulation.mujoco_run.render_png`);
    :class:`~origami_cad.simulation.mjcf.MjcfError` without a GL context.
    """
    robot = robot if isinstance(robot, Robot) else load_robot(robot)
    model, data = load_model(robot_mjcf(robot, timestep=1e-3))
    play_gait(model, data, robot, at)
    return render_png(model, data, path, size=size)
