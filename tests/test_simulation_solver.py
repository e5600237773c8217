"""Simulation solver: the compiled assembly against the element-by-element one, the
factorisation in its fixed ordering, and the preconditioned Newton steps against plain ones."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

from origami_cad.pattern.design import miura_design
from origami_cad.simulation import SimulationParams, build_structure, simulate, solver
from origami_cad.simulation.cables import SimString, StringSet, string_derivatives, string_length
from origami_cad.simulation.mechanics import (
    bar_hessians,
    bar_lengths,
    fold_angles,
    hinge_gradients,
    hinge_hessians,
)
from origami_cad.simulation.solver import Ground, HessianAssembly, total_energy
from origami_cad.strings import TOP, TSAParams
from origami_cad.strings.route import RouteSpec, StringRoute

ONBOARD = TSAParams(model="onboard", length=120.0, radius=0.6, max_helix_angle=75.0)


def _miura_structure(cells: int = 2):
    cp = miura_design(2 * cells, 2 * cells, 15.0, 15.0, 60.0).pattern
    st = build_structure(cp, SimulationParams(), cp.face_labels[0], None)
    return cp, st


def _reference(x, st, strings, ground):
    """The energy's gradient and the free-free Hessian assembled densely, element by element,
    from the NumPy element functions (the assembly before the compiled kernels)."""
    n = len(x)
    grad = np.zeros((n, 3))
    hess = np.zeros((3 * n, 3 * n))
    length, unit = bar_lengths(x, st.bars)
    force = st.bar_k * (length - st.bar_rest)
    np.add.at(grad, st.bars[:, 1], force[:, None] * unit)
    np.add.at(grad, st.bars[:, 0], -force[:, None] * unit)
    for bar, block in zip(st.bars, bar_hessians(x, st.bars, st.bar_k, st.bar_rest), strict=True):
        dofs = (3 * bar[:, None] + np.arange(3)).ravel()
        hess[np.ix_(dofs, dofs)] += block
    rho = fold_angles(x, st.hinges)
    dr = hinge_gradients(x, st.hinges)
    over = np.abs(rho) - (st.hinge_limit - st.limit_margin)
    active = over > 0
    moment = st.hinge_k * (rho - st.hinge_rest) + np.where(
        active, st.limit_k * over, 0.0
    ) * np.sign(rho)
    k_rot = st.hinge_k + np.where(active, st.limit_k, 0.0)
    np.add.at(grad, st.hinges.ravel(), (moment[:, None, None] * dr).reshape(-1, 3))
    d2 = hinge_hessians(x, st.hinges)
    for h, hinge in enumerate(st.hinges):
        dofs = (3 * hinge[:, None] + np.arange(3)).ravel()
        g = dr[h].ravel()
        hess[np.ix_(dofs, dofs)] += k_rot[h] * np.outer(g, g) + moment[h] * d2[h]
    grad[:, 2] += st.weight
    g_ground, h_nodes = ground.derivatives(x)
    grad += g_ground
    for node in range(n):
        hess[3 * node : 3 * node + 3, 3 * node : 3 * node + 3] += h_nodes[node]
    for s in strings.strings:
        tension = s.stiffness * (string_length(x, s, strings)[0] - s.free_length)
        assert tension > 0  # the test wants every string term
        nodes, g, h = string_derivatives(x, s, strings)
        grad[nodes] += tension * g
        dofs = (3 * nodes[:, None] + np.arange(3)).ravel()
        gf = g.ravel()
        hess[np.ix_(dofs, dofs)] += s.stiffness * np.outer(gf, gf) + tension * h
    free = np.repeat(~st.fixed, 3)
    return grad, hess[np.ix_(free, free)]


def test_compiled_assembly_equals_the_element_assembly():
    _cp, st = _miura_structure()
    rng = np.random.default_rng(7)
    # a folded, stretched, twisted state: every bar and hinge term is non-zero
    x = st.x0 + rng.normal(size=st.x0.shape) * np.array([0.3, 0.3, 3.0])
    st.hinge_rest = rng.uniform(-0.2, 0.2, len(st.hinges))
    rho = fold_angles(x, st.hinges)
    st.hinge_limit = np.where(rng.random(len(st.hinges)) < 0.3, 0.5 * np.abs(rho), np.inf)
    assert np.any(np.abs(rho) > st.hinge_limit)  # some fold limits are active
    ground = Ground(float(np.median(x[:, 2])), 100.0, friction=0.4)
    ground.start(st.x0 + 0.01 * rng.normal(size=st.x0.shape))
    tri = st.triangles[rng.choice(len(st.triangles), 3, replace=False)]
    s = SimString(
        np.array([10.0, 5.0, 40.0]),
        tri,
        rng.uniform(0.1, 0.4, (3, 2)),
        np.array([1.0, -1.0, 1.0]),
        np.array([1.0, -1.0, -1.0]),
        2.2,
    )
    strings = StringSet([s], 1.1, ONBOARD, theta=4.0)
    s.free_length = 0.9 * string_length(x, s, strings)[0]
    s.stiffness = 1500.0 / s.free_length

    whole = HessianAssembly(st, strings, split_strings=False)
    _, data, low, _ = whole.assemble(x, st, strings, ground)
    assert low.u.shape == (whole.size, 0)  # k g g^T in the sparse matrix
    _, ref_hess = _reference(x, st, strings, ground)
    np.testing.assert_allclose(
        whole.matrix(data).toarray(), ref_hess, rtol=0, atol=1e-12 * np.abs(ref_hess).max()
    )
    asm = HessianAssembly(st, strings, split_strings=True)
    grad, data, low, tensions = asm.assemble(x, st, strings, ground)
    ref_grad, ref_hess = _reference(x, st, strings, ground)
    assert tensions[0] > 0
    np.testing.assert_allclose(grad, ref_grad, rtol=0, atol=1e-12 * np.abs(ref_grad).max())
    a = asm.operator(data, low).toarray()
    np.testing.assert_allclose(a, ref_hess, rtol=0, atol=1e-12 * np.abs(ref_hess).max())
    # the string's axial stiffness k g g^T is the low rank, outside the sparse part
    assert low.u.shape == (asm.size, 1)
    np.testing.assert_allclose(low.dense(), s.stiffness * np.outer(low.u, low.u), rtol=1e-12)
    # the sparse pattern holds every non-zero of the reference but the low rank's
    pattern = asm.matrix(np.ones(asm.nnz + 1)).toarray() != 0
    sparse_part = asm.matrix(data).toarray()
    assert np.all(pattern[sparse_part != 0])
    np.testing.assert_allclose(
        sparse_part + low.dense(), ref_hess, atol=1e-12 * np.abs(ref_hess).max()
    )
    # the energy kernel against the NumPy terms
    length, _ = bar_lengths(x, st.bars)
    over = np.clip(np.abs(rho) - st.hinge_limit, 0.0, None)
    energy = (
        0.5 * np.sum(st.bar_k * (length - st.bar_rest) ** 2)
        + 0.5 * np.sum(st.hinge_k * (rho - st.hinge_rest) ** 2)
        + 0.5 * st.limit_k * np.sum(over**2)
        + np.dot(st.weight, x[:, 2])
        + ground.energy(x)
        + 0.5 * s.stiffness * (string_length(x, s, strings)[0] - s.free_length) ** 2
    )
    assert total_energy(x, st, strings, ground) == pytest.approx(energy, rel=1e-12)
    # a shift adds to the diagonal only
    shifted = asm.operator(data, low, 2.5).toarray()
    np.testing.assert_allclose(shifted - a, 2.5 * np.eye(asm.size), atol=1e-9)
    # the gradient alone (the solver's convergence check) is the same gradient, bit for bit
    alone, none, no_low, alone_tensions = asm.assemble(x, st, strings, ground, hessian=False)
    assert none is None and no_low is None and alone_tensions == tensions
    assert np.array_equal(alone, grad)


def test_factorisation_solves_and_tells_the_inertia():
    _, st = _miura_structure()
    asm = HessianAssembly(st, None)
    _grad, data, _, _ = asm.assemble(st.x0, st, None, None)
    a = asm.matrix(data, 1e-3)  # the flat sheet's free-free Hessian (+ a small shift): SPD
    factor = asm.factorise(data, 1e-3)
    assert factor is not None
    rhs = np.random.default_rng(1).normal(size=asm.size)
    x = factor.solve(rhs)
    np.testing.assert_allclose(a @ x, rhs, atol=1e-8 * np.abs(rhs).max())
    np.testing.assert_allclose(x, np.linalg.solve(a.toarray(), rhs), rtol=1e-6, atol=1e-9)
    # not positive definite: refused
    assert asm.factorise(data, -1.0) is None
    # the ordering is a permutation, computed once
    order = asm.ordering
    assert sorted(order) == list(range(asm.size))
    assert asm.ordering is order
    assert isinstance(a, sp.csc_matrix)


def _fold(cp, steps: int):
    row = [label for label in cp.face_labels if label.startswith("c0r0s")]
    faces = tuple(cp.face_index(label) for label in row)
    points = []
    for f in faces:
        centre = cp.vertices[cp.faces[f]].mean(axis=0)
        points.append((float(centre[0]), float(centre[1])))
    hx, hy = points[0]
    string = StringRoute((hx, hy, 8.0), faces, tuple(points), (TOP,) * len(faces), tuple(row))
    route = RouteSpec(ONBOARD, (string,), 2.2, math.radians(60), 8.0, fixed_panel=row[0])
    return simulate(cp, route, steps=steps)


def test_preconditioned_steps_reach_the_same_equilibria_as_factorised_ones(monkeypatch):
    cp = miura_design(4, 4, 15.0, 15.0, 60.0).pattern
    fast = _fold(cp, 12)
    # every Newton step from a fresh factorisation
    monkeypatch.setattr(HessianAssembly, "reuse_factorisations", False)
    plain = _fold(cp, 12)
    assert len(fast.states) == len(plain.states) > 5
    turned = np.abs(fast.fold_angles[-1]).max()
    assert turned > 10.0  # the string really folded the sheet
    # the settled sheet before the strings pull (states 0 and 1) is an equilibrium to
    # 1e-7 N along its softest folding mode: a few 1e-6 mm; once pulled, 1e-9 mm
    np.testing.assert_allclose(fast.states[:2], plain.states[:2], atol=1e-5)
    np.testing.assert_allclose(fast.states[2:], plain.states[2:], atol=1e-8)
    np.testing.assert_allclose(fast.tensions, plain.tensions, rtol=1e-6, atol=1e-6)
    assert fast.converged.all() and plain.converged.all()


def test_the_preconditioner_is_kept_across_solves_unless_switched_off(monkeypatch):
    _, st = _miura_structure()
    rng = np.random.default_rng(3)
    st.hinge_rest = np.where(st.folds, rng.choice([-1.0, 1.0], len(st.hinges)) * 0.05, 0.0)
    start = st.x0 + np.r_[0.0, 0.0, 1.0] * rng.normal(size=(len(st.x0), 1)) * 0.01
    runs = []
    for reuse in (True, False):
        monkeypatch.setattr(HessianAssembly, "reuse_factorisations", reuse)
        asm = HessianAssembly(st)
        x1, first = solver.solve_equilibrium(start, st, assembly=asm)
        st.hinge_rest = st.hinge_rest * 1.1  # the next step: a little further
        x2, second = solver.solve_equilibrium(x1, st, assembly=asm)
        st.hinge_rest = st.hinge_rest / 1.1
        assert first.converged and second.converged
        runs.append((x2, second))
    (x_fast, fast), (x_plain, plain) = runs
    assert fast.cg_iterations > 0 and fast.factorisations < fast.iterations
    assert plain.cg_iterations == 0 and plain.factorisations >= plain.iterations
    # both are equilibria to 1e-7 N of residual force: about 1e-6 mm along the soft folding
    np.testing.assert_allclose(x_fast, x_plain, atol=1e-5)
    assert np.abs(x_fast - start).max() > 1e-2  # the hinges really folded the sheet


def test_a_whole_first_step_settles_the_flat_sheet_to_the_same_state_in_fewer_iterations():
    _, st = _miura_structure(3)
    signs = np.where(np.arange(len(st.hinges)) % 2 == 0, 1.0, -1.0)
    st.hinge_rest = np.where(st.folds, signs * math.radians(3.0), 0.0)
    flat = st.x0.copy()
    x_cut, cut = solver.solve_equilibrium(flat, st, assembly=HessianAssembly(st))
    x_whole, whole = solver.solve_equilibrium(
        flat, st, assembly=HessianAssembly(st), whole_step=True
    )
    assert cut.converged and whole.converged
    assert whole.iterations < cut.iterations
    assert np.abs(x_whole - flat).max() > 0.1  # the creases really folded
    np.testing.assert_allclose(x_whole, x_cut, atol=1e-5)
    # the step alone folds the sheet already
    stepped = solver.whole_newton_step(flat, st, HessianAssembly(st))
    assert np.abs(stepped - flat).max() > 0.1
    np.testing.assert_array_equal(flat, st.x0)  # the start is not changed in place
