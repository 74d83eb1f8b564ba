"""Closed loops in C++ (hovi.control.simulate / simulate_batch, cpp/src/control/) against independent
computations: the controls the C++ loop applied equal Policy.control on the states it visited (with
saturation), and a Python loop of Integrator.step under Policy.control gives the same run; a push
changes the momentum at its knot by J(q)^T impulse with J from central differences of the point's
world position (Model.body_poses); Model.scale_mass gives the mass matrix of a model built with the
scaled mass, and batches of runs on such plants (and per-run pushes, on 1 or 2 threads) are each
run alone, bit for bit; with contacts, a feed-forward policy is the open-loop rollout bit for bit."""
import dataclasses

import numpy as np
import pytest

import hovi
from hovi import control
from hovi.contact import Contacts, Terrain
from hovi.examples import models
from hovi.examples.standing import standing

UPRIGHT = np.array([0.0, np.pi])


def zero_policy(integ, u_ref=None):
    """Zero gains and the feed-forward u_ref (m,) (default zero) at every step."""
    n, m, s = integ.n, integ.model.n_controls, integ.s
    u = np.zeros(m) if u_ref is None else np.asarray(u_ref, dtype=float)
    return control.Policy(x_ref=np.zeros((1, 2 * n)), u_ref=np.tile(u, (1, s + 1, 1)), gains=np.zeros((1, m, 2 * n)),
                          lower=np.full(m, -np.inf), upper=np.full(m, np.inf), cost_to_go=np.zeros((1, 2 * n, 2 * n)),
                          dt=integ.dt, s=s)


def python_loop(integ, policy, q0, p0, steps):
    """The closed loop in Python: u^k = policy.control(k, q^k, p^k), one Integrator.step at a time."""
    q, p = np.array(q0, dtype=float), np.array(p0, dtype=float)
    Q, P, U = [q], [p], []
    for k in range(steps):
        u = policy.control(k, q, p)
        q, p, _ = integ.step(q, p, u)
        Q.append(q), P.append(p), U.append(u)
    return np.array(Q), np.array(P), np.array(U)


# --- 6. the applied controls are Policy.control, saturated --------------------------------------

def test_applied_controls_are_policy_control_with_saturation(cartpole_lqr):
    integ, policy = cartpole_lqr
    limited = policy.with_limits(-4.0, 3.0)
    steps = 300
    run = control.simulate(integ, limited, UPRIGHT + [0.1, 0.2], steps)
    tr = run.trajectory
    assert run.converged and run.u.shape == (steps, 3, 1)
    expected = np.array([limited.control(k, tr.q[k], tr.p[k]) for k in range(steps)])
    np.testing.assert_allclose(run.u, expected, rtol=1e-12, atol=1e-12)
    assert run.u.min() >= -4.0 and run.u.max() <= 3.0
    assert np.sum(run.u[:, 0, 0] == -4.0) > 0 and np.sum(run.u[:, 0, 0] == 3.0) > 0     # both limits were hit
    assert np.sum((run.u[:, 0, 0] > -4.0) & (run.u[:, 0, 0] < 3.0)) > 100                # and left
    unlimited = policy.control(0, tr.q[0], tr.p[0])
    assert abs(unlimited[0, 0]) > 10                                                      # it did saturate
    # it still balances: the saturated LQR recovers
    assert np.abs(tr.q[-1] - UPRIGHT).max() < 0.05
    # the run is the open-loop rollout of the applied controls, and a Python loop of steps
    np.testing.assert_array_equal(integ.rollout(tr.q[0], steps, p0=tr.p[0], u=run.u).q, tr.q)
    Q, P, U = python_loop(integ, limited, tr.q[0], tr.p[0], steps)
    np.testing.assert_allclose(Q, tr.q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(P, tr.p, rtol=0, atol=1e-10)
    # u = -K x amplifies the states' round-off by |K| (up to 441 here)
    np.testing.assert_allclose(U, run.u, rtol=0, atol=1e-10 * np.abs(limited.gains).max())


def test_time_varying_policy_past_its_last_stage_uses_the_last(cartpole_lqr):
    integ, _ = cartpole_lqr
    N = 60
    t = (np.arange(N)[:, None] + integ.nodes[None, :]) * integ.dt
    U = (2.0 * np.sin(3 * t) + 0.5 * t)[..., None]                 # varies within each step too
    traj = integ.rollout(np.array([0.0, 0.4]), N, u=U)
    policy = control.tvlqr(integ, traj, U, u_limits=(-1.5, 1.5))
    steps = N + 40
    run = control.simulate(integ, policy, [0.05, 0.45], steps)
    tr = run.trajectory
    expected = np.array([policy.control(k, tr.q[k], tr.p[k]) for k in range(steps)])
    np.testing.assert_allclose(run.u, expected, rtol=1e-12, atol=1e-12)
    assert np.abs(run.u).max() <= 1.5 and np.sum(np.abs(run.u) == 1.5) > 0
    assert np.sum(np.abs(np.diff(run.u[:N, :, 0], axis=1)) > 1e-3) > 0   # per-point feed-forward applied
    # past the last stage: the last stage's reference and gain
    last = dataclasses.replace(policy, x_ref=policy.x_ref[-1:], u_ref=policy.u_ref[-1:], gains=policy.gains[-1:])
    for k in range(N, steps):
        np.testing.assert_array_equal(policy.control(k, tr.q[k], tr.p[k]), last.control(0, tr.q[k], tr.p[k]))


def test_with_limits_refuses_crossed_limits(cartpole_lqr):
    _, policy = cartpole_lqr
    with pytest.raises(ValueError, match="lower <= upper"):
        policy.with_limits(1.0, -1.0)
    with pytest.raises(ValueError, match="lower <= upper"):
        policy.with_limits(np.nan, 1.0)


# --- 7. pushes -------------------------------------------------------------------------------------

L_LINK = 0.5


@pytest.fixture(scope="module")
def pendulum():
    model = models.pendulum(2)
    model.add_actuator(0)
    model.add_actuator(1)
    # the geometry the point Jacobian below assumes: COMs mid-link below joints at the origin and -L z
    np.testing.assert_allclose(model.body_poses(np.zeros(2))[:, :3, 3], [[0, 0, -L_LINK / 2], [0, 0, -1.5 * L_LINK]],
                               atol=1e-15)
    return hovi.Integrator(model, s=2, dt=0.01)


def point_jacobian(model, body, point, q, eps=1e-6):
    """d x / d q of the world position x(q) = R(q) (point - com) + o(q) of `point` (in the body's
    joint frame; the body frame sits at the COM, com = (0, 0, -L/2) for the pendulum's links, with
    the joint frame's axes), by central differences of Model.body_poses."""
    com = np.array([0.0, 0.0, -L_LINK / 2])

    def x(q):
        g = model.body_poses(q)[body]
        return g[:3, :3] @ (np.asarray(point) - com) + g[:3, 3]

    J = np.zeros((3, model.n))
    for j in range(model.n):
        e = np.zeros(model.n)
        e[j] = eps
        J[:, j] = (x(q + e) - x(q - e)) / (2 * eps)
    return J


@pytest.mark.parametrize("body, point, time", [(1, (0.02, 0.01, -0.4), 0.123), (0, (0.0, 0.02, -0.3), 0.3),
                                               ("link2", (0.05, -0.03, 0.1), 0.1)])
def test_a_push_adds_its_generalised_impulse_at_its_knot(pendulum, body, point, time):
    integ, model = pendulum, pendulum.model
    policy = zero_policy(integ)
    q0, steps = np.array([0.3, -0.2]), 40
    impulse = np.array([0.5, -0.3, 0.2])
    run = control.simulate(integ, policy, q0, steps, pushes=[control.Push(time, body, impulse, point)])
    tr = run.trajectory
    k = int(np.ceil(time / integ.dt - 1e-9))                     # the first knot at or after `time`
    assert k == {0.123: 13, 0.3: 30, 0.1: 10}[time]
    free = integ.rollout(q0, k)                                  # no push before knot k
    np.testing.assert_allclose(tr.q[:k + 1], free.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(tr.p[:k], free.p[:k], rtol=0, atol=1e-12)
    b = model.body_index(body) if isinstance(body, str) else body
    dp = point_jacobian(model, b, point, free.q[k]).T @ impulse
    assert np.abs(dp).max() > 0.05
    np.testing.assert_allclose(tr.p[k] - free.p[k], dp, rtol=0, atol=1e-9)      # recorded after the push
    # then the free motion from the pushed state
    after = integ.rollout(free.q[k], steps - k, p0=free.p[k] + dp)
    np.testing.assert_allclose(tr.q[k:], after.q, rtol=0, atol=1e-9)
    assert np.all(run.u == 0)


def test_a_push_with_a_duration_is_split_over_its_knots(pendulum):
    integ, model = pendulum, pendulum.model
    q0, steps = np.array([0.3, -0.2]), 30
    impulse, point = np.array([0.0, 0.6, -0.4]), (0.01, 0.0, -0.35)
    push = control.Push(0.05, "link2", impulse, point, duration=0.04)
    assert [(k, b) for k, b, *_ in push.knots(model, integ.dt)] == [(5, 1), (6, 1), (7, 1), (8, 1)]
    run = control.simulate(integ, zero_policy(integ), q0, steps, pushes=[push])
    # the same by hand: a quarter of the impulse at knots 5..8, J at each knot's q
    q, p = q0.copy(), np.zeros(2)
    Q, P = [q], [p]
    for k in range(steps):
        if 5 <= k <= 8:
            p = p + point_jacobian(model, 1, point, q).T @ (impulse / 4)
            P[-1] = p
        q, p, _ = integ.step(q, p, np.zeros(2))
        Q.append(q), P.append(p)
    np.testing.assert_allclose(run.trajectory.q, np.array(Q), rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.trajectory.p, np.array(P), rtol=0, atol=1e-9)
    # the whole impulse at once at knot 5 is another run
    once = control.simulate(integ, zero_policy(integ), q0, steps, pushes=[control.Push(0.05, "link2", impulse, point)])
    assert np.abs(once.trajectory.q[-1] - run.trajectory.q[-1]).max() > 1e-4


def test_bad_pushes_are_refused_naming_the_body(pendulum):
    integ = pendulum
    policy = zero_policy(integ)
    with pytest.raises(ValueError, match="'foot'"):
        control.simulate(integ, policy, np.zeros(2), 5, pushes=[control.Push(0.0, "foot", [1, 0, 0])])
    with pytest.raises(ValueError, match="body index"):
        control.simulate(integ, policy, np.zeros(2), 5, pushes=[control.Push(0.0, 2, [1, 0, 0])])
    with pytest.raises(ValueError, match="Push impulse"):
        control.simulate(integ, policy, np.zeros(2), 5, pushes=[control.Push(0.0, 0, [1, 0])])
    with pytest.raises(ValueError, match="Push time"):
        control.simulate(integ, policy, np.zeros(2), 5, pushes=[control.Push(-0.1, 0, [1, 0, 0])])


# --- 8. model mismatch and batches ---------------------------------------------------------------------

@pytest.mark.parametrize("body, factor, built", [("pole", 1.2, dict(pole_mass=0.36)),
                                                 ("cart", 1.2, dict(cart_mass=1.2)),
                                                 (1, 0.5, dict(pole_mass=0.15))])
def test_scale_mass_is_a_model_built_with_that_mass(body, factor, built):
    original = models.cartpole()
    plant = original.copy()
    plant.scale_mass(body, factor)
    reference = models.cartpole(**built)      # the rod's and the cart's inertias are proportional to their masses
    rng = np.random.default_rng(5)
    for q in rng.uniform(-3, 3, size=(5, 2)):
        np.testing.assert_allclose(plant.mass_matrix(q), reference.mass_matrix(q), rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(plant.inverse_dynamics(q, np.zeros(2), np.zeros(2)),
                                   reference.inverse_dynamics(q, np.zeros(2), np.zeros(2)), rtol=1e-12, atol=1e-15)
        assert np.abs(plant.mass_matrix(q) - original.mass_matrix(q)).max() > 1e-3    # the copy alone changed
    np.testing.assert_allclose(original.masses, [1.0, 0.3])
    np.testing.assert_allclose(plant.masses, reference.masses, rtol=1e-15)


def test_scale_mass_refuses_bad_input():
    model = models.cartpole()
    with pytest.raises(hovi.ModelError, match="no body named 'nope'"):
        model.scale_mass("nope", 1.2)
    for factor in (0.0, -1.0, np.inf, np.nan, 1e300, 1e-300):  # 1e300 was taken, then blamed on a joint
        with pytest.raises(hovi.ModelError, match=r"scale_mass: body 'pole': factor must lie in \[1e-12, 1e12\], got"):
            model.scale_mass("pole", factor)
    for factor in ("1.2", None, True, [1.2]):  # not pybind's list of overloads
        with pytest.raises(ValueError, match="scale_mass: factor must be a real number, got"):
            model.scale_mass("pole", factor)
    integ = hovi.Integrator(model, s=2)
    model.scale_mass("pole", 1.1)
    with pytest.raises(hovi.ModelError, match="scale_mass"):                      # the Integrator has the old copy
        integ.step(np.zeros(2), np.zeros(2), np.zeros(1))


def mismatched_plants(factors):
    plants = []
    for f in factors:
        model = models.cartpole()
        model.scale_mass("pole", f)
        plants.append(hovi.Integrator(model, s=2, dt=0.01))
    return plants


def same_run(a, b):
    return (np.array_equal(a.trajectory.q, b.trajectory.q) and np.array_equal(a.trajectory.p, b.trajectory.p)
            and np.array_equal(a.u, b.u))


def test_batch_on_mismatched_plants_is_each_run_alone_on_any_threads(cartpole_lqr):
    _, policy = cartpole_lqr
    factors = [1.0, 1.2, 0.8, 1.5]
    plants = mismatched_plants(factors)
    q0 = UPRIGHT + np.array([[0.0, 0.2], [0.1, -0.15], [0.0, 0.1], [-0.2, 0.05]])
    pushes = [[control.Push(0.5, "pole", [0.3, 0.0, 0.0], (0.0, 0.0, -0.25))], [],
              [control.Push(0.2, "cart", [1.0, 0.0, 0.0], duration=0.1)],
              [control.Push(0.3, 1, [-0.2, 0.0, 0.1]), control.Push(0.6, 0, [0.5, 0.0, 0.0])]]
    qdot0 = np.array([[0.0, 0.0], [0.1, 0.2], [-0.1, 0.0], [0.0, -0.3]])
    steps = 300
    alone = [control.simulate(plants[b], policy, q0[b], steps, qdot0=qdot0[b], pushes=pushes[b]) for b in range(4)]
    one = control.simulate_batch(plants, policy, q0, steps, qdot0=qdot0, pushes=pushes, threads=1)
    two = control.simulate_batch(plants, policy, q0, steps, qdot0=qdot0, pushes=pushes, threads=2)
    assert len(one) == len(two) == 4
    for b in range(4):
        assert same_run(one[b], alone[b]), b
        assert same_run(two[b], alone[b]), b
        assert alone[b].converged and np.abs(alone[b].trajectory.q[-1] - UPRIGHT).max() < 0.1    # each recovers
    # the plants do differ: the nominal and the heavy pole from the same state under the same policy
    nominal, heavy = control.simulate_batch([plants[0], plants[1]], policy, q0[0], steps, qdot0=np.zeros(2))
    assert np.abs(nominal.trajectory.q - heavy.trajectory.q).max() > 1e-3
    # and the heavy run is a Python loop of the heavy plant's steps under Policy.control
    Q, P, U = python_loop(plants[1], policy, q0[0], np.zeros(2), steps)
    np.testing.assert_array_equal(heavy.trajectory.p[0], np.zeros(2))             # at rest by default
    np.testing.assert_allclose(heavy.trajectory.q, Q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(heavy.u, U, rtol=0, atol=1e-10 * np.abs(policy.gains).max())
    # one plant and one push list for every run
    p0 = np.array([plants[2].momentum(q0[b], qdot0[b]) for b in range(4)])
    shared = control.simulate_batch(plants[2], policy, q0, steps, p0=p0, pushes=[pushes[3]], threads=2)
    for b in range(4):
        assert same_run(shared[b], control.simulate(plants[2], policy, q0[b], steps, qdot0=qdot0[b], pushes=pushes[3]))


def test_batch_with_per_run_states_starts_at_rest_by_default(cartpole_lqr):
    integ, policy = cartpole_lqr
    q0 = UPRIGHT + np.array([[0.0, 0.2], [0.1, -0.15], [0.0, 0.1]])
    runs = control.simulate_batch(integ, policy, q0, 20)
    for b in range(3):
        assert same_run(runs[b], control.simulate(integ, policy, q0[b], 20))


def test_batch_refuses_plants_that_do_not_fit(cartpole_lqr):
    integ, policy = cartpole_lqr
    with pytest.raises(ValueError, match="one plant or 3"):
        control.simulate_batch(mismatched_plants([1.0, 1.1]), policy, np.tile(UPRIGHT, (3, 1)), 5)
    with pytest.raises(ValueError, match="does not fit the policy"):
        control.simulate(hovi.Integrator(models.cartpole(), s=1, dt=0.01), policy, UPRIGHT, 5)
    with pytest.raises(TypeError, match="hovi.Integrator"):
        control.simulate_batch([integ.model], policy, UPRIGHT, 5)


# --- 10. contacts --------------------------------------------------------------------------------------

def test_standing_littledog_feed_forward_policy_is_the_open_loop_rollout():
    st = standing("littledog")
    integ, steps = st.integrator, 200
    policy = zero_policy(integ, st.u)
    run = control.simulate(integ, policy, st.q0, steps)
    ref = integ.rollout(st.q0, steps, u=st.u)
    assert run.converged and run.trajectory.contact is not None
    np.testing.assert_array_equal(run.trajectory.q, ref.q)
    np.testing.assert_array_equal(run.trajectory.p, ref.p)
    np.testing.assert_array_equal(run.trajectory.contact.impulses, ref.contact.impulses)
    np.testing.assert_array_equal(run.u, np.broadcast_to(st.u, run.u.shape))
    weight = st.model.total_mass * 9.81 * integ.dt
    np.testing.assert_allclose(run.trajectory.contact.normal[-1].sum(), weight, rtol=1e-6)


def block_on_ground(mass=2.0):
    """A point mass in the x-z plane on flat ground, pushed along x (control 0)."""
    model = hovi.Model()
    model.add_body("slider", None, "prismatic", axis=(1, 0, 0))
    model.add_body("mass", "slider", "prismatic", axis=(0, 0, 1), mass=mass, inertia=np.eye(3) * 1e-3)
    model.add_actuator(0)
    contacts = Contacts(model, [("mass", (0.0, 0.0, 0.0))], Terrain(), mu=0.5, plane="xz")
    return hovi.Integrator(model, s=1, dt=0.01, contacts=contacts)


def pd_pull(integ, m=2.0, mu=0.5, g=9.81):
    """A PD pull of the block to x = 0.3 (gains on x and on the momentum), saturated at 1.1 mu m g
    (it slides while saturated)."""
    limit = 1.1 * mu * m * g
    return dataclasses.replace(zero_policy(integ), x_ref=np.array([[0.3, 0.0, 0.0, 0.0]]),
                               gains=np.array([[[40.0, 0.0, 8.0, 0.0]]])).with_limits(-limit, limit)


def test_feedback_on_a_block_with_friction_is_a_python_loop_of_steps_and_its_rollout():
    """The hook sees (q^k, p^k) before the knot's contact impulse (galerkin_integrator.hpp): the state
    the step starts from, the p that Integrator.step returns; a Python loop of steps under
    Policy.control is the same run."""
    integ = block_on_ground()
    m, mu, g = 2.0, 0.5, 9.81
    policy = pd_pull(integ)
    steps = 300
    run = control.simulate(integ, policy, np.zeros(2), steps)
    tr = run.trajectory
    assert run.converged and tr.contact is not None
    Q, P, U = python_loop(integ, policy, np.zeros(2), np.zeros(2), steps)
    np.testing.assert_allclose(tr.q, Q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(run.u, U, rtol=0, atol=1e-10 * np.abs(policy.gains).max())
    assert np.sum(run.u[:, 0, 0] == 1.1 * mu * m * g) >= 3                # saturated at the start
    ref = integ.rollout(np.zeros(2), steps, u=run.u)
    np.testing.assert_array_equal(ref.q, tr.q)
    np.testing.assert_array_equal(ref.p, tr.p)
    np.testing.assert_array_equal(ref.contact.impulses, tr.contact.impulses)
    assert np.abs(tr.q[:, 1]).max() <= 1e-12                              # it stays on the ground
    # it slides towards x = 0.3 and sticks once the pull no longer beats static friction
    assert 0.0 < tr.q[-1, 0] < 0.3
    assert abs(tr.q[-1, 0] - tr.q[-50, 0]) <= 1e-12                       # at rest, stuck
    assert np.abs(run.u[-50:]).max() <= mu * m * g
    assert np.abs(tr.contact.friction[-50:, 0, 0] + run.u[-50:, 0, 0] * integ.dt).max() <= 1e-12   # friction = -u


def test_a_policy_on_a_body_at_rest_on_the_ground_sees_the_step_momentum():
    """With contacts the policy's state is each step's own momentum, before its knot's impulse (the
    state of the contact Jacobians; the impulse is the step's unknown): at rest on the ground that is
    p_z = -m g dt / 2 from the second step on, recorded as ``contact.step_momenta``."""
    integ = block_on_ground()
    policy = dataclasses.replace(zero_policy(integ, [3.0]), gains=np.array([[[0.0, 0.0, 0.0, 10.0]]]))
    run = control.simulate(integ, policy, np.zeros(2), 5)
    assert np.abs(run.trajectory.q).max() == 0.0                          # 3 N < mu m g: at rest throughout
    pz = run.trajectory.contact.step_momenta[:5, 1]
    m, g, dt = integ.model.masses.sum(), 9.81, integ.dt
    np.testing.assert_allclose(pz[1:], -m * g * dt / 2, rtol=1e-9)
    np.testing.assert_allclose(run.u[:, :, 0], (3.0 - 10.0 * pz)[:, None].repeat(run.u.shape[1], 1), rtol=1e-12)


def test_policy_control_on_the_recorded_contact_states_is_the_applied_controls():
    integ = block_on_ground()
    policy = pd_pull(integ)
    run = control.simulate(integ, policy, np.zeros(2), 100)
    tr = run.trajectory
    expected = np.array([policy.control(k, tr.q[k], tr.contact.step_momenta[k]) for k in range(100)])
    np.testing.assert_allclose(run.u, expected, rtol=1e-12, atol=1e-12)


def test_tvlqr_on_a_sliding_block_reproduces_it_and_tracks_it():
    """TVLQR along a contact trajectory (the contact state held in the Jacobians, the references the
    steps' own momenta ``contact.step_momenta``): from its own start the closed loop is the trajectory."""
    integ = block_on_ground()
    N = 100
    U = (12.0 + 2.0 * np.sin(np.arange(N) * integ.dt * 5))[:, None]      # beyond friction: it slides
    traj = integ.rollout(np.zeros(2), N, u=U)
    assert np.all(np.diff(traj.q[1:, 0]) > 0)
    policy = control.tvlqr(integ, traj, U, q_weight=100.0)
    run = control.simulate(integ, policy, traj.q[0], N, p0=traj.p[0])
    np.testing.assert_allclose(run.trajectory.q, traj.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(run.u[:, 0], U, rtol=1e-12)
    q0 = np.array([-0.02, 0.0])
    closed = control.simulate(integ, policy, q0, N).trajectory
    opened = integ.rollout(q0, N, u=U)
    assert abs(closed.q[-1, 0] - traj.q[-1, 0]) < 0.1 * abs(opened.q[-1, 0] - traj.q[-1, 0])


def test_an_angular_push_adds_the_bodys_angular_jacobian_times_the_impulse():
    """Push(angular=tau): p += J_w(q)^T tau, J_w from central differences of the body's world
    orientation (dR R^T = [J_w dq]x), on a 3D three-link pendulum (axes x, y, x)."""
    m = models.pendulum(3)
    for j in range(3):
        m.add_actuator(j)
    integ = hovi.Integrator(m, s=1, dt=0.01)
    policy = control.Policy(x_ref=np.zeros((1, 6)), u_ref=np.zeros((1, 2, 3)), gains=np.zeros((1, 3, 6)),
                            lower=np.full(3, -np.inf), upper=np.full(3, np.inf), cost_to_go=np.zeros((1, 6, 6)),
                            dt=0.01, s=1)
    q0, tau, imp = np.array([0.3, -0.2, 0.5]), np.array([0.1, -0.3, 0.2]), np.array([0.05, 0.0, -0.1])
    run = control.simulate(integ, policy, q0, 1, pushes=[control.Push(0.0, 2, imp, point=[0, 0, -0.1], angular=tau)])

    def R(q):
        return m.body_poses(q)[2][:3, :3]

    h, Jw = 1e-6, np.zeros((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        W = (R(q0 + e) - R(q0 - e)) / (2 * h) @ R(q0).T
        Jw[:, j] = [W[2, 1], W[0, 2], W[1, 0]]
    # the linear part alone, from the same run without the angular impulse
    lin = control.simulate(integ, policy, q0, 1, pushes=[control.Push(0.0, 2, imp, point=[0, 0, -0.1])])
    np.testing.assert_allclose(run.trajectory.p[0] - lin.trajectory.p[0], Jw.T @ tau, rtol=0, atol=1e-9)


def test_a_closed_loop_trajectory_carries_the_controls_it_applied():
    """ClosedLoop.trajectory.controls are the saturated controls the policy applied (ClosedLoop.u), so a
    rollout of them from the same state is the closed loop's trajectory, bit for bit."""
    model = models.cartpole()
    integ = hovi.Integrator(model, s=2, dt=0.01)
    policy = control.lqr(integ, [0.0, np.pi], u_limits=(-2.0, 2.0))
    run = control.simulate(integ, policy, [0.1, np.pi - 0.3], 80)
    np.testing.assert_array_equal(run.trajectory.controls, run.u)
    assert np.abs(run.u).max() == 2.0                                     # saturated at some steps
    np.testing.assert_array_equal(integ.rollout(run.trajectory.q[0], 80, u=run.trajectory.controls).q,
                                  run.trajectory.q)
