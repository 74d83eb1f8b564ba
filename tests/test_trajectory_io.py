"""Trajectories saved to .npz and read back: every array identical, the statistics kept, and
files that do not fit the integrator rejected with a clear error."""
import numpy as np
import pytest

import hovi


def rollout(model, s=2):
    integ = hovi.Integrator(model, s=s, dt=0.01)
    q0 = np.random.default_rng(0).uniform(-0.3, 0.3, model.n)
    return integ, integ.rollout(q0, 50)


def test_round_trip_keeps_every_array_and_the_statistics(tmp_path):
    integ, traj = rollout(hovi.examples.models.pendulum(4))
    path = tmp_path / "pendulum.npz"
    traj.save(path)
    back = hovi.load_trajectory(path, integ)
    for name in ("t", "q", "p", "control_points", "iterations", "residuals", "factorizations"):
        np.testing.assert_array_equal(getattr(back, name), getattr(traj, name), err_msg=name)
    assert back.status == traj.status and back.solve_seconds == traj.solve_seconds
    assert back.multipliers is None
    np.testing.assert_array_equal(back.energy, traj.energy)  # the integrator is attached


def test_constrained_multipliers_round_trip(tmp_path):
    model = hovi.examples.models.fourbar()
    integ = hovi.Integrator(model, s=1, dt=0.01)
    q, qd = integ.project(np.full(model.n, 0.3), np.zeros(model.n))
    traj = integ.rollout(q, 20, qdot0=qd)
    traj.save(tmp_path / "fourbar.npz")
    back = hovi.load_trajectory(tmp_path / "fourbar.npz")
    assert traj.multipliers is not None and traj.multipliers.size > 0
    np.testing.assert_array_equal(back.multipliers, traj.multipliers)
    assert back.discretization is None


def test_files_that_do_not_fit_are_rejected(tmp_path):
    integ, traj = rollout(hovi.examples.models.pendulum(4))
    path = tmp_path / "t.npz"
    traj.save(path)
    with pytest.raises(ValueError, match="joint names"):
        hovi.load_trajectory(path, hovi.Integrator(hovi.examples.models.pendulum(5), s=2, dt=0.01))
    with pytest.raises(ValueError, match="s = 2, dt = 0.01 differ"):
        hovi.load_trajectory(path, hovi.Integrator(hovi.examples.models.pendulum(4), s=3, dt=0.01))
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    with pytest.raises(ValueError, match="not a hovi trajectory"):
        hovi.load_trajectory(tmp_path / "other.npz")
    (tmp_path / "junk.npz").write_bytes(b"not a zip file")
    with pytest.raises(ValueError, match="not a trajectory file"):
        hovi.load_trajectory(tmp_path / "junk.npz")
    with pytest.raises(ValueError, match="no integrator"):
        hovi.Trajectory(t=traj.t, q=traj.q, p=traj.p, control_points=traj.control_points,
                        iterations=traj.iterations, residuals=traj.residuals).save(tmp_path / "x.npz")


def test_a_trajectory_carries_its_discretization_not_the_integrator():
    integ, traj = rollout(hovi.examples.models.pendulum(3), s=3)
    d = traj.discretization
    assert d is integ.discretization and (d.s, d.dt, d.model) == (3, 0.01, integ.model)
    np.testing.assert_array_equal(traj.energy, integ.energies(traj.q, traj.p))
    np.testing.assert_array_equal(traj.qdot[5], integ.velocity(traj.q[5], traj.p[5]))
    # every configuration sample in time order: q^{k,0..s-1} of each step, then q^K
    Q = traj.configuration_points
    assert Q.shape == (50 * 3 + 1, 3)
    np.testing.assert_array_equal(Q[3 * 7:3 * 8], traj.control_points[7, :3])
    np.testing.assert_array_equal(Q[3 * 8], traj.q[8])
    np.testing.assert_array_equal(Q[-1], traj.q[-1])


def test_controls_are_recorded_saved_and_loaded(tmp_path):
    """A rollout keeps the controls of its steps per control point (held ones repeated, none given:
    zero); the file carries them; a replay of the loaded controls is the rollout, bit for bit."""
    model = hovi.examples.models.cartpole()
    integ = hovi.Integrator(model, s=2, dt=0.01)
    u = np.sin(np.arange(30))[:, None]                       # (steps, m): held over each step
    traj = integ.rollout([0.0, 0.3], 30, u=u)
    np.testing.assert_array_equal(traj.controls, np.repeat(u[:, None, :], 3, axis=1))
    assert not integ.rollout([0.0, 0.3], 5).controls.any()  # no controls given: zero
    traj.save(tmp_path / "c.npz")
    back = hovi.load_trajectory(tmp_path / "c.npz", integ)
    np.testing.assert_array_equal(back.controls, traj.controls)
    np.testing.assert_array_equal(integ.rollout(back.q[0], 30, p0=back.p[0], u=back.controls).q, traj.q)
    arrays = dict(np.load(tmp_path / "c.npz"))
    arrays["controls"] = arrays["controls"][:, :2]
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(ValueError, match=r"controls must have shape \(K, s\+1, m\) with K = 30, s = 2, got \(30, 2, 1\)"):
        hovi.load_trajectory(tmp_path / "bad.npz", integ)
    assert hovi.Integrator(hovi.examples.models.pendulum(2)).rollout([0.1, 0.0], 3).controls is None  # no controls


def test_an_optimised_trajectory_is_converged_and_carries_its_controls():
    """A VI solution as a Trajectory: status 'optimized' counts as converged (the DEL equations are the
    optimiser's constraints), and its controls are the solution's."""
    from hovi import trajopt
    from hovi.examples.swingups import pendulum_swingup
    prob = pendulum_swingup(N=20, T=1.0)
    result = trajopt.solve(prob, trajopt.VI(s=1), options={"print_level": 0})
    traj = result.transcription.solution_trajectory(result.x)
    assert traj.status == ["optimized"] * 20 and traj.converged
    np.testing.assert_array_equal(traj.controls, result.transcription.stage_controls(result.x))
