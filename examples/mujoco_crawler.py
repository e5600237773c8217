"""The crawler of Fig. 7 in MuJoCo, in a closed loop (docs/mujoco.md).

Exports examples/crawler/crawler.toml to MJCF, then at every step reads the body's pose
(position and heading), plays the robot file's gait through the TSAs (servo turns, mapped
to each string's actuator by eq. 8's onboard counterpart) and steers: a heading error
shortens the stride of the legs on the side the body turns towards. Writes
trajectory.png (the body's path and its x over time) into the output folder.

    python examples/mujoco_crawler.py --seconds 64 -o out/mujoco_crawler

Needs ``pip install origami-cad[mujoco]``; renders nothing on screen (headless).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import mujoco
import numpy as np

from origami_cad.crawler.mujoco import robot_mjcf
from origami_cad.crawler.robot import load_robot
from origami_cad.crawler.walk import gait_turns
from origami_cad.simulation.mujoco_run import load_model, tsa_actuators, tsa_controls

ROBOT = Path(__file__).resolve().parent / "crawler" / "crawler.toml"
STEER = 2.0  # stride change per radian of heading error


def heading(data, body: int) -> float:
    """The body's yaw, radians (its x axis against the world's)."""
    xmat = data.xmat[body].reshape(3, 3)
    return math.atan2(xmat[1, 0], xmat[0, 0])


def run(seconds: float, folder: Path) -> dict:
    robot = load_robot(ROBOT)
    model, data = load_model(robot_mjcf(robot, timestep=1e-3))
    acts = tsa_actuators(model)
    body = model.body(robot.body).id
    keys, times = gait_turns(robot), robot.gait_t
    rest = keys[0]  # standing turns: steering scales the stride above them
    left = np.array([robot.pattern.face_centroids()[leg.face][1] > 0 for leg in robot.legs])
    log = []
    while data.time < seconds:
        tc = data.time % times[-1]
        turns = np.array([np.interp(tc, times, keys[:, k]) for k in range(len(robot.legs))])
        error = heading(data, body)  # want 0: straight along +x
        scale = np.where(left, 1.0 + STEER * error, 1.0 - STEER * error).clip(0.5, 1.5)
        tsa_controls(model, data, rest + scale * (turns - rest), acts)
        mujoco.mj_step(model, data)
        if not log or data.time - log[-1][0] >= 0.05:
            log.append((data.time, *(data.xipos[body] * 1e3), error))
    t, x, y, _, yaw = np.array(log).T
    folder.mkdir(parents=True, exist_ok=True)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(x, y)
    ax1.set(xlabel="x, mm", ylabel="y, mm", title="body path (MuJoCo)", aspect="equal")
    ax2.plot(t, x - x[0], label="x")
    ax2.plot(t, np.degrees(yaw), label="heading, deg")
    ax2.set(xlabel="time, s", title="closed loop: gait + heading steering")
    ax2.legend()
    fig.tight_layout()
    fig.savefig(folder / "trajectory.png", dpi=100)
    plt.close(fig)
    return {
        "forward_mm": float(x[-1] - x[0]),
        "seconds": float(t[-1]),
        "yaw_deg": float(np.degrees(yaw[-1])),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=64.0, help="simulated time, s")
    parser.add_argument("-o", "--output", default="out/mujoco_crawler", help="output folder")
    args = parser.parse_args()
    out = run(args.seconds, Path(args.output))
    speed = out["forward_mm"] / out["seconds"]
    print(
        f"{out['forward_mm']:.1f} mm forward in {out['seconds']:.1f} s ({speed:.3f} mm/s), "
        f"heading {out['yaw_deg']:.2f} deg; wrote {args.output}/trajectory.png"
    )


if __name__ == "__main__":
    main()
