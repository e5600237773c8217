"""Running exported models in MuJoCo: TSA turns to actuator controls, fold ratios, frames.

Needs the optional ``mujoco`` package (``pip install origami-cad[mujoco]``); models come
from :func:`~origami_cad.simulation.mjcf.to_mjcf`. Units: the model's SI inside (m, s);
mm, turns and degrees at this module's edges.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from origami_cad.simulation.mjcf import MJ, MjcfError
from origami_cad.strings.tsa import TSAParams

# off-screen rendering without a display: MuJoCo picks its GL backend when it is first
# imported, so this must be set before (EGL; MUJOCO_GL=osmesa for software rendering)
os.environ.setdefault("MUJOCO_GL", "egl")

__all__ = [
    "crease_angles",
    "hold_mean_pose",
    "load_model",
    "render_png",
    "set_fold",
    "tsa_actuators",
    "tsa_controls",
    "vertex_coords",
]


def load_model(xml: str):
    """``(MjModel, MjData)`` of MJCF text; :class:`MjcfError` if MuJoCo refuses it."""
    import mujoco

    try:
        model = mujoco.MjModel.from_xml_string(xml)
    except ValueError as exc:
        raise MjcfError(f"MuJoCo refused the model: {exc}") from None
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)  # site positions for the first controls
    return model, data


@dataclass(frozen=True)
class TSAActuators:
    """The TSA actuators of a model, read from its ``custom`` numerics (arrays, mm)."""

    ids: np.ndarray  # actuator index
    route: np.ndarray  # the route (TSA) each belongs to
    guide: np.ndarray  # site of the TSA's guide
    hole: np.ndarray  # site of the first hole
    offset: np.ndarray  # consumed(0, x0) - x0, mm
    tsas: tuple[TSAParams, ...]  # one per route


def tsa_actuators(model) -> TSAActuators:
    """The model's TSA actuators: their routes, guide and first-hole sites and TSA models."""
    import mujoco

    rows, tsas = [], {}
    for a in range(model.nu):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_ACTUATOR, a)
        code, route, x0, d1, d2, ds, x_fixed, length, radius, helix = model.numeric(
            name
        ).data.tolist()
        tsa = TSAParams(
            model="ring" if code == 0 else "onboard",
            d1=d1,
            d2=d2,
            string_width=ds,
            x_dis=None if x_fixed < 0 else x_fixed,
            length=length,
            radius=radius,
            max_helix_angle=helix,
        )
        tsas[int(route)] = tsa
        guide, hole = model.site(f"{name}_guide").id, model.site(f"{name}_h0").id
        rows.append((a, int(route), guide, hole, float(tsa.consumed(0.0, x0)) - x0))
    ids, route, guide, hole, offset = (np.array(c) for c in zip(*rows, strict=True))
    return TSAActuators(ids, route, guide, hole, offset, tuple(tsas[r] for r in sorted(tsas)))


def tsa_controls(model, data, turns, actuators: TSAActuators | None = None) -> np.ndarray:
    """Each actuator's control (string taken up, m) for the TSAs' turns (one per route).

    ``u = consumed(theta, x_dis) - x_dis - (consumed(0, x0) - x0)`` with eq. 8 or the
    onboard model (:meth:`TSAParams.consumed`), ``theta = 2 pi turns``, ``x_dis`` (mm)
    the current distance from the guide to the first hole in ``data``. Writes
    ``data.ctrl`` and returns it.
    """
    acts = actuators or tsa_actuators(model)
    turns = np.atleast_1d(np.asarray(turns, dtype=float))
    x = np.linalg.norm(data.site_xpos[acts.hole] - data.site_xpos[acts.guide], axis=1) / MJ
    for r, tsa in enumerate(acts.tsas):
        mine = acts.route == r
        theta = 2.0 * math.pi * max(float(turns[r]), 0.0)
        now = np.asarray(tsa.consumed(theta, x[mine])) - x[mine]
        data.ctrl[acts.ids[mine]] = (now - acts.offset[mine]) * MJ
    return data.ctrl


def crease_angles(model, data, edges: int) -> np.ndarray:
    """Fold angle of every tree crease (``crease<e>`` joints), radians, NaN elsewhere (m,)."""
    import mujoco

    out = np.full(edges, np.nan)
    for j in range(model.njnt):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or ""
        if name.startswith("crease"):
            out[int(name[6:])] = data.qpos[model.jnt_qposadr[j]]
    return out


def render_png(model, data, path: str | os.PathLike[str], *, size=(640, 480), distance=0.7):
    """Render the current state off-screen into a PNG (EGL or OSMesa: ``MUJOCO_GL``).

    Returns the path; :class:`MjcfError` when no GL context can be made (the reason).
    """
    import imageio.v3 as iio
    import mujoco

    try:
        renderer = mujoco.Renderer(model, size[1], size[0])
    except Exception as exc:  # no display, no EGL/OSMesa: say which
        raise MjcfError(f"no off-screen GL context ({os.environ['MUJOCO_GL']}): {exc}") from None
    camera = mujoco.MjvCamera()
    camera.lookat[:] = data.xpos[1]
    camera.distance, camera.azimuth, camera.elevation = distance, 135.0, -25.0
    with renderer:
        renderer.update_scene(data, camera)
        iio.imwrite(path, renderer.render())
    return path


def vertex_coords(model, data, cp) -> np.ndarray:
    """The pattern's vertices now, ``(n, 3)`` mm: each the mean over the panels it is on."""
    out, count = np.zeros((cp.n_vertices, 3)), np.zeros(cp.n_vertices)
    for f, ring in enumerate(cp.faces):
        b = model.body(cp.face_labels[f]).id
        v = np.column_stack([cp.vertices[ring], np.zeros(len(ring))])
        out[ring] += v @ data.xmat[b].reshape(3, 3).T + data.xpos[b] / MJ
        count[ring] += 1
    return out / np.maximum(count, 1)[:, None]


def hold_mean_pose(model, data, cp) -> None:
    """Move the ``ring`` of guides so that the sheet sits in it in its mean pose.

    The sheet lies free in the ring and is pulled evenly: as in the project's string
    models (``strings.route.mean_pose``), its vertices' centroid stays where it was flat
    in the ring and it has no mean rotation. The exported model holds the root panel and
    carries the guides on a mocap body instead (the same relative placement). Call it
    between steps of a model exported with ``gravity=0`` and no held panel.
    """
    import mujoco

    from origami_cad.strings.route import rigid_fit

    flat = np.column_stack([cp.vertices, np.zeros(cp.n_vertices)])
    rot, shift = rigid_fit(flat, vertex_coords(model, data, cp))  # rot flat + shift ~ now
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rot.ravel())
    data.mocap_pos[0], data.mocap_quat[0] = shift * MJ, quat


def set_fold(model, data, table, p: float) -> None:
    """Put every crease joint at the rigid folding's angle at fold ratio ``p`` (``table``
    from :func:`~origami_cad.simulation.simulate.rigid_table`), and update positions."""
    import mujoco

    ratios, angles = table
    for j in range(model.njnt):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or ""
        if name.startswith("crease"):
            e = int(name[6:])
            data.qpos[model.jnt_qposadr[j]] = np.interp(p, ratios, angles[:, e])
    mujoco.mj_forward(model, data)


def tie_strings(model, data) -> None:
    """Make the current pose the strings' taut start: each TSA actuator's ``T0`` becomes its
    tendon's length now (after :func:`set_fold`: strings tied on the pre-folded sheet)."""
    for a in range(model.nu):
        tendon = model.actuator_trnid[a, 0]
        kp = -model.actuator_gainprm[a, 0]
        model.actuator_biasprm[a, 0] = kp * data.ten_length[tendon]
