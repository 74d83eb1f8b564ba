"""The linearisation of a free base's step in tangent coordinates (cpp/include/hovi/integrators/
free_base_jacobians.hpp) and LQR on it: A and B against central differences of the step taken through
``Model.integrate`` and ``Model.difference`` (an independent computation: whole steps, solved anew);
the quadrotor's LQR at hover from attitudes and on plants it was not made for."""
import numpy as np
import pytest

import hovi
from conftest import bench_module
from hovi.contact import Contacts, Terrain
from hovi.control import Push, lqr, simulate, tvlqr
from hovi.control.lqr import equilibrium_controls
from hovi.examples.models import quadrotor

fb = bench_module("free_base")
bq = bench_module("quadrotor")


def actuated_chain():
    """bench/free_base.py's floating chain with its joints actuated, a damper and drag on the base."""
    m = fb.chain()
    m.add_actuator("upper_joint")
    m.add_actuator("lower_joint", gear=2.0)
    m.add_damper("lower_joint", 0.1)
    m.add_drag("body", 0.3, 0.05)
    return m


def random_state(model, integ, rng):
    q = model.neutral()
    q[:3] = rng.normal(size=3)
    quat = rng.normal(size=4)
    q[3:7] = quat / np.linalg.norm(quat)
    q[7:] = 0.5 * rng.normal(size=model.nq - 7)
    return q, integ.momentum(q, rng.normal(size=model.nv))


def axis_angle(axis, degrees):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    half = np.radians(degrees) / 2
    return np.r_[np.sin(half) * axis, np.cos(half)]


@pytest.mark.parametrize("build", [quadrotor, actuated_chain])
@pytest.mark.parametrize("s", [1, 2])
def test_step_jacobians_are_the_differences_through_integrate_and_difference(build, s, rng):
    model = build()
    integ = hovi.Integrator(model, s=s, dt=0.01)
    n, m = model.nv, model.n_controls
    q, p = random_state(model, integ, rng)
    u = 3 * rng.normal(size=(s + 1, m))
    lin = hovi.Linearizer(integ).step_jacobians(q, p, u)
    assert lin.A.shape == (2 * n, 2 * n) and lin.B.shape == (2 * n, (s + 1) * m)

    def tangent(qq, pp, uu):  # the step's end as a tangent vector at the nominal end
        q1, p1, info = integ.step(qq, pp, uu)
        assert info.converged
        return np.r_[model.difference(lin.q_next, q1), p1 - lin.p_next]

    h = 1e-5
    A = np.array([tangent(model.integrate(q, e[:n]), p + e[n:], u) - tangent(model.integrate(q, -e[:n]), p - e[n:], u)
                  for e in h * np.eye(2 * n)]).T / (2 * h)
    B = np.array([tangent(q, p, u + e.reshape(s + 1, m)) - tangent(q, p, u - e.reshape(s + 1, m))
                  for e in h * np.eye((s + 1) * m)]).T / (2 * h)
    assert np.abs(lin.A - A).max() <= 1e-7 * np.abs(A).max()
    assert np.abs(lin.B - B).max() <= 1e-6 * np.abs(B).max()


def test_a_rollouts_jacobians_are_its_steps_and_a_batch_its_rollouts(rng):
    model = quadrotor()
    integ = hovi.Integrator(model, s=2, dt=0.02)
    lin = hovi.Linearizer(integ)
    q0, p0 = random_state(model, integ, rng)
    u = 2.45 + rng.normal(size=(6, 3, 4))
    traj = integ.rollout(q0, 6, p0=p0, u=u)
    As, Bs = lin.rollout_jacobians(traj, u)
    for k in range(6):
        A, B = lin.linearize_at(traj.control_points[k], u[k], start=traj.q[k])  # the same step: the same numbers
        assert np.array_equal(As[k], A) and np.array_equal(Bs[k], B)
        step = lin.step_jacobians(traj.q[k], traj.p[k], u[k])  # the step solved anew: equal to its Newton tolerance
        assert np.abs(As[k] - step.A).max() <= 1e-8 * np.abs(step.A).max()
        assert np.abs(Bs[k] - step.B).max() <= 1e-8 * np.abs(step.B).max()
    A2, B2 = lin.linearize_at(traj.control_points, u, start=traj.q[:-1])
    assert np.array_equal(A2, As) and np.array_equal(B2, Bs)
    batch = integ.rollout_batch(np.array([q0, traj.q[3]]), 6, p0s=np.array([p0, traj.p[3]]), u=np.array([u, u]))
    jac = lin.rollout_jacobians_batch(batch, np.array([u, u]))
    assert jac.errors == [None, None]
    assert np.abs(jac.A[0] - As).max() <= 1e-12 * np.abs(As).max()
    with pytest.raises(ValueError, match="start q"):
        lin.linearize_at(traj.control_points[0], u[0])


@pytest.mark.parametrize("build", [quadrotor, actuated_chain])
def test_the_forces_jacobians_are_their_differences(build, rng):
    """force_jacobians on a free base, in its velocity's coordinates: dQ/dq by a tangent δ of q (q ⊕ δ, the
    velocity held), dQ/dv and dQ/du against central differences (a follower thrust, drag, a damper)."""
    model = build()
    model.add_drag("body", 0.4, 0.1)
    n, m = model.nv, model.n_controls
    q, _ = random_state(model, hovi.Integrator(model, s=1, dt=0.01), rng)
    v, u = rng.normal(size=n), rng.normal(size=m)
    Q, Qq, Qv, Qu = model.force_jacobians(q, v, u)
    h = 1e-6
    dq = np.array([model.force_jacobians(model.integrate(q, e), v, u)[0] - model.force_jacobians(model.integrate(q, -e), v, u)[0]
                   for e in h * np.eye(n)]).T / (2 * h)
    dv = np.array([model.force_jacobians(q, v + e, u)[0] - model.force_jacobians(q, v - e, u)[0]
                   for e in h * np.eye(n)]).T / (2 * h)
    du = np.array([model.force_jacobians(q, v, u + e)[0] - model.force_jacobians(q, v, u - e)[0]
                   for e in h * np.eye(m)]).T / (2 * h)
    for exact, differenced in ((Qq, dq), (Qv, dv), (Qu, du)):
        assert np.abs(exact - differenced).max() <= 1e-7 * (1 + np.abs(differenced).max())


def test_the_hover_controls_balance_gravity():
    model = quadrotor(mass=1.3)
    integ = hovi.Integrator(model, s=1, dt=0.01)
    q = model.neutral()
    q[2] = 1.0
    u = equilibrium_controls(integ, q)
    assert np.abs(u - 1.3 * 9.81 / 4).max() <= 1e-9
    q[3:7] = axis_angle((1, 0, 0), 90)  # on its side: the thrusts push sideways, nothing holds it up
    with pytest.raises(ValueError, match="q is not an equilibrium"):
        lqr(integ, q)


@pytest.mark.parametrize("axis, degrees", [((1, 0, 0), 30), ((0.3, 1, 0.2), 90), ((1, -1, 0.5), 150),
                                           ((0, 1, 0), 179)])
def test_lqr_brings_a_quadrotor_back_to_hover_from_any_attitude(axis, degrees):
    """One LQR made at hover (tangent coordinates: no attitude is singular) from tilts up to upside
    down, on a plant 20 % heavier than its model with thrust limits the design did not see."""
    model = quadrotor()
    integ = hovi.Integrator(model, s=1, dt=0.01)
    q_eq = model.neutral()
    q_eq[2] = 1.0
    policy = lqr(integ, q_eq, q_weight=[10, 10, 10, 1, 1, 1], v_weight=1.0, u_weight=0.1, u_limits=(-15, 15))
    plant_model = quadrotor(mass=1.2)
    plant = hovi.Integrator(plant_model, s=1, dt=0.01)
    q0 = q_eq.copy()
    q0[:3] = [0.5, -0.3, 1.2]
    q0[3:7] = axis_angle(axis, degrees)
    run = simulate(plant, policy, q0, 800, qdot0=[0.2, 0, 0, 0, 1.0, 0])
    assert run.converged
    # the heavier plant hovers below the reference (proportional feedback): its attitude comes back level
    tail = np.array([plant_model.difference(q_eq, q) for q in run.trajectory.q[-100:]])
    assert np.abs(tail[:, 3:]).max() < 1e-2
    assert np.abs(tail[:, :3]).max() < 0.5


def test_the_policy_in_python_is_the_loops_and_a_push_is_rejected():
    model = quadrotor()
    integ = hovi.Integrator(model, s=2, dt=0.01)
    q_eq = model.neutral()
    q_eq[2] = 1.0
    policy = lqr(integ, q_eq, q_weight=10.0, v_weight=1.0, u_weight=0.1)
    run = simulate(integ, policy, q_eq, 300, pushes=[Push(time=0.5, body="body", impulse=(0.5, 0, 0),
                                                           point=(0, 0.1, 0.05), angular=(0, 0.02, 0))])
    assert run.converged
    traj = run.trajectory
    for k in (0, 49, 50, 51, 120):
        assert np.abs(policy.control(k, traj.q[k], traj.p[k], model) - run.u[k]).max() <= 1e-10
    moved = np.array([model.difference(q_eq, q) for q in traj.q])
    assert np.abs(moved[60]).max() > 0.01  # the push moved it
    assert np.abs(moved[-1]).max() < 0.02 * np.abs(moved).max()
    with pytest.raises(ValueError, match="needs its model"):
        policy.control(0, q_eq, np.zeros(6))


def test_a_push_on_a_free_base_is_its_wrench_impulse():
    """A push (impulse at a point, angular impulse) changes the public momentum by the wrench impulse's
    conjugate: the linear momentum (in the base's frame) by R^T J and the angular by r x J + L."""
    model = quadrotor()
    integ = hovi.Integrator(model, s=1, dt=0.01)
    q = model.neutral()
    q[3:7] = axis_angle((1, 2, 3), 70)
    policy = hovi.control.Policy(x_ref=np.r_[q, np.zeros(6)][None], u_ref=np.zeros((1, 2, 4)),
                                 gains=np.zeros((1, 4, 12)), lower=np.full(4, -np.inf), upper=np.full(4, np.inf),
                                 cost_to_go=np.zeros((1, 12, 12)), dt=0.01, s=1)
    J, L, r = np.array([0.3, -0.2, 0.5]), np.array([0.01, 0.02, -0.03]), np.array([0.1, 0.05, -0.02])
    run = simulate(integ, policy, q, 1, pushes=[Push(time=0.0, body="body", impulse=J, point=r, angular=L)])
    R = fb.quaternion_matrix(q[3:7])
    expected = np.r_[R.T @ J, np.cross(r, R.T @ J) + R.T @ L]
    assert np.abs(run.trajectory.p[0] - expected).max() <= 1e-12


def test_what_is_not_on_a_free_base_yet_says_so():
    model = quadrotor()
    with pytest.raises(hovi.ModelError, match="free base"):  # its chart's rows need the step's centre
        hovi.Linearizer(hovi.Integrator(model, s=1, dt=0.01)).del_jacobian(np.zeros((2, 6)))
    with pytest.raises(hovi.ModelError, match="free base"):
        hovi.trajopt.VI(1).transcribe(hovi.trajopt.Problem(model, 5, 0.05, controls="held"))


@pytest.mark.parametrize("build", [quadrotor, actuated_chain])
def test_the_cost_state_map_is_the_velocitys_derivative(build, rng):
    """T = d(q ⊖ q_ref, v)/d(q ⊖ q_ref, p) away from rest: against central differences of
    Integrator.velocity through integrate."""
    model = build()
    integ = hovi.Integrator(model, s=1, dt=0.01)
    n = model.nv
    q, p = random_state(model, integ, rng)
    T = hovi._core.control.velocity_state_map(model, q[None], p[None])[0]
    h = 1e-6
    dv_dq = np.array([integ.velocity(model.integrate(q, e), p) - integ.velocity(model.integrate(q, -e), p)
                      for e in h * np.eye(n)]).T / (2 * h)
    dv_dp = np.array([integ.velocity(q, p + e) - integ.velocity(q, p - e) for e in h * np.eye(n)]).T / (2 * h)
    assert np.array_equal(T[:n], np.eye(n, 2 * n))
    scale = np.abs(dv_dq).max() + np.abs(integ.velocity(q, p)).max()  # velocity per radian (the quadrotor's is 0)
    assert np.abs(T[n:, :n] - dv_dq).max() <= 1e-7 * scale
    assert np.abs(T[n:, n:] - dv_dp).max() <= 1e-8 * np.abs(dv_dp).max()


def test_tvlqr_tracks_a_quadrotor_flip_on_a_heavier_plant():
    """A flip (a full turn about x from open-loop roll-torque pulses, bench/quadrotor.py's, through every
    attitude an Euler chart has trouble with) tracked by time-varying LQR on a plant 20 % heavier with
    another inertia: without feedback the plant ends metres and radians off; with it, near the end."""
    model = quadrotor()
    integ = hovi.Integrator(model, s=1, dt=0.01)
    q0, u, ref = bq.flip_reference(integ)
    roll = np.unwrap([2 * np.arctan2(q[3], q[6]) for q in ref.q])
    assert np.degrees(roll[-1]) > 355
    policy = tvlqr(integ, ref, u, q_weight=[10, 10, 10, 2, 2, 2], v_weight=1.0, u_weight=0.05)
    assert policy.x_ref.shape == (len(u), 13)
    plant = hovi.Integrator(bq.quadrotor("free", *bq.HEAVIER), s=1, dt=0.01)
    closed = simulate(plant, policy, q0, len(u))
    opened = simulate(plant, policy.without_feedback(), q0, len(u))
    assert closed.converged and opened.converged
    miss = lambda run: np.abs(model.difference(ref.q[-1], run.trajectory.q[-1])).max()
    assert miss(opened) > 1.0
    assert miss(closed) < 0.05 * miss(opened)


CONTACT_CASES = {  # (friction, body velocity (linear, angular in its frame), contact points under the body)
    "one point sticking": (0.8, [0, 0, 0, 0.1, -0.2, 0.3], [(0, 0, -0.1)]),
    "one point sliding": (0.3, [1.5, 0.5, 0, 0.1, -0.2, 0.3], [(0, 0, -0.1)]),
    "two points sliding": (0.3, [1.5, 0.5, 0, 0.1, 0.0, 0.3], [(0.1, 0, -0.1), (-0.1, 0, -0.1)]),
    "two points sticking": (0.9, [0, 0, 0, 0, 0, 0.3], [(0.1, 0, -0.1), (-0.1, 0, -0.1)]),
}


@pytest.mark.parametrize("case", list(CONTACT_CASES))
def test_the_contact_step_of_a_free_base_is_linearised(case):
    """Through contact (each contact's state held): A and B against central differences of whole contact
    steps through integrate and difference, from a state one step after landing (contacts loaded)."""
    mu, velocity, points = CONTACT_CASES[case]
    model = quadrotor()
    integ = hovi.Integrator(model, s=1, dt=0.01, contacts=Contacts(model, [("body", p) for p in points], Terrain(), mu=mu))
    q = model.neutral()
    q[2] = 0.1
    u = np.full((2, 4), 1.0)
    q1, p1, _ = integ.step(q, integ.momentum(q, velocity), u)
    lin = hovi.Linearizer(integ).step_jacobians(q1, p1, u)
    integ.check_start = lambda *args, **kwargs: None  # the differences start 1e-6 m inside or above the ground
    n = model.nv

    def tangent(qq, pp, uu):
        qn, pn, info = integ.step(qq, pp, uu)
        return np.r_[model.difference(lin.q_next, qn), pn - lin.p_next]

    h = 1e-6
    A = np.array([tangent(model.integrate(q1, e[:n]), p1 + e[n:], u) - tangent(model.integrate(q1, -e[:n]), p1 - e[n:], u)
                  for e in h * np.eye(2 * n)]).T / (2 * h)
    hu = 1e-4  # the controls' columns are small (N -> m over a step): a larger step keeps round-off below them
    B = np.array([tangent(q1, p1, u + e.reshape(2, 4)) - tangent(q1, p1, u - e.reshape(2, 4))
                  for e in hu * np.eye(8)]).T / (2 * hu)
    # 5e-8 on the two sticking points: a pitch of the start sinks one point and lifts the other, a switch
    # at second order that the differences see as O(h) (the Euler base's do the same)
    assert np.abs(lin.A - A).max() <= 1e-7 * np.abs(A).max()
    assert np.abs(lin.B - B).max() <= 1e-8 * np.abs(B).max()
    if "sliding" in case:  # every complementarity pair away from its switch: the central path ends at the held step
        smoothed = hovi.Linearizer(integ).step_jacobians(q1, p1, u, smoothing=1e-14)
        assert np.abs(smoothed.A - lin.A).max() <= 1e-6 * np.abs(A).max()


def test_lqr_through_contact_holds_a_landed_quadrotor_against_a_push():
    """On its four legs: the statics share the weight between the thrusts and the contacts (least norm
    over both); LQR with the stance held (the contact linearisation on the free base) keeps it level and
    on its legs through a push that slides it (a sliding stance moves its rest: x and yaw stay where the
    push left them), and it comes to rest."""
    model = quadrotor()
    legs = [("body", (x, y, -0.05)) for x, y in [(0.15, 0.15), (-0.15, 0.15), (-0.15, -0.15), (0.15, -0.15)]]
    integ = hovi.Integrator(model, s=1, dt=0.01, contacts=Contacts(model, legs, Terrain(), mu=0.8))
    q = model.neutral()
    q[2] = 0.05
    policy = lqr(integ, q, q_weight=10.0, v_weight=1.0, u_weight=0.1)
    assert np.all(policy.u_ref[0, 0] > 0) and policy.u_ref[0, 0].sum() < 9.81
    run = simulate(integ, policy, q, 200, pushes=[Push(0.5, "body", [0.2, 0, 0], point=(0, 0, 0.05))])
    assert run.converged
    moved = np.array([model.difference(q, x) for x in run.trajectory.q])
    assert np.abs(moved[:, 0]).max() > 1e-3                  # the push slid it
    assert np.abs(moved[:, 3:5]).max() < 1e-3                # level throughout (roll, pitch)
    assert np.abs(run.trajectory.qdot[-2]).max() < 1e-6      # at rest again
    assert run.trajectory.contact.gaps.min() >= -1e-9


def test_bad_starts_references_and_plants_are_named():
    model = quadrotor()
    integ = hovi.Integrator(model, s=1, dt=0.01)
    lin = hovi.Linearizer(integ)
    traj = integ.rollout(model.neutral(), 2, u=np.full((2, 2, 4), 2.0))
    with pytest.raises(ValueError, match="start must be a 1-D array of length 7"):
        lin.linearize_at(traj.control_points[0], np.full((2, 4), 2.0), start=np.zeros(6))
    with pytest.raises(ValueError, match=r"starts \(steps, nq\)"):
        lin.linearize_at(traj.control_points, np.full((2, 2, 4), 2.0), start=np.zeros((2, 6)))
    pendulum = hovi.Integrator(hovi.examples.models.pendulum(1), s=1, dt=0.01)
    with pytest.raises(ValueError, match="start is for a model with a free base"):
        hovi.Linearizer(pendulum).linearize_at(np.zeros((2, 1)), start=np.zeros(1))
    policy = lqr(integ, np.r_[0, 0, 1.0, 0, 0, 0, 1.0])
    with pytest.raises(ValueError, match=r"x_ref must have shape \(S, nq \+ n\)"):
        hovi.control.Policy(x_ref=np.zeros((1, 14)), u_ref=policy.u_ref, gains=policy.gains, lower=policy.lower,
                            upper=policy.upper, cost_to_go=policy.cost_to_go, dt=0.01, s=1)
    euler = hovi.Integrator(bq.quadrotor("euler", *bq.NOMINAL), s=1, dt=0.01)  # n = 6 as well, nq = 6
    with pytest.raises(ValueError, match=r"the plant \(nq = 6, n = 6.*does not fit the policy \(nq = 7"):
        simulate(euler, policy, np.r_[0, 0, 1.0, 0, 0, 0], 2)
