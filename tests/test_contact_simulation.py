"""The contact simulator (hovi.Integrator(..., contacts=...), cpp/include/hovi/integrators/contact_stages, contact_solver) against
closed forms at s = 1: a dropped block falls as z0 - g t^2/2 and rests with normal force m g; a
pushed block sticks or accelerates at (F - mu m g)/m; a sliding block stops after v0^2/(2 mu g);
a block on an incline sticks for tan(theta) < mu and slides at g (sin theta - mu cos theta)
above; a box dropped on a corner comes to rest flat; complementarity, the friction cone and
non-penetration at every step; the robots standing; bad input."""
import pickle

import numpy as np
import pytest

import hovi
from hovi.contact import Box, Contacts, Gap, Terrain

from conftest import bench_module, planar_point_mass

G = 9.81
TOL = 1e-9  # the bound on penetration and complementarity (the solver's own: 1e-10)


def block(mass=2.0, actuated=False):
    """A block (a point mass of 2 kg by default) moving in the x-z plane."""
    return planar_point_mass(mass, actuated)


def integrator(model, mu=0.5, dt=0.01, terrain=None, points=(("mass", (0.0, 0.0, 0.0)),), plane="xz"):
    contacts = Contacts(model, list(points), terrain or Terrain(), mu=mu, plane=plane)
    return hovi.Integrator(model, s=1, dt=dt, contacts=contacts)


def check_complementarity(traj, mu):
    """Every step: lambda, beta, gamma >= 0; gap >= -TOL; lambda gap = 0; the cone mu lambda >= sum beta
    with gamma (mu lambda - sum beta) = 0; beta_i (gamma + D_i . displacement) = 0 (as far as the gaps
    and impulses recorded show it: the displacement is checked through the friction direction)."""
    c = traj.contact
    z = c.impulses
    d = len(c.directions)
    lam, beta, gamma = z[..., 0], z[..., 1:1 + d], z[..., -1]
    assert z.min() >= 0
    assert c.gaps.min() >= -TOL
    assert np.abs(lam * c.gaps).max() <= TOL * max(1.0, lam.max())
    cone = mu * lam - beta.sum(-1)
    assert cone.min() >= -TOL
    assert np.abs(gamma * cone).max() <= TOL


def test_dropped_block_falls_as_the_closed_form_and_rests_with_its_weight():
    m, z0, dt = 2.0, 0.1, 0.01
    integ = integrator(block(m), dt=dt)
    traj = integ.rollout(np.array([0.0, z0]), 100)
    t = traj.t
    landing = np.sqrt(2 * z0 / G)
    free = t < landing - dt
    np.testing.assert_allclose(traj.q[free, 1], z0 - G * t[free] ** 2 / 2, rtol=0, atol=1e-14)  # exact at s = 1
    rest = t[:-1] > landing + 2 * dt
    np.testing.assert_allclose(traj.contact.normal[rest[:-0 or None][:len(traj.contact.normal)], 0] / (m * G * dt), 1.0,
                               rtol=1e-9)
    assert np.all(traj.q[1:][t[1:] > landing + dt, 1] == 0.0)                 # inelastic: no rebound, no penetration
    np.testing.assert_allclose(traj.qdot[rest.nonzero()[0][:-1]], 0.0, atol=1e-12)  # at rest: zero velocity
    check_complementarity(traj, 0.5)


@pytest.mark.parametrize("ratio", [0.5, 0.99])
def test_block_pushed_below_the_friction_limit_does_not_move(ratio):
    m, mu, dt = 2.0, 0.5, 0.01
    F = ratio * mu * m * G
    traj = integrator(block(m, actuated=True), mu, dt).rollout(np.array([0.0, 0.0]), 50, u=np.array([F]))
    assert np.abs(traj.q).max() <= 1e-15                                    # round-off: it sticks
    np.testing.assert_allclose(traj.contact.friction[1:, 0, 0] / (F * dt), -1.0, rtol=1e-9)  # friction = -F
    check_complementarity(traj, mu)


def test_block_pushed_beyond_the_friction_limit_accelerates_at_the_closed_form():
    m, mu, dt = 2.0, 0.5, 0.01
    F = 1.5 * mu * m * G
    traj = integrator(block(m, actuated=True), mu, dt).rollout(np.array([0.0, 0.0]), 50, u=np.array([F]))
    x = traj.q[:, 0]
    accel = np.diff(x, 2)[5:] / dt ** 2                                      # constant force: exact second differences
    np.testing.assert_allclose(accel, (F - mu * m * G) / m, rtol=1e-9)
    np.testing.assert_allclose(traj.contact.friction[5:, 0, 0] / (mu * m * G * dt), -1.0, rtol=1e-9)
    check_complementarity(traj, mu)


def stop_distance(dt, v0=1.0, mu=0.5):
    integ = integrator(block(), mu, dt)
    traj = integ.rollout(np.array([0.0, 0.0]), int(round(0.4 / dt)), qdot0=np.array([v0, 0.0]))
    check_complementarity(traj, mu)
    dx = np.diff(traj.q[:, 0])
    assert dx.min() >= -1e-13 and abs(dx[-1]) <= 1e-13                      # stopped (to round-off), never backwards
    return traj.q[-1, 0]


def test_sliding_block_stops_at_the_closed_form_distance():
    v0, mu = 1.0, 0.5
    exact = v0 ** 2 / (2 * mu * G)
    errors = {dt: abs(stop_distance(dt, v0, mu) - exact) / exact for dt in (0.01, 0.005, 0.0025)}
    assert errors[0.01] <= 1e-3                                              # the goal at dt = 0.01
    assert max(errors.values()) <= 1e-3


@pytest.mark.parametrize("theta, mu, sticks", [(0.3, 0.5, True), (0.3, 0.2, False), (0.5, 0.5, False)])
def test_block_on_an_incline_sticks_below_the_friction_angle_and_slides_above(theta, mu, sticks):
    """The incline as gravity tilted by theta in the x-z plane over flat ground."""
    m, dt = 2.0, 0.01
    model = block(m)
    model.gravity = (G * np.sin(theta), 0.0, -G * np.cos(theta))
    traj = integrator(model, mu, dt).rollout(np.array([0.0, 0.0]), 60)
    check_complementarity(traj, mu)
    assert np.tan(theta) < mu if sticks else np.tan(theta) > mu
    x = traj.q[:, 0]
    if sticks:
        assert np.abs(x).max() <= 1e-15
    else:
        np.testing.assert_allclose(np.diff(x, 2)[5:] / dt ** 2, G * (np.sin(theta) - mu * np.cos(theta)), rtol=1e-9)
    assert np.abs(traj.q[:, 1]).max() <= 1e-15


def box_model(m=1.0, a=0.2, b=0.15, c=0.1):
    """A box a x b x c (m) on a floating base (x, y, z, yaw, pitch, roll) and its eight corners."""
    model = hovi.Model()
    model.add_body("x", None, "prismatic", axis=(1, 0, 0))
    model.add_body("y", "x", "prismatic", axis=(0, 1, 0))
    model.add_body("z", "y", "prismatic", axis=(0, 0, 1))
    model.add_body("yaw", "z", "revolute", axis=(0, 0, 1))
    model.add_body("pitch", "yaw", "revolute", axis=(0, 1, 0))
    model.add_body("box", "pitch", "revolute", axis=(1, 0, 0), mass=m,
                   inertia=m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b]))
    corners = [(sx * a / 2, sy * b / 2, sz * c / 2) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    return model, [("box", p) for p in corners]


@pytest.mark.parametrize("dt", [0.005, 0.0025])
def test_box_dropped_on_a_corner_tumbles_and_rests_flat(dt):
    model, corners = box_model()
    integ = hovi.Integrator(model, s=1, dt=dt, contacts=Contacts(model, corners, Terrain(), mu=0.6))
    traj = integ.rollout(np.array([0.0, 0.0, 0.3, 0.2, 0.5, 0.4]), int(round(3.0 / dt)),
                         qdot0=np.array([0.3, 0.0, 0.0, 0.0, 1.0, 0.0]))
    check_complementarity(traj, 0.6)
    q = traj.q[-1]
    assert abs(q[2] - 0.05) < 1e-12 and abs(q[4]) < 1e-9 and abs(q[5]) < 1e-9  # flat on its largest face
    # at rest: its four bottom corners are redundant contacts, solved through the LCP regularised by
    # 1e-9 of its diagonal (lcp.cpp), whose complements are off by ~1e-12 m a step: a creep of a few 1e-9
    np.testing.assert_allclose(traj.qdot[-2], 0.0, atol=1e-8)
    active = traj.contact.active
    first = int(np.argmax(active.any(1)))
    assert active[first].sum() == 1                                          # it lands on one corner
    E = traj.energy
    assert np.ptp(E[:first]) <= 1e-10 * abs(E[0])                           # flight: the VI's energy, constant
    # after the first impact the energy only falls, up to the discrete energy's own O(dt^2) wobble while
    # the box pivots on a corner (it halves and quarters with dt: see the test's two dt)
    rises = np.diff(E[first + 1:-1])
    assert rises.max() <= 0.2 * dt ** 2
    assert E[-2] < 0.2 * E[0]


def test_gaps_and_boxes_of_the_terrain_are_felt():
    """A block sliding off a box top falls into a gap and lands on its floor."""
    m, dt = 1.0, 0.005
    terrain = Terrain(ground=0.0, gaps=[Gap(0.2, 2.0, depth=0.3)], boxes=[Box(-1.0, 0.05, top=0.1)])
    traj = integrator(block(m), 0.0, dt, terrain).rollout(np.array([0.0, 0.1]), 300, qdot0=np.array([1.0, 0.0]))
    check_complementarity(traj, 0.0)
    x, z = traj.q[:, 0], traj.q[:, 1]
    np.testing.assert_allclose(z[x < 0.05], 0.1, rtol=0, atol=1e-15)        # on the box
    assert abs(z[-1] + 0.3) < 1e-12 and x[-1] > 0.2                          # on the gap's floor


def test_step_agrees_with_rollout_and_reports_impulses():
    integ = integrator(block(), dt=0.01)
    traj = integ.rollout(np.array([0.0, 0.002]), 5)
    q, p = traj.q[0], traj.p[0]
    for k in range(5):
        q, p, info = integ.step(q, p)
        np.testing.assert_allclose(q, traj.q[k + 1], rtol=0, atol=1e-15)  # the same step from another first guess
        assert info.impulses.shape == (1, 4) and info.gaps.shape == (1,)
    assert info.impulses[0, 0] > 0


def test_pickled_integrator_with_contacts_computes_the_same():
    integ = integrator(block(), dt=0.01)
    other = pickle.loads(pickle.dumps(integ))
    a = integ.rollout(np.array([0.0, 0.05]), 30, qdot0=np.array([0.5, 0.0]))
    b = other.rollout(np.array([0.0, 0.05]), 30, qdot0=np.array([0.5, 0.0]))
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.contact.impulses, b.contact.impulses)


def test_trajectory_with_contacts_saves_and_loads(tmp_path):
    integ = integrator(block(), dt=0.01)
    traj = integ.rollout(np.array([0.0, 0.05]), 20)
    traj.save(tmp_path / "t.npz")
    back = hovi.load_trajectory(tmp_path / "t.npz", integ)
    np.testing.assert_array_equal(back.contact.impulses, traj.contact.impulses)
    np.testing.assert_array_equal(back.contact.gaps, traj.contact.gaps)
    arrays = dict(np.load(tmp_path / "t.npz"))
    arrays["contact_impulses"][7, 0, 0] = -0.5  # a negative normal impulse: a pull, never a contact's
    np.savez(tmp_path / "bad.npz", **arrays)
    with pytest.raises(ValueError, match=r"contact_impulses must be >= 0 .* the normal impulse of contact 0 at "
                                         r"step 7 = -0.5"):
        hovi.load_trajectory(tmp_path / "bad.npz", integ)


def test_progress_chunks_give_the_same_rollout():
    integ = integrator(block(), dt=0.01)
    a = integ.rollout(np.array([0.0, 0.05]), 40, qdot0=np.array([0.5, 0.0]))
    b = integ.rollout(np.array([0.0, 0.05]), 40, qdot0=np.array([0.5, 0.0]), progress=True, chunk=7)
    # each chunk starts its Newton solves from other guesses: the same steps to round-off (a stuck block
    # creeps by round-off, 5e-15 N s a step, differently in each)
    np.testing.assert_allclose(b.q, a.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(b.p, a.p, rtol=0, atol=1e-12)


def test_bad_contacts_are_refused_with_the_argument_named():
    model = block()
    other = hovi.Model()
    other.add_body("a", None, "revolute", axis=(0, 1, 0), mass=1.0, inertia=np.eye(3))
    with pytest.raises(ValueError, match="contacts were built for another model"):
        hovi.Integrator(model, s=1, contacts=Contacts(other, [("a", (0, 0, 0))], Terrain(), mu=0.5))
    contacts = Contacts(model, [("mass", (0, 0, 0))], Terrain(), mu=0.5, plane="xz")
    with pytest.raises(ValueError, match="not Contacts.with_inputs"):
        hovi.Integrator(contacts.with_inputs, s=1, contacts=contacts)
    with pytest.raises(hovi.ModelError, match="no mass"):
        hovi.Integrator(model, s=1, contacts=Contacts(model, [("slider", (0, 0, 0))], Terrain(), mu=0.5, plane="xz"))
    with pytest.raises(ValueError, match="need locate_impacts"):
        hovi.Integrator(model, s=2, contacts=contacts, locate_impacts=False)
    with pytest.raises(ValueError, match="locate_impacts must be"):
        hovi.Integrator(model, s=1, contacts=contacts, locate_impacts="yes")
    with pytest.raises(TypeError, match="contacts must be a hovi.contact.Contacts"):
        hovi.Integrator(model, s=1, contacts=[("mass", (0, 0, 0))])
    for tol in (0.0, -1.0, float("nan"), "1e-9"):
        with pytest.raises(ValueError, match="contact_tol"):
            hovi.Integrator(model, s=1, contacts=contacts, contact_tol=tol)
    with pytest.raises(ValueError, match="mu"):
        Contacts(model, [("mass", (0, 0, 0))], Terrain(), mu=float("nan"))
    with pytest.raises(ValueError, match="ground"):
        Terrain(ground=float("nan"))
    with pytest.raises(ValueError):
        Contacts(model, [("nope", (0, 0, 0))], Terrain(), mu=0.5)


def test_rollout_batch_with_contacts_is_each_rollout():
    integ = integrator(block(actuated=True), dt=0.01)
    q0s = np.array([[0.0, 0.05], [0.0, 0.0], [0.1, 0.2]])
    qdot0s = np.array([[0.5, 0.0], [1.0, 0.0], [0.0, -1.0]])
    u = np.array([[1.0], [0.0], [-2.0]])
    batch = integ.rollout_batch(q0s, 40, qdot0s=qdot0s, u=u, threads=2)
    for b in range(3):
        one = integ.rollout(q0s[b], 40, qdot0=qdot0s[b], u=u[b])
        item = batch.trajectory(b)
        np.testing.assert_array_equal(item.q, one.q)
        np.testing.assert_array_equal(item.p, one.p)
        np.testing.assert_array_equal(item.contact.impulses, one.contact.impulses)
        np.testing.assert_array_equal(item.contact.gaps, one.contact.gaps)


def test_step_batch_with_contacts_is_each_step():
    integ = integrator(block(), dt=0.01)
    qs = np.array([[0.0, 0.001], [0.0, 0.0], [0.0, 0.3]])
    ps = np.array([[0.5, -0.5], [0.2, 0.0], [0.0, 0.0]])
    batch = integ.step_batch(qs, ps, threads=2)
    for b in range(3):
        q, p, info = integ.step(qs[b], ps[b])
        np.testing.assert_array_equal(batch.q_next[b], q)
        np.testing.assert_array_equal(batch.p_next[b], p)
        np.testing.assert_array_equal(batch.info(b).impulses, info.impulses)
    assert batch.impulses[0, 0, 0] > 0 and batch.impulses[2, 0, 0] == 0   # one lands, one flies


@pytest.mark.parametrize("s", [2, 3])
def test_higher_order_with_impact_location_lands_and_rests(s):
    """s > 1 locates the impact on the step's polynomial (the default): the dropped block lands at its
    time, inelastically, and rests with its weight; the contact conditions hold at every step."""
    m, z0, dt = 2.0, 0.1, 0.01
    model = block(m)
    integ = hovi.Integrator(model, s=s, dt=dt, contacts=Contacts(model, [("mass", (0, 0, 0))], Terrain(), mu=0.5,
                                                                  plane="xz"))
    assert integ.locate_impacts is None and integ.s == s
    traj = integ.rollout(np.array([0.0, z0]), 60)
    check_complementarity(traj, 0.5)
    k = int(np.argmax(traj.contact.active[:, 0]))
    theta = traj.contact.impact[k]
    assert 0 < theta < 1                                                       # the landing step was split
    assert abs(traj.t[k] + theta * dt - np.sqrt(2 * z0 / G)) <= 1e-12          # at the closed-form impact time
    assert np.abs(traj.q[k + 1:, 1]).max() <= 1e-15                             # no rebound (round-off)
    np.testing.assert_allclose(traj.contact.normal[k + 2:, 0] / (m * G * dt), 1.0, rtol=1e-9)


def test_impact_location_keeps_the_order_of_the_flight():
    """bench/contact_order.py --quick: a rod tumbling onto frictionless ground; with s = 2 the flight
    and the impact time are of order 4 (the closed form), with s = 1 of order 2; without location
    the impact happens at the next knot (an error that does not shrink with dt at these steps)."""
    contact_order = bench_module("contact_order")
    t = contact_order.exact_impact()
    rows = {(s, loc, dt): contact_order.run(s, dt, loc, t) for s, loc in [(1, False), (1, True), (2, True)]
            for dt in (0.02, 0.01)}
    for (s, loc), order in [((1, True), 2), ((2, True), 4)]:
        for field in ("flight_error", "impact_time_error"):
            ratio = rows[(s, loc, 0.02)][field] / rows[(s, loc, 0.01)][field]
            assert ratio > 0.7 * 2 ** order, (s, field, ratio)
    assert rows[(1, False, 0.01)]["impact_time_error"] > 5 * rows[(1, True, 0.01)]["impact_time_error"]
    assert all(r["px_after_error"] < 1e-11 for r in rows.values())             # frictionless: p_x kept


def test_flat_foot_is_simulated_as_its_sole_corners():
    """A flat foot (hovi.contact.FlatFoot) in the simulator: its four sole corners, here a box's
    bottom face as a sole; the box dropped flat rests on it with its weight."""
    from hovi.contact import FlatFoot, flat_feet_contacts
    model, _ = box_model()
    q0 = np.array([0.0, 0.0, 0.06, 0.0, 0.0, 0.0])
    foot = FlatFoot(model, "box", (0.0, 0.0, -0.05), 0.1, 0.075, mu=0.6, q0=q0)
    contacts = flat_feet_contacts(model, [foot], Terrain())
    assert len(contacts.points) == 4 and contacts.mu == 0.6
    integ = hovi.Integrator(model, s=1, dt=0.005, contacts=contacts)
    traj = integ.rollout(q0, 200)
    check_complementarity(traj, 0.6)
    assert abs(traj.q[-1, 2] - 0.05) < 1e-12
    np.testing.assert_allclose(traj.contact.normal[-1].sum() / (model.total_mass * G * 0.005), 1.0, rtol=1e-9)
    with pytest.raises(TypeError, match="FlatFoot"):
        flat_feet_contacts(model, ["box"], Terrain())


def test_step_takes_a_first_guess_of_the_impulses():
    """Integrator.step(impulses=...): the step's own impulses as the first guess give the same step;
    a guess of another shape, or one for an integrator without contacts, is refused by name."""
    integ = integrator(block())
    q, p = np.array([0.0, 0.0]), np.array([0.2, 0.0])
    q1, p1, info = integ.step(q, p)
    q2, p2, again = integ.step(q, p, impulses=info.impulses)
    np.testing.assert_allclose(q2, q1, rtol=0, atol=1e-13)
    np.testing.assert_allclose(again.impulses, info.impulses, rtol=0, atol=1e-13)
    with pytest.raises(ValueError, match="impulses"):
        integ.step(q, p, impulses=np.zeros(7))
    with pytest.raises(ValueError, match="impulses are for an integrator with contacts"):
        hovi.Integrator(hovi.examples.models.pendulum(1), s=1).step([0.0], [0.0], impulses=np.zeros(4))


# --- starts inside the terrain, energy added by the contact, fixed contacts ------------------------

@pytest.mark.parametrize("s", [1, 2])
def test_a_start_inside_the_terrain_is_refused_naming_the_contact_and_its_depth(s):
    """1 m under the ground a step threw the body out at 100 m/s (energy -9.81 J -> 5,000 J, every step
    'converged'): every entry refuses it; a start within contact_tol is taken."""
    model = block(1.0)
    integ = hovi.Integrator(model, s=s, dt=0.01, contacts=Contacts(model, [("mass", (0, 0, 0), 0.0, "foot")],
                                                                    Terrain(), mu=0.5, plane="xz"))
    deep = np.array([0.0, -1.0])
    message = r"contact 0 \('foot', body 'mass'\) starts 1 m inside the terrain, deeper than contact_tol"
    with pytest.raises(ValueError, match="q0: " + message):
        integ.rollout(deep, 5)
    with pytest.raises(ValueError, match="q: " + message):
        integ.step(deep, np.zeros(2))
    with pytest.raises(ValueError, match=r"state 1 of the batch: q0s\[1\]: " + message):
        integ.rollout_batch(np.array([[0.0, 0.5], deep]), 5)
    with pytest.raises(ValueError, match=r"qs\[0\]: " + message):
        integ.step_batch(deep[None])
    traj = integ.rollout(np.array([0.0, -1e-11]), 5)  # within contact_tol (1e-10)
    assert traj.converged and traj.energy[:-1].max() <= traj.energy[0] + 1e-9  # (the last p is before its impulse)


def test_fddp_and_closed_loops_refuse_a_start_inside_the_terrain():
    from hovi import control, trajopt
    model = block(actuated=True)
    contacts = Contacts(model, [("mass", (0.0, 0.0, 0.0))], Terrain(), mu=0.5, plane="xz")
    pr = trajopt.Problem(model, 10, 0.2, controls="held", u_bounds=(-40.0, 40.0))
    pr.initial_state([0.0, -1.0])
    pr.add_cost(trajopt.ControlEffort(0.01))
    with pytest.raises(ValueError, match=r"the problem's q0: contact 0 \(body 'mass'\) starts 1 m inside"):
        trajopt.FDDP(contacts=contacts).solve(pr, trajopt.VI(1))
    plant = hovi.Integrator(model, s=1, dt=0.02, contacts=contacts)
    policy = control.Policy.open_loop(np.zeros((1, 1)), dt=0.02, s=1, n=2)
    with pytest.raises(ValueError, match=r"q0: contact 0 \(body 'mass'\) starts 1 m inside"):
        control.simulate(plant, policy, [0.0, -1.0], 5)


def test_energy_added_by_the_contact_is_flagged():
    """A block sliding at 4 m/s onto a 2 cm step of the terrain is carried onto it by its normal
    impulse, launched upwards at 2 m/s (to 0.21 m): the step gains that launch's kinetic energy and the
    potential energy of the 2 cm lift, and is flagged (a warning, Trajectory.contact.added_energy); a
    block dropped on flat ground, whose contact only takes energy away, is not."""
    model = block(1.0)
    step_up = integrator(model, mu=0.5, terrain=Terrain(boxes=[Box(0.5, 2.0, top=0.02)]))
    with pytest.warns(RuntimeWarning, match=r"the contact added energy at 1 step\(s\), the first at step 13"):
        traj = step_up.rollout(np.zeros(2), 100, qdot0=[4.0, 0.0])
    added = traj.contact.added_energy
    assert np.flatnonzero(added).tolist() == [13]
    v_up = (traj.q[15, 1] - traj.q[14, 1]) / step_up.dt + 9.81 * step_up.dt / 2  # the launch speed after step 13
    assert traj.q[:, 1].max() > 0.2 and v_up > 1.9
    # the energy of the launch, m = 1 kg: its kinetic energy and the 2 cm it was lifted
    assert added[13] == pytest.approx(0.5 * v_up ** 2 + 9.81 * 0.02, rel=1e-2)
    with pytest.warns(RuntimeWarning, match="of run 0"):
        batch = step_up.rollout_batch(np.zeros((2, 2)), 100, qdot0s=[[4.0, 0.0], [0.1, 0.0]])
    np.testing.assert_array_equal(batch.contact.added_energy[0], added)
    assert not batch.contact.added_energy[1].any()
    np.testing.assert_array_equal(batch.trajectory(0).contact.added_energy, added)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        drop = integrator(model).rollout(np.array([0.0, 0.3]), 100)
    assert drop.contact.active.any() and not drop.contact.added_energy.any()


def test_contacts_and_terrains_are_fixed_once_made():
    """Changing a Contacts' terrain or friction after an integrator was made changed a pickled copy but
    not the original: both are now fixed, and a copy computes what the original does."""
    import dataclasses
    model = block(1.0)
    terrain = Terrain(ground=0.0, gaps=[Gap(0.2, 0.4)])
    contacts = Contacts(model, [("mass", (0, 0, 0))], terrain, mu=0.5, plane="xz")
    integ = hovi.Integrator(model, s=1, dt=0.01, contacts=contacts)
    for name, value in (("mu", 0.1), ("terrain", Terrain(ground=1.0)), ("points", ())):
        with pytest.raises(AttributeError, match=f"Contacts are fixed once made.*{name!r}"):
            setattr(contacts, name, value)
    with pytest.raises(dataclasses.FrozenInstanceError):
        terrain.ground = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        terrain.gaps[0].depth = 2.0
    with pytest.raises(ValueError, match="read-only"):
        contacts.points[0].point[2] = 1.0
    assert isinstance(terrain.gaps, tuple)
    copy = pickle.loads(pickle.dumps(integ))
    a, b = integ.rollout([0.0, 0.5], 60, qdot0=[0.2, 0.0]), copy.rollout([0.0, 0.5], 60, qdot0=[0.2, 0.0])
    np.testing.assert_array_equal(a.q, b.q)
    with pytest.raises(AttributeError, match="fixed once made"):
        copy.contacts.mu = 0.1
    assert dataclasses.replace(terrain, ground=0.1).ground == 0.1
