"""The strings of an MJCF model: tendons through the hole sites, TSA actuators on them.

See :mod:`origami_cad.simulation.mjcf` for the construction; units mm in, SI out.
"""

from __future__ import annotations

import numpy as np

from origami_cad.simulation.model import SimulationParams
from origami_cad.strings.route import RouteSpec

__all__ = ["MJ", "TSA_CODES", "string_sites", "tendon_specs", "tendon_xml"]

MJ = 1e-3  # m per mm
TSA_CODES = {"ring": 0.0, "onboard": 1.0}


def string_sites(spec: RouteSpec, string, s_name: str) -> list[tuple[int, str, np.ndarray]]:
    """(face or -1 for the world, site name, position mm) of a string, in route order."""
    half = spec.thickness / 2.0
    ax, ay, az = string.anchor
    if string.anchor_face >= 0:  # onboard: height above the panel's top face
        sites = [(string.anchor_face, f"{s_name}_guide", np.array([ax, ay, az + half]))]
    else:
        sites = [(-1, f"{s_name}_guide", np.array([ax, ay, az]))]
    sides = list(string.sides)
    leave = [*sides[1:], sides[-1]]
    for k, (face, (x, y)) in enumerate(zip(string.faces, string.points, strict=True)):
        sites.append((face, f"{s_name}_h{k}", np.array([x, y, sides[k] * half])))
        if leave[k] != sides[k]:
            sites.append((face, f"{s_name}_h{k}x", np.array([x, y, leave[k] * half])))
    return sites


def tendon_specs(routes, params: SimulationParams):
    """Per string: its name, sites, rest length L0 (mm) and the custom numbers of its TSA."""
    out = []
    for r, spec in enumerate(routes):
        tsa = spec.tsa
        for s, string in enumerate(spec.strings):
            name = f"tsa{r}_s{s}"
            sites = string_sites(spec, string, name)
            pts = np.array([p for _, _, p in sites])
            segs = np.linalg.norm(np.diff(pts, axis=0), axis=1)
            x0, rest = float(segs[0]), float(segs[1:].sum())
            l0 = float(tsa.consumed(0.0, x0)) + rest
            x_fixed = -1.0 if tsa.x_dis is None else tsa.x_dis
            numbers = [TSA_CODES[tsa.model], r, x0, tsa.d1, tsa.d2, tsa.string_width, x_fixed]
            numbers += [tsa.length, tsa.radius, tsa.max_helix_angle]
            kp = params.string_axial_stiffness / l0 / MJ  # N/m
            out.append((name, sites, l0, numbers, kp))
    return out


def tendon_xml(tendons) -> list[str]:
    if not tendons:
        return []
    lines = ["  <tendon>"]
    for name, sites, *_ in tendons:
        lines.append(f'    <spatial name="{name}" width="0.0005" rgba="0.9 0.1 0.1 1">')
        lines += [f'      <site site="{s}"/>' for _, s, _ in sites]
        lines.append("    </spatial>")
    lines += ["  </tendon>", "  <actuator>"]
    for name, sites, _, _, kp in tendons:
        pts = np.array([p for _, _, p in sites])
        t0 = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()) * MJ  # m
        kv = 2e-3 * kp  # s: damps the string's stretch
        lines.append(
            f'    <general name="{name}" tendon="{name}" gainprm="{-kp:.6g}" biastype="affine" '
            f'biasprm="{kp * t0:.9g} {-kp:.6g} {-kv:.6g}" ctrlrange="0 {t0:.6g}" '
            'forcerange="-200 0"/>'
        )
    lines += ["  </actuator>", "  <custom>"]
    for name, _, _, numbers, _ in tendons:
        lines.append(f'    <numeric name="{name}" data="{" ".join(f"{v:.9g}" for v in numbers)}"/>')
    return [*lines, "  </custom>"]
