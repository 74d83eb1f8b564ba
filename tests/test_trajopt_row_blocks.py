"""The NLP program's built-in rows in C++ (cpp/src/trajopt/body_point_rows.cpp,
complementarity_rows.cpp): values against the Python definitions (each path constraint's own
evaluate, the contact quantities of hovi.trajopt.ContactRows), Jacobians against central
differences of the values, exact Hessians against central differences of the Jacobians, on models
whose points sit away from the bodies' centres of mass; and their bad input."""
import numpy as np
import pytest

import hovi
from hovi import trajopt
from hovi.contact import Box, Contacts, Gap, Terrain
from hovi.trajopt import ComplementarityRelaxation


def swinging_model():
    """Three revolute links in space (two axes), a side link on the first, centres of mass off the joints."""
    model = hovi.examples.models.pendulum(3)
    model.add_body("side", 0, "revolute", axis=(1, 0, 0), com=(0.05, 0.1, -0.1), mass=0.5,
                   inertia=np.diag([0.01, 0.02, 0.03]))
    return model


def path_nlp(method):
    """Every kind of body-point constraint, at the points and between them, on one window and on
    points alone: three C++ blocks (one per set of configurations)."""
    model = swinging_model()
    prob = trajopt.Problem(model, N=4, T=0.8)
    prob.initial_state(np.zeros(model.n)).add_cost(trajopt.ControlEffort())
    window = (0.1, 0.7)
    for c in (trajopt.Clearance(3, [0, 0.1, 0], center=[0.2, 0, -0.5], radius=0.1, window=window, between=2),
              trajopt.BodyPoint(2, [0.1, 0, -0.5], axes="xz", lower=-1.0, window=window, between=2),
              trajopt.PoseHeld(1, np.full(model.n, 0.2), point=(0.0, 0.05, -0.2), window=window, between=2),
              trajopt.Clearance(0, [0, 0, -0.2], center=[0, 0.3, 0], radius=0.2, axes="yz", window=(0.3, 0.8))):
        prob.add_constraint(c)
    return trajopt.NLP(prob, method)


def contact_nlp(method):
    """A body free in x, y, z, pitching and rolling, its centre of mass off the joints, two contact
    points over a terrain with a box and a gap (3D friction, d = 4)."""
    model = hovi.Model()
    for name, parent, axis in (("x", None, (1, 0, 0)), ("y", "x", (0, 1, 0)), ("z", "y", (0, 0, 1))):
        model.add_body(name, parent, "prismatic", axis=axis)
    model.add_body("pitch", "z", "revolute", axis=(0, 1, 0))
    model.add_body("block", "pitch", "revolute", axis=(1, 0, 0), mass=2.0, com=(0.05, -0.02, 0.03),
                   inertia=np.diag([0.02, 0.03, 0.04]))
    model.add_actuator(3)
    terrain = Terrain(ground=-1.0, gaps=[Gap(0.4, 0.6)], boxes=[Box(-10.0, 0.3, top=0.05)])
    contacts = Contacts(model, [("block", (0.2, 0.1, -0.1)), ("block", (-0.2, -0.1, -0.1))], terrain, mu=0.7)
    prob = trajopt.Problem(contacts.with_inputs, N=3, T=0.3)
    prob.initial_state([0.0, 0.0, 0.3, 0.1, -0.1]).add_cost(trajopt.ControlEffort(weight=contacts.effort_weights()))
    return trajopt.NLP(prob.add_contacts(contacts), method, relaxation=ComplementarityRelaxation(1e-2))


METHODS = [trajopt.VI(s=1), trajopt.VI(s=2), trajopt.HermiteSimpson("implicit")]


def blocks_of(nlp):
    """(block, its Jacobian values' rows in the block's order and columns) for each C++ block of the NLP."""
    out = []
    for block, places, entries in nlp._blocks():
        local = {r: i for i, r in enumerate(places)}
        out.append((block, np.array([local[r] for r in nlp.jac_rows[entries]]), nlp.jac_cols[entries]))
    return out


def jacobian_dense(block, rows, cols, x):
    J = np.zeros((block.rows, len(x)))
    np.add.at(J, (rows, cols), block.jacobian(x))
    return J


def relative_error(a, b):
    return float(np.abs(a - b).max() / np.abs(b).max())


def check_derivatives(nlp, x):
    """Each block's Jacobian against central differences of its values and its Hessian of lam . rows
    (random lam) against central differences of J^T lam (steps 1e-6 max(1, |x_j|)); returns the
    worst relative errors."""
    worst_j = worst_h = 0.0
    rng = np.random.default_rng(3)
    for block, rows, cols in blocks_of(nlp):
        lam = rng.normal(size=block.rows)
        J = jacobian_dense(block, rows, cols, x)
        H = np.zeros((len(x), len(x)))
        np.add.at(H, block.hessian_structure, block.hessian(x, lam))
        H = H + np.tril(H, -1).T
        Jfd, Hfd = np.zeros_like(J), np.zeros_like(H)
        for j in range(len(x)):
            e = np.zeros(len(x))
            e[j] = 1e-6 * max(1.0, abs(x[j]))
            Jfd[:, j] = (block.values(x + e) - block.values(x - e)) / (2 * e[j])
            Hfd[:, j] = (jacobian_dense(block, rows, cols, x + e) - jacobian_dense(block, rows, cols, x - e)).T @ lam / (2 * e[j])
        worst_j = max(worst_j, relative_error(J, Jfd))
        worst_h = max(worst_h, relative_error(H, Hfd))
    return worst_j, worst_h


@pytest.mark.parametrize("method", METHODS, ids=repr)
def test_body_point_rows_derivatives_against_central_differences(method):
    """Measured: Jacobians 2.3e-10 to 2.5e-10, Hessians 2.5e-10 to 4.6e-10 relative to the largest entry
    (the differences' truncation and round-off)."""
    nlp = path_nlp(method)
    assert len(nlp._blocks()) == 3
    x = np.random.default_rng(1).normal(scale=0.4, size=nlp.n_variables)
    worst_j, worst_h = check_derivatives(nlp, x)
    assert worst_j <= 5e-9 and worst_h <= 5e-9


@pytest.mark.parametrize("method", METHODS, ids=repr)
def test_complementarity_rows_derivatives_against_central_differences(method):
    """Measured: Jacobians 8.2e-11, Hessians 3.1e-11 to 8.6e-11 relative to the largest entry."""
    nlp = contact_nlp(method)
    x = np.random.default_rng(2).normal(scale=0.3, size=nlp.n_variables)
    worst_j, worst_h = check_derivatives(nlp, x)
    assert worst_j <= 5e-9 and worst_h <= 5e-9


@pytest.mark.parametrize("method", METHODS, ids=repr)
def test_complementarity_rows_equal_the_contact_quantities(method):
    """The rows (C++) against hovi.trajopt.ContactRows.quantities (Python, from body_point_kinematics
    and the terrain's height): phi, psi, zeta_k, the three products, and the held inputs; some
    points above the box, some over the gap and the ground."""
    nlp = contact_nlp(method)
    cr = nlp.contact_rows
    x = np.random.default_rng(4).normal(scale=0.3, size=nlp.n_variables)
    rows0 = nlp.core.n_constraints + len(nlp._path_place)
    g = nlp.constraints(x)[rows0:rows0 + cr.count]
    k = cr.quantities(x)
    EC = cr.E * cr.C
    heights = np.unique(np.round(k["phi"] - cr.kinematics(x)[0][1:, :, 2], 12))
    assert len(heights) >= 2                                     # the points meet more than one face
    zeta = k["zeta"].transpose(2, 0, 1).reshape(cr.d, EC)
    expected = np.concatenate([k["phi"].ravel(), k["psi"].ravel(), zeta.ravel(), (k["lambda"] * k["phi"]).ravel(),
                               (k["gamma"] * k["psi"]).ravel(),
                               (k["beta"].transpose(2, 0, 1).reshape(cr.d, EC) * zeta).ravel()])
    np.testing.assert_allclose(g[:cr.n_pair_rows], expected, rtol=0, atol=1e-13)
    last, before = cr.hold_inputs()
    np.testing.assert_array_equal(g[cr.n_pair_rows:], x[last] - x[before])


def test_blocks_refuse_bad_input():
    nlp = path_nlp(trajopt.VI(s=1))
    model, nv = nlp.problem.model, nlp.n_variables
    offsets, weights = np.zeros((2, 1), np.int32), np.ones((2, 1))
    local, c, L, D, idx = np.zeros((1, 3)), np.zeros(1), np.ones((1, 3)), np.zeros((1, 3)), np.zeros((1, 1), np.int32)
    BodyPointRows = hovi._core.trajopt.BodyPointRows
    assert BodyPointRows(model, nv, offsets, weights, [1], local, c, L, D, idx).rows == 2
    with pytest.raises(ValueError, match="weights"):
        BodyPointRows(model, nv, offsets, np.ones((3, 1)), [1], local, c, L, D, idx)
    with pytest.raises(ValueError, match="outside the variables"):
        BodyPointRows(model, nv, offsets + nv, weights, [1], local, c, L, D, idx)
    with pytest.raises(ValueError, match="body index 9"):
        BodyPointRows(model, nv, offsets, weights, [9], local, c, L, D, idx)
    with pytest.raises(ValueError, match="idx"):
        BodyPointRows(model, nv, offsets, weights, [1], local, c, L, D, idx + 1)
    with pytest.raises(ValueError, match="L"):
        BodyPointRows(model, nv, offsets, weights, [1], local, c, np.ones((2, 3)), D, idx)
    with pytest.raises(ValueError, match="L contains NaN or infinity"):
        BodyPointRows(model, nv, offsets, weights, [1], local, c, np.full((1, 3), np.inf), D, idx)
    with pytest.raises(ValueError, match="x"):
        BodyPointRows(model, nv, offsets, weights, [1], local, c, L, D, idx).values(np.zeros(nv + 1))

    cn = contact_nlp(trajopt.VI(s=1))
    block = cn.contact_rows.block(cn.n_variables)
    assert block.rows == cn.contact_rows.count and block.nnz == len(cn.contact_rows.rows)
    ct, cr = cn.contact_rows.contacts, cn.contact_rows
    two = hovi._core.ContactModel([4, 4], np.zeros((2, 3)), ct.terrain.core(), ct.mu, ct.D)
    args = (ct.with_inputs, cn.n_variables, two, ct.first_input)
    ComplementarityRows = hovi._core.trajopt.ComplementarityRows
    q_off, u_off = cr.q_off.astype(np.int32), cr.u_off.astype(np.int32)
    with pytest.raises(ValueError, match="increase"):
        ComplementarityRows(*args, cr.t[::-1], q_off, u_off)
    with pytest.raises(ValueError, match="two configuration points"):
        ComplementarityRows(*args, cr.t[:1], q_off[:1], u_off[:1])
    with pytest.raises(ValueError, match="contact input lies outside"):
        ComplementarityRows(*args, cr.t, q_off, u_off + cn.n_variables)
    bad = hovi._core.ContactModel([7, 4], np.zeros((2, 3)), ct.terrain.core(), ct.mu, ct.D)
    with pytest.raises(ValueError, match="body index 7"):
        ComplementarityRows(ct.with_inputs, cn.n_variables, bad, ct.first_input, cr.t, q_off, u_off)

def test_program_refuses_rows_placed_twice():
    """Between the transcription's rows and the linear rows every place is taken once."""
    nlp = path_nlp(trajopt.VI(s=1))
    blocks = nlp._blocks()
    (first, rows, entries), (second, rows2, entries2) = blocks[:2]
    twice = [(first, rows, entries), (second, np.r_[rows[:1], rows2[1:]].astype(np.int32), entries2)] + blocks[2:]
    no_squares = (np.zeros(1, np.int32), np.zeros(0, np.int32), np.zeros(0))
    A = (nlp.A.indptr.astype(np.int32), nlp.A.indices.astype(np.int32), nlp.A.data)
    args = (nlp.core, 0.0, no_squares, np.zeros(0), np.zeros(0), A, nlp.jac_rows.astype(np.int32),
            nlp.jac_cols.astype(np.int32))
    assert hovi._core.trajopt.Program(*args, blocks).n_constraints == nlp.n_constraints
    with pytest.raises(ValueError, match="taken twice"):
        hovi._core.trajopt.Program(*args, twice)
    with pytest.raises(ValueError, match="blocks must be"):
        hovi._core.trajopt.Program(*args, [first])
    with pytest.raises(ValueError, match="must be a RowBlock"):
        hovi._core.trajopt.Program(*args, [(1, rows, entries)] + blocks[1:])
    with pytest.raises(ValueError, match="arrays of integers"):
        hovi._core.trajopt.Program(*args, [(first, "rows", entries)] + blocks[1:])
