"""bench/casadi_baseline.py, the CasADi side of the trajectory-optimisation comparison: its
hand-written CasADi dynamics are hovi's models, its Hermite-Simpson NLP is hovi's (the same optimum as
hovi's HermiteSimpson at the same N), and its one-interval error measures what it should.

Skipped without casadi (a bench-only dependency, requirements-dev.txt).

The pendulum at N = 40 has two nearby local optima of the Hermite-Simpson NLP from the hanging rest:
cost 1.0944 (first swing to +q) and 1.2959 (first swing to -q). CasADi's exact-Hessian IPOPT and
hovi with hessian='fd' find the first; hovi's default limited-memory Hessian takes the other path
from the same start and ends in the second. Warm-started from CasADi's solution hovi's default
stays on it: the two NLPs are the same."""
import numpy as np
import pytest

pytest.importorskip("casadi")

from conftest import bench_module  # noqa: E402

cb = bench_module("casadi_baseline")

from hovi import trajopt  # noqa: E402
from hovi.examples import swingups  # noqa: E402

NAMES = ["pendulum", "cartpole", "acrobot"]


@pytest.mark.parametrize("name", NAMES)
def test_dynamics_match_hovi(name):
    """CasADi's q̈ (a symbolic Lagrangian) = hovi's forward dynamics of the example's model with
    tau = B u, at 20 random states and controls, to 1e-12 (relative to max(1, |q̈|))."""
    f = cb.dynamics(name)
    model = swingups.EXAMPLES[name](N=2).model
    np.testing.assert_array_equal(cb.ACTUATION[name], model.actuation)
    n, m = cb.ACTUATION[name].shape
    rng = np.random.default_rng(33)
    for _ in range(20):
        q, qd, u = rng.uniform(-2 * np.pi, 2 * np.pi, n), rng.normal(0, 3, n), rng.normal(0, 5, m)
        ours = np.array(f(q, qd, u)).ravel()
        theirs = model.forward_dynamics(q, qd, model.actuation @ u)
        assert np.abs(ours - theirs).max() <= 1e-12 * max(1.0, np.abs(theirs).max())
    # the mass matrix: q̈ is affine in u with slope M⁻¹ B
    q = rng.uniform(-np.pi, np.pi, n)
    du = np.array(f(q, np.zeros(n), np.ones(m))).ravel() - np.array(f(q, np.zeros(n), np.zeros(m))).ravel()
    np.testing.assert_allclose(model.mass_matrix(q) @ du, cb.ACTUATION[name] @ np.ones(m), atol=1e-12)


def test_problem_data_are_hovis():
    sw = cb.swingup("cartpole", 50)
    assert (sw.N, sw.T) == (50, 2.5)
    np.testing.assert_array_equal(sw.q_lower[:1], [-1.0])
    np.testing.assert_array_equal(sw.u_upper, [20.0])
    np.testing.assert_array_equal(sw.qT, [0.0, np.pi])


@pytest.fixture(scope="module")
def pendulum40():
    return cb.solve("pendulum", 40)


def test_pendulum_swings_up(pendulum40):
    s = pendulum40
    assert s.success, s.status
    np.testing.assert_allclose(s.q[-1], [np.pi], atol=1e-12)
    np.testing.assert_allclose(s.qd[-1], [0.0], atol=1e-12)
    np.testing.assert_allclose(s.q[0], [0.0], atol=1e-12)
    assert np.abs(s.u).max() <= 4.0 + 1e-12
    assert s.setup_seconds > 0 and s.ipopt_seconds > 0 and s.iterations > 0
    assert s.cost == pytest.approx(1.0944014, rel=1e-6)


def test_pendulum_is_hovis_hermite_simpson(pendulum40):
    """The same NLP as hovi's HermiteSimpson('implicit') at N = 40: the same optimum (cost, knots,
    controls) from CasADi's solution, and from the cold start with hovi's exact-ish Hessian ('fd');
    hovi's default L-BFGS from the cold start ends in the other, costlier local optimum (module
    docstring), never in a cheaper one."""
    s = pendulum40
    method = trajopt.HermiteSimpson("implicit")
    default = trajopt.solve(swingups.pendulum_swingup(N=40), method, verbose=False)
    assert default.success and s.cost <= default.cost * (1 + 1e-8)
    warm = trajopt.solve(swingups.pendulum_swingup(N=40), method, verbose=False, guess=s.as_guess())
    fd = trajopt.solve(swingups.pendulum_swingup(N=40), method, verbose=False, hessian="fd")
    for r in (warm, fd):
        assert r.success
        assert r.cost == pytest.approx(s.cost, rel=1e-9)
        np.testing.assert_allclose(r.trajectory["q"], s.q, atol=1e-5)
        np.testing.assert_allclose(r.trajectory["u"], s.u, atol=1e-4)
    # and hovi's one-interval error of its own solution is CasADi's
    assert cb.hovi_one_interval_error(fd, "pendulum") == pytest.approx(cb.casadi_one_interval_error(s), rel=1e-4)


def test_one_interval_error_is_the_transcription_error(pendulum40):
    """Hermite-Simpson's local error is O(h^5): halving h shrinks the one-interval error ~32x (> 10x
    here); the knots of an exact solution (hovi's fine VI rollout of zero controls) give ~0."""
    e40 = cb.casadi_one_interval_error(pendulum40)
    e80 = cb.casadi_one_interval_error(cb.solve("pendulum", 80))
    assert 1e-8 < e80 < e40 / 10
    import hovi
    prob = swingups.pendulum_swingup(N=10)
    integ = hovi.Integrator(prob.model, s=3, dt=0.2 / 32, tol=1e-14)
    traj = integ.rollout([1.0], 320, qdot0=[0.0])
    q, qd = np.asarray(traj.q)[::32], np.asarray(traj.qdot)[::32]
    err = cb.one_interval_error(prob.model, prob.model.actuation, np.arange(11) * 0.2, q, qd, lambda t: np.zeros((len(t), 1)))
    assert err < 1e-9


def test_quick_comparison_rows():
    """run() on the pendulum at N = 10: CasADi's SX and MX graphs agree, every row has the columns
    of the table, and the summary picks a hovi row at least as accurate as CasADi's."""
    out = cb.run({"pendulum": (10,)}, refine=4, log=lambda *a: None)
    rows = out["swingups"]["pendulum"]["rows"]
    sx, mx = rows[0], rows[1]
    assert sx["solver"] == "CasADi HS (SX)" and mx["solver"] == "CasADi HS (MX)"
    assert sx["cost"] == pytest.approx(mx["cost"], rel=1e-9)
    # hovi's default pipeline for every method, and each s >= 2 and Hermite-Simpson also solved directly
    assert {r["solver"] for r in rows[2:]} == {f"hovi {m[0]}" for m in cb.HOVI_METHODS} | \
        {f"hovi {m[0]} (direct)" for m in cb.HOVI_METHODS if m[2] > 1 or m[1] == "hs"}
    direct = {r["solver"]: r for r in rows[2:]}
    for label, _, _ in cb.HOVI_METHODS[1:]:      # the same problem and optimum either way
        assert direct[f"hovi {label}"]["cost"] == pytest.approx(direct[f"hovi {label} (direct)"]["cost"], rel=1e-7)
    for r in rows:
        for key in ("setup_seconds", "ipopt_seconds", "iterations", "cost_error", "one_interval_error"):
            assert np.isfinite(r[key])
    m = out["matches"]["pendulum"]
    if m["hovi"] is not None:
        assert m["hovi"]["cost_error"] <= m["casadi"]["cost_error"]
    assert "| pendulum | 10 | CasADi HS (SX) |" in cb.report(out)
