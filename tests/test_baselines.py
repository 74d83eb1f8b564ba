"""The Section 5 baselines through Python: the same equations and solutions as hovi's own
algorithms (their full tests are the C++ ones in cpp/tests/test_*baselines*)."""
import numpy as np
import pytest

import hovi
import hovi.baselines


@pytest.mark.parametrize("armature", [False, True])
def test_autodiff_matches_recursive_algorithms(armature):
    model = hovi.examples.models.pendulum(5)
    if armature:  # 1/2 a q̇^2 in the automatically differentiated L_d
        model.armature = [0.2, 0.0, 0.1, 0.3, 0.05]
    integ = hovi.Integrator(model, s=2, dt=0.02, direction="recursive")
    lin = hovi.Linearizer(integ)
    ad = hovi.baselines.AutodiffDel(model, 2, 0.02)
    rng = np.random.default_rng(0)
    qc, p = rng.uniform(-1, 1, (3, 5)), rng.uniform(-1, 1, 5)
    r, pn = integ.del_residual(qc, p)
    r_ad, pn_ad = ad.residual(qc, p)
    np.testing.assert_allclose(r_ad, r, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(pn_ad, pn, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(ad.newton_direction(qc, p), integ.newton_direction(qc, p), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(ad.d2Ld(qc), lin.del_jacobian(qc).dq, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("armature", [False, True])
def test_quasi_newton_and_newton_reach_the_same_step(armature):
    model = hovi.examples.models.pendulum(8)
    if armature:  # the quasi-Newton Jacobian -(M(q^k) + diag(a)) / dt
        model.armature = np.linspace(0.0, 0.4, 8)
    rng = np.random.default_rng(1)
    q0, qd0 = rng.uniform(-0.5, 0.5, (2, 10, 8))
    newton = hovi.baselines.one_step_batch(model, 0.005, q0, qd0, "newton", tol=1e-12)
    qn = hovi.baselines.one_step_batch(model, 0.005, q0, qd0, "quasi_newton", tol=1e-12)
    assert newton["converged"].all() and qn["converged"].all()
    assert (qn["iterations"] > newton["iterations"]).all()  # linear against quadratic convergence
    np.testing.assert_allclose(qn["q_next"], newton["q_next"], atol=1e-10)
    integ = hovi.Integrator(model, s=1, dt=0.005, tol=1e-12)
    q1, _, _ = integ.step(q0[0], integ.momentum(q0[0], qd0[0]))
    np.testing.assert_allclose(newton["q_next"][0], q1, atol=1e-10)


def test_continuation_batch_reports_the_branch_or_an_explicit_failure():
    model = hovi.examples.models.pendulum(32)
    rng = np.random.default_rng(0)
    q0, qd0 = rng.uniform(-np.pi / 2, np.pi / 2, (2, 30, 32))
    easy = hovi.baselines.one_step_batch(model, 0.005, q0, qd0, "continuation")
    newton = hovi.baselines.one_step_batch(model, 0.005, q0, qd0, "newton")
    assert easy["converged"].all() and newton["converged"].all()
    np.testing.assert_allclose(easy["q_next"], newton["q_next"], atol=1e-9)
    hard = hovi.baselines.one_step_batch(model, 0.06, q0, qd0, "continuation")
    assert set(hard["status"]) <= {"converged", "continuation_stalled"} and "continuation_stalled" in hard["status"]
    assert np.isfinite(hard["q_next"]).all() and np.isfinite(hard["residual"]).all()
    integ = hovi.Integrator(model, s=1, dt=0.06)
    for k in np.flatnonzero(hard["converged"]):
        p0 = integ.momentum(q0[k], qd0[k])
        r, _ = integ.del_residual(np.array([q0[k], hard["q_next"][k]]), p0)
        assert np.abs(r).max() <= 1e-10 * (1 + np.abs(p0).max())
    both = hovi.baselines.one_step_batch(model, 0.06, q0, qd0, "newton+continuation")
    assert (both["converged"] >= hard["converged"]).all()


def test_hermite_simpson_converges_at_order_3_or_better_against_dop853():
    from scipy.integrate import solve_ivp
    model = hovi.examples.models.pendulum(5)
    rng = np.random.default_rng(1)
    q0, v0 = rng.uniform(-0.5, 0.5, 5), rng.uniform(-0.5, 0.5, 5)

    def f(t, y):
        return np.concatenate([y[5:], model.forward_dynamics(y[:5], y[5:])])

    ref = solve_ivp(f, (0, 1), np.concatenate([q0, v0]), method="DOP853", rtol=1e-13, atol=1e-13).y[:5, -1]
    dts = [0.05, 0.025, 0.0125, 0.00625]
    errors = []
    for dt in dts:
        d = hovi.baselines.HermiteSimpson(model, dt, tol=1e-13).rollout(q0, v0, int(round(1 / dt)))
        assert d["steps"] == int(round(1 / dt))
        errors.append(np.linalg.norm(d["q"][-1] - ref))
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert slope >= 3.0, (slope, errors)


def test_hermite_simpson_simplified_newton_gives_the_full_newton_trajectory():
    """Keeping the Jacobian within a step (the default, as for the VI) reaches the same steps."""
    model = hovi.examples.models.pendulum(8)
    q0 = np.random.default_rng(3).uniform(-np.pi / 12, np.pi / 12, 8)
    full = hovi.baselines.HermiteSimpson(model, 0.01, tol=1e-12, reuse_jacobian=False).rollout(q0, np.zeros(8), 500)
    kept = hovi.baselines.HermiteSimpson(model, 0.01, tol=1e-12).rollout(q0, np.zeros(8), 500)
    assert full["steps"] == kept["steps"] == 500
    np.testing.assert_allclose(kept["q"], full["q"], rtol=0, atol=1e-10)
    np.testing.assert_allclose(kept["v"], full["v"], rtol=0, atol=1e-9)


def test_hermite_simpson_rejects_bad_input():
    with pytest.raises(ValueError, match="dt"):
        hovi.baselines.HermiteSimpson(hovi.examples.models.pendulum(2), 0.0)
    hs = hovi.baselines.HermiteSimpson(hovi.examples.models.pendulum(2), 0.01)
    with pytest.raises(ValueError, match="q0 must be a 1-D array of length 2"):
        hs.rollout(np.zeros(3), np.zeros(2), 5)


def test_baseline_batches_and_autodiff_reject_bad_input():
    model = hovi.examples.models.pendulum(3)
    with pytest.raises(ValueError, match="method must be 'newton', 'quasi_newton', 'continuation' or 'newton"):
        hovi.baselines.one_step_batch(model, 0.01, np.zeros((1, 3)), np.zeros((1, 3)), "bisection")
    with pytest.raises(ValueError, match=r"qdot0 must be a 2-D array of shape \(1, 3\)"):
        hovi.baselines.one_step_batch(model, 0.01, np.zeros((1, 3)), np.zeros((2, 3)), "newton")
    with pytest.raises(ValueError, match="method must be 'recursive' or 'autodiff'"):
        hovi.baselines.fig3_batch(model, 2, 0.01, np.zeros((1, 3)), np.zeros((1, 3)), "symbolic")
    ad = hovi.baselines.AutodiffDel(model, 2, 0.01)
    with pytest.raises(ValueError, match=r"control_points must be a 2-D array of shape \(3, 3\)"):
        ad.residual(np.zeros((2, 3)), np.zeros(3))
    forced = hovi.examples.models.pendulum(3)
    forced.add_drag(0, 0.1)
    with pytest.raises(hovi.ModelError):
        hovi.baselines.AutodiffDel(forced, 2, 0.01)
