"""The Lagrangian's Hessian by coloured differences (hovi.trajopt.hessian) against dense central
differences of the Lagrangian's gradient, and IPOPT with it against IPOPT with L-BFGS."""
import numpy as np
import pytest
import scipy.sparse as sp

from hovi import trajopt
from hovi.trajopt.complementarity import ComplementarityRelaxation
from hovi.examples.swingups import cartpole_swingup, pendulum_swingup, slider_crank_to_target
from hovi.trajopt.hessian import LagrangianHessian, distance2_colouring, star_colouring
from test_trajopt_jacobian import tumbling_block


def lagrangian_gradient(nlp, x, lam, sigma):
    """sigma grad f(x) + J(x)^T lambda (n_variables,), from the NLP's C++ program."""
    program = nlp.program()
    jt_lam = np.bincount(nlp.jac_cols, weights=program.jacobian(x) * lam[nlp.jac_rows], minlength=nlp.n_variables)
    return sigma * program.gradient(x) + jt_lam


def coloured_values(H, x, lam, sigma):
    """The Hessian's values at (H.rows, H.cols) from one forward difference of the gradient per colour
    (steps sqrt(eps) max(1, |x_j|)): a reference in numpy of what the C++ program computes."""
    h = np.sqrt(np.finfo(float).eps) * np.maximum(1.0, np.abs(x))
    g0 = lagrangian_gradient(H.nlp, x, lam, sigma)
    read_colour = H.colour[H.read_col]
    out = np.empty(len(H.rows))
    for c in range(H.n_colours):
        Hd = lagrangian_gradient(H.nlp, x + np.where(H.colour == c, h, 0.0), lam, sigma) - g0
        sel = read_colour == c
        out[sel] = Hd[H.read_row[sel]] / h[H.read_col[sel]]   # the row meets one column of colour c
    return out


def test_coloured_hessian_equals_dense_central_differences_of_the_lagrangian_gradient():
    for prob, method in ((cartpole_swingup(N=6, T=1.5), trajopt.VI(s=2)), (slider_crank_to_target(N=5), trajopt.VI(s=2)),
                         (cartpole_swingup(N=4, T=1.5), trajopt.HermiteSimpson("implicit"))):
        nlp = trajopt.NLP(prob, method)
        H = LagrangianHessian(nlp)
        rng = np.random.default_rng(5)
        x = np.clip(rng.uniform(-1, 1, nlp.n_variables), nlp.lower, nlp.upper)
        probed = LagrangianHessian(nlp, probe=np.zeros(nlp.n_variables))   # the pattern found elsewhere than x
        assert probed.n_colours < H.n_colours and len(probed.rows) < len(H.rows)
        lam, sigma = rng.normal(size=nlp.n_constraints), 0.7
        dense = np.empty((nlp.n_variables, nlp.n_variables))
        for j in range(nlp.n_variables):
            e = np.zeros(nlp.n_variables)
            e[j] = 1e-5
            dense[:, j] = (lagrangian_gradient(nlp, x + e, lam, sigma) - lagrangian_gradient(nlp, x - e, lam, sigma)) / 2e-5
        scale = np.abs(dense).max()
        lower = np.tril(dense)
        for hessian in (H, probed):
            sparse = np.zeros_like(dense)
            program = nlp.program()
            program.set_colouring(*(a.astype(np.int32) for a in (hessian.colour, hessian.rows, hessian.cols,
                                                                  hessian.read_row, hessian.read_col)), 1, True)
            sparse[hessian.rows, hessian.cols] = program.hessian(x, lam, sigma)   # the C++ coloured differences
            np.testing.assert_allclose(sparse[hessian.rows, hessian.cols], coloured_values(hessian, x, lam, sigma),
                                       rtol=1e-6, atol=1e-9 * scale)
            assert np.abs(sparse - lower).max() <= 1e-6 * scale      # values, and no entry outside the pattern
        assert np.abs(dense - dense.T).max() <= 1e-6 * scale         # (the Hessian is symmetric)


def test_gram_pattern_is_the_pattern_of_a_transpose_a_plus_identity():
    """The C++ coupling pattern (variables sharing a row of A) against scipy's A^T A + I."""
    from hovi import _core
    rng = np.random.default_rng(2)
    for rows, n, density in ((30, 50, 0.08), (5, 40, 0.3), (0, 7, 0.0), (40, 12, 0.5)):
        A = sp.random(rows, n, density=density, format="csr", random_state=rng)
        indptr, indices = _core.trajopt.gram_pattern(A.indptr.astype(np.int32), A.indices.astype(np.int32), n)
        got = sp.csr_matrix((np.ones(len(indices)), indices, indptr), (n, n)).toarray()
        want = ((abs(A).T @ abs(A)).toarray() != 0) | np.eye(n, dtype=bool)
        assert np.array_equal(got != 0, want)
        assert all(np.all(np.diff(indices[indptr[j]:indptr[j + 1]]) > 0) for j in range(n))   # sorted, no repeats


def test_hessian_threads_give_the_same_values_and_solve():
    """The colours' differences (fd) and the VI's own Hessian (directional, by stages) on two threads:
    bitwise the values of one thread, so the same solve; also with a path constraint, whose Python
    part is differenced on the calling thread."""
    with_path = pendulum_swingup(N=10)
    with_path.add_constraint(trajopt.BodyPoint(0, [0, 0, -0.5], axes="z", lower=-0.45, window=(1.5, 2.0)))
    for prob in (cartpole_swingup(N=12), with_path):
        nlp = trajopt.NLP(prob, trajopt.VI(s=3))
        H = LagrangianHessian(nlp, probe=np.zeros(nlp.n_variables))
        program = nlp.program()
        rng = np.random.default_rng(3)
        x, lam = rng.uniform(-1, 1, nlp.n_variables), rng.normal(size=nlp.n_constraints)
        for by_differences in (True, False):
            values = []
            for threads in (1, 2, None):
                program.set_colouring(H.colour.astype(np.int32), H.rows.astype(np.int32), H.cols.astype(np.int32),
                                      H.read_row.astype(np.int32), H.read_col.astype(np.int32), threads,
                                      by_differences)
                values.append(program.hessian(x, lam, 0.3))
            assert program.hessian_threads >= 1
            assert np.array_equal(values[0], values[1]) and np.array_equal(values[0], values[2])
            np.testing.assert_allclose(values[0], coloured_values(H, x, lam, 0.3), rtol=1e-5,
                                       atol=1e-5 * np.abs(values[0]).max())
    one, two = (trajopt.solve(cartpole_swingup(N=12), trajopt.VI(s=3), verbose=False, threads=t) for t in (1, 2))
    assert one.success and one.iterations == two.iterations and np.array_equal(one.x, two.x)
    with pytest.raises(ValueError, match="threads"):
        trajopt.Ipopt(threads=0)


def test_pattern_functions_refuse_bad_patterns():
    """The colourings, gram_pattern, probed_pattern and the Hessian's threads name what is wrong."""
    from hovi import _core
    i32 = lambda *a: np.array(a, np.int32)                     # noqa: E731
    bad = [((i32(0, 2, 1, 2), i32(0, 1)), "indptr must not decrease"),
           ((i32(1, 2), i32(0, 1)), "indptr must start at 0"),
           ((i32(0, 1, 2), i32(0, 2)), "column indices out of range")]
    for (indptr, indices), message in bad:
        for f in (_core.trajopt.star_colouring, _core.trajopt.distance2_colouring):
            with pytest.raises(ValueError, match=message):
                f(indptr, indices)
        with pytest.raises(ValueError, match=message):
            _core.trajopt.gram_pattern(indptr, indices, 2)
    with pytest.raises(ValueError, match="n must be >= 0"):
        _core.trajopt.gram_pattern(i32(0), i32(), -1)
    nlp = trajopt.NLP(pendulum_swingup(N=4), trajopt.VI(s=1))
    program = nlp.program()
    with pytest.raises(ValueError, match="one row per variable"):
        program.probed_pattern(i32(0, 1), i32(0), np.zeros(nlp.n_variables))
    with pytest.raises(ValueError, match="set_colouring first"):
        program.set_hessian_options(2, False)


def test_colours_do_not_grow_with_the_horizon():
    colours = [LagrangianHessian(trajopt.NLP(cartpole_swingup(N=N), trajopt.VI(s=2))).n_colours
               for N in (8, 32)]
    assert colours[0] == colours[1]


def test_distance2_colouring_separates_variables_with_a_common_neighbour():
    P = sp.csr_matrix(np.array([[1, 1, 0, 0], [1, 1, 1, 0], [0, 1, 1, 1], [0, 0, 1, 1]], float))  # a path 0-1-2-3
    c = distance2_colouring(P)
    assert len({c[0], c[1], c[2]}) == 3 and len({c[1], c[2], c[3]}) == 3 and c[0] == c[3]


def readable_from_one_side(P, colour):
    """Every coupled pair (i, j) of the pattern P has a side whose row meets the other's colour once."""
    P = sp.coo_matrix(P)
    count = np.zeros((P.shape[0], colour.max() + 1), int)
    np.add.at(count, (P.row, colour[P.col]), 1)
    return bool(np.all((count[P.row, colour[P.col]] == 1) | (count[P.col, colour[P.row]] == 1)))


def test_star_colouring_reads_every_entry_from_one_side_with_fewer_colours():
    hub = np.zeros((9, 9))
    hub[0, :] = hub[:, 0] = 1
    hub = sp.csr_matrix(hub + np.eye(9))                  # one variable coupled to all: two colours suffice
    assert star_colouring(hub).max() + 1 == 2 and distance2_colouring(hub).max() + 1 == 9
    rng = np.random.default_rng(3)
    for density in (0.02, 0.1, 0.3):                      # random symmetric patterns, checked entry by entry
        A = sp.random(60, 60, density, random_state=rng, format="csr")
        P = ((A + A.T + sp.eye(60)) != 0).astype(float).tocsr()
        star, d2 = star_colouring(P), distance2_colouring(P)
        r, c = P.nonzero()
        assert np.all(star[r[r != c]] != star[c[r != c]])
        assert readable_from_one_side(P, star) and star.max() <= d2.max()
    nlp = trajopt.NLP(cartpole_swingup(N=8), trajopt.VI(s=2))
    H = LagrangianHessian(nlp, probe=np.zeros(nlp.n_variables))
    P = sp.coo_matrix((np.ones(len(H.rows)), (H.rows, H.cols)), (nlp.n_variables,) * 2)
    assert readable_from_one_side(P + P.T, H.colour)


@pytest.mark.parametrize("make", [pendulum_swingup, slider_crank_to_target])
def test_newton_steps_with_the_coloured_hessian_reach_the_lbfgs_optimum_in_fewer_iterations(make):
    lbfgs = trajopt.solve(make(), trajopt.VI(s=2), verbose=False, hessian="lbfgs", continuation=False)
    exact = trajopt.solve(make(), trajopt.VI(s=2), verbose=False, hessian="fd", continuation=False)
    assert lbfgs.success and exact.success
    assert exact.cost == pytest.approx(lbfgs.cost, rel=1e-6)
    np.testing.assert_allclose(exact.trajectory["q"], lbfgs.trajectory["q"], atol=1e-5)
    assert exact.iterations < lbfgs.iterations


def test_hessian_choice_is_checked():
    prob = pendulum_swingup(N=4)
    with pytest.raises(ValueError, match="hessian must be"):
        trajopt.solve(prob, verbose=False, hessian="bfgs")
    prob.add_cost(trajopt.CallbackCost(lambda t, w, q, v, u: (0.0, 0 * q, 0 * v, 0 * u)))
    with pytest.raises(ValueError, match="CallbackCost"):
        trajopt.solve(prob, verbose=False, hessian="fd")
    with pytest.raises(ValueError, match="CallbackCost"):
        trajopt.solve(prob, verbose=False, hessian="directional")
    # the default, 'auto', takes the limited-memory Hessian for a CallbackCost, the directional one otherwise
    assert trajopt.Ipopt().hessian_for(trajopt.NLP(prob)) == "lbfgs"
    assert trajopt.Ipopt().hessian_for(trajopt.NLP(pendulum_swingup(N=4))) == "directional"
    assert trajopt.solve(prob, trajopt.VI(s=2), verbose=False).success


def test_nlps_over_one_transcription_that_differ_in_bounds_probe_once(monkeypatch):
    """A contact homotopy's solves (relaxed, then exact on sides) share the probed pattern, which is
    the one a fresh probe finds; another cost probes again."""
    _, prob = tumbling_block()
    tr = trajopt.VI(s=1).transcribe(prob)
    probes = []
    original = LagrangianHessian.probed_pattern
    monkeypatch.setattr(LagrangianHessian, "probed_pattern",
                        lambda self, P, x, seed=0, own=False: probes.append(1) or original(self, P, x, seed, own))
    x0 = tr.initial_guess(None)
    first = LagrangianHessian(trajopt.NLP(prob, tr, relaxation=ComplementarityRelaxation(1e-1)), probe=x0)
    nlp = trajopt.NLP(prob, tr, relaxation=ComplementarityRelaxation(1e-3))
    again = LagrangianHessian(nlp, probe=x0 + 0.01)
    assert len(probes) == 1
    fresh = LagrangianHessian(nlp, probe=x0 + 0.01, seed=1)   # another seed: its own probe
    assert len(probes) == 2
    for H in (again, fresh):
        np.testing.assert_array_equal(H.rows, first.rows)
        np.testing.assert_array_equal(H.cols, first.cols)
    prob.add_cost(trajopt.StateTracking(np.zeros(prob.model.n), weight=1.0))
    LagrangianHessian(trajopt.NLP(prob, tr, relaxation=ComplementarityRelaxation(1e-3)), probe=x0)
    assert len(probes) == 3
