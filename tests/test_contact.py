"""Contact-implicit trajectory optimisation (hovi.contact + hovi.trajopt.solve_contact) against
closed-form answers: a point mass dropped on the ground, resting under a push in static friction,
and sliding to rest; complementarity, penetration and the replay checked at every point."""
import pickle

import numpy as np
import pytest

import hovi
from hovi import trajopt
from hovi.contact import Box, Contacts, Gap, Terrain
from hovi.trajopt import ContactRows
from hovi.trajopt.contact_sides import sides_of_solution, sides_of, canonical, least_slack
from hovi.trajopt.solvers.contact_homotopy import FINISH_BELOW

from conftest import planar_point_mass

G = 9.81
VI1 = trajopt.VI(s=1)  # the contact model that is inelastic and well posed (hovi.contact.contacts)


def contact_problem(model, q0, qdot0, T, N, mu, fixed_u=None):
    contacts = Contacts(model, [("mass", (0.0, 0.0, 0.0))], Terrain(), mu=mu, plane="xz")
    prob = trajopt.Problem(contacts.with_inputs, N=N, T=T)
    prob.initial_state(q0, qdot0)
    if fixed_u is not None:
        prob.u_lower[:len(fixed_u)] = prob.u_upper[:len(fixed_u)] = fixed_u
    prob.add_cost(trajopt.ControlEffort(weight=contacts.effort_weights(0.0)))
    prob.add_contacts(contacts)
    return contacts, prob


def check_contact_result(result):
    assert result.success, result.status
    assert result.constraint_violation < 1e-8
    assert result.contact["penetration"] <= 1e-6
    assert result.contact["complementarity"] <= 1e-6 * (1 + 1e-6)
    assert result.contact["cone"] <= 1e-8
    replay = result.replay()  # the optimised forces as controls, simulated by the integrator
    tr = result.trajectory
    np.testing.assert_allclose(replay.q, tr["q"][::result.transcription.s], atol=1e-7)


def test_dropped_point_mass_falls_freely_then_rests_on_the_ground():
    model = planar_point_mass()
    z0, T, N = 0.3, 0.5, 25
    contacts, prob = contact_problem(model, [0.0, z0], [0.0, 0.0], T, N, mu=0.5)
    result = trajopt.solve_contact(prob, VI1)
    check_contact_result(result)
    t, q = result.trajectory["t"], result.trajectory["q"]
    u = result.trajectory["u"]
    impact = np.sqrt(2 * z0 / G)
    before = t < impact - result.transcription.dt
    np.testing.assert_allclose(q[before, 1], z0 - G * t[before] ** 2 / 2, atol=1e-8)  # the VI is exact here
    np.testing.assert_allclose(u[before, contacts.input_index(0, "normal")], 0, atol=1e-5)
    after = t > impact + 2 * result.transcription.dt
    np.testing.assert_allclose(q[after, 1], 0, atol=1e-6)
    np.testing.assert_allclose(u[after, contacts.input_index(0, "normal")], G, rtol=1e-3)


def test_pushed_mass_stays_at_rest_in_static_friction():
    model = planar_point_mass(actuated=True)
    mu, push = 0.6, 0.5 * 0.6 * G  # half of what friction can hold
    contacts, prob = contact_problem(model, [0.0, 0.0], [0.0, 0.0], 0.3, 15, mu, fixed_u=[push])
    result = trajopt.solve_contact(prob, VI1)
    check_contact_result(result)
    forces = contacts.forces(result.trajectory["u"])[:, 0]
    np.testing.assert_allclose(result.trajectory["q"], 0, atol=1e-6)
    np.testing.assert_allclose(forces[:, 0], -push, rtol=1e-4)   # friction balances the push
    np.testing.assert_allclose(forces[:, 2], G, rtol=1e-4)       # the normal force carries the weight


def test_sliding_block_stops_where_coulomb_friction_says():
    model = planar_point_mass()
    mu, v0 = 0.5, 1.0
    contacts, prob = contact_problem(model, [0.0, 0.0], [v0, 0.0], 0.4, 40, mu)
    result = trajopt.solve_contact(prob, VI1)
    check_contact_result(result)
    t, q = result.trajectory["t"], result.trajectory["q"]
    forces = contacts.forces(result.trajectory["u"])[:, 0]
    stop = v0 / (mu * G)
    distance = v0 ** 2 / (2 * mu * G)
    assert q[-1, 0] == pytest.approx(distance, rel=0.02)
    sliding = (t > 0) & (t < stop - 2 * result.transcription.dt)
    np.testing.assert_allclose(forces[sliding, 0], -mu * forces[sliding, 2], rtol=1e-3)  # the cone saturates
    np.testing.assert_allclose(q[t > stop + 2 * result.transcription.dt, 0], q[-1, 0], atol=1e-6)  # at rest


def test_terrain_heights_and_contact_input_layout():
    terrain = Terrain(ground=0.1, gaps=[Gap(1.0, 1.5, depth=0.5)], boxes=[Box(2.0, 2.4, top=0.26)])
    pts = np.array([[0.0, 0, 0.3], [1.2, 0, 0.3], [2.2, 0, 0.3], [3.0, 0, 0.05]])
    np.testing.assert_allclose(terrain.gap(pts), [0.2, 0.7, 0.04, -0.05])
    assert terrain.segments((0.0, 3.0)) == [(0.0, 1.0, 0.1), (1.0, 1.5, -0.4), (1.5, 2.0, 0.1), (2.0, 2.4, 0.26),
                                            (2.4, 3.0, 0.1)]
    model = planar_point_mass(actuated=True)
    contacts = Contacts(model, [("mass", (0, 0, 0)), (1, (0.1, 0, 0))], terrain, mu=1.0)
    assert contacts.with_inputs.n_controls == 1 + 2 * (2 + 4) and model.n_controls == 1  # the robot is not changed
    assert contacts.input_index(1, "slack") == 12
    with pytest.raises(ValueError, match="mu must be"):
        Contacts(model, [("mass", (0, 0, 0))], terrain, mu=-1)
    with pytest.raises(ValueError, match="x0 < x1"):
        Terrain(gaps=[Gap(1.0, 0.5)])
    with pytest.raises(ValueError, match="depth must be > 0"):
        Terrain(gaps=[Gap(0.5, 1.0, depth=0.0)])
    prob = trajopt.Problem(model, N=4, T=1.0)
    with pytest.raises(ValueError, match="contacts.with_inputs"):
        prob.add_contacts(contacts)


def test_contact_inputs_are_the_forces_of_the_layout_built_by_hand():
    """Contacts.with_inputs (built in C++) is, byte for byte, the model a user builds with add_control and
    add_point_wrench in the documented order: per contact lambda (+z), beta_i (D_i), gamma (no force)."""
    model = hovi.examples.models.pendulum(3)
    model.add_actuator(1)
    points = [(1, (0.1, 0.02, -0.3), 0.05), (2, (0.0, -0.04, 0.2))]
    contacts = Contacts(model, points, Terrain(), mu=0.7)
    by_hand = model.copy()
    for body, point, *_ in points:
        by_hand.add_point_wrench(body, force=(0, 0, 1), point=point, control=by_hand.add_control())
        for direction in contacts.D:
            by_hand.add_point_wrench(body, force=direction, point=point, control=by_hand.add_control())
        by_hand.add_control()
    assert pickle.dumps(contacts.with_inputs) == pickle.dumps(by_hand)
    assert [contacts.input_index(1, w, i) for w, i in (("normal", 0), ("friction", 3), ("slack", 0))] == [7, 11, 12]
    with pytest.raises(ValueError, match="c must be a contact index in"):
        contacts.input_index(2, "normal")
    with pytest.raises(ValueError, match="what must be 'normal', 'friction' or 'slack', got 'tangent'"):
        contacts.input_index(0, "tangent")
    with pytest.raises(ValueError, match=r"i must be a friction direction in \[0, 4\)"):
        contacts.input_index(0, "friction", 4)


def test_bad_contact_input_is_refused_with_a_reason():
    model, terrain = planar_point_mass(), Terrain()
    point = [("mass", (0.0, 0.0, 0.0))]
    for points, match in (([], "at least one"), ([("nobody", (0, 0, 0))], "unknown contact body 'nobody'"),
                          ([(7, (0, 0, 0))], "unknown contact body 7"), ([("mass", (0, 0))], "3 finite numbers"),
                          ([("mass", (0, 0, np.nan))], "3 finite numbers"), ([("mass",)], "body name or index")):
        with pytest.raises(ValueError, match=match):
            Contacts(model, points, terrain, mu=0.5)
    with pytest.raises(TypeError, match="Terrain"):
        Contacts(model, point, "flat", mu=0.5)
    with pytest.raises(ValueError, match="plane must be"):
        Contacts(model, point, terrain, mu=0.5, plane="xy")
    with pytest.raises(ValueError, match="mu must be"):
        Contacts(model, point, terrain, mu=np.inf)
    contacts, prob = contact_problem(model, [0.0, 0.1], [0.0, 0.0], 0.2, 4, mu=0.5)
    with pytest.raises(TypeError, match="Contacts"):
        prob.add_contacts(contacts.with_inputs)
    with pytest.raises(ValueError, match="already"):
        prob.add_contacts(contacts)
    with pytest.raises(ValueError, match="per_point"):
        trajopt.Problem(contacts.with_inputs, N=4, T=0.2, controls="held").add_contacts(contacts)
    with pytest.raises(ValueError, match="solve_contact"):  # the exact conditions straight to IPOPT
        trajopt.solve(prob, verbose=False)
    for kwargs, match in (({"epsilons": ()}, "epsilons"), ({"epsilons": (1e-2, 1e-1)}, "decreasing"),
                          ({"epsilons": (0.1, 0.0)}, "positive"),
                          ({"finish_below": -1.0}, "finish_below"), ({"time_limit": 0.0}, "time_limit"),
                          ({"time_limit": np.nan}, "time_limit")):
        with pytest.raises(ValueError, match=match):
            trajopt.solve_contact(prob, VI1, **kwargs)
    with pytest.raises(ValueError, match="s must be"):
        trajopt.solve_contact(prob, trajopt.VI(s=0))
    with pytest.raises(TypeError, match="sides_from must be a Result"):
        trajopt.solve_contact(prob, VI1, sides_from=np.zeros(3))
    _, longer = contact_problem(planar_point_mass(), [0.0, 0.3], [0.5, 0.0], 0.6, 6, mu=0.5)
    other = trajopt.solve_contact(longer, VI1, epsilons=(1e-1,), finish_below=0)
    with pytest.raises(ValueError, match="sides_from must solve a problem with the same horizon T"):
        trajopt.solve_contact(prob, trajopt.VI(2), sides_from=other)
    prob.initial_state([0.0, -0.01])
    with pytest.raises(ValueError, match="initial configuration puts contact point 0 0.01 below the terrain"):
        trajopt.solve_contact(prob, VI1)
    plain = trajopt.Problem(model, N=4, T=0.2).initial_state([0.0, 0.1]).add_cost(trajopt.ControlEffort())
    with pytest.raises(ValueError, match="no contacts"):
        trajopt.solve_contact(plain, VI1)


def test_time_limit_stops_the_homotopy_between_solves():
    """A budget spent after the first relaxed solve: no further solve starts, and the result says so."""
    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.3], [0.0, 0.0], 0.5, 25, mu=0.5)
    result = trajopt.solve_contact(prob, VI1, time_limit=1e-3)
    assert len(result.contact["solves"]) == 1 and result.contact["solves"][0][0] == 0.1
    assert result.contact["out_of_time"] and not result.contact["finished"] and result.contact["epsilon"] == 0.1
    assert not result.success and result.status.startswith("stopped by time_limit = 0.001 s before the exact solve")
    assert not trajopt.solve_contact(prob, VI1, time_limit=600.0).contact["out_of_time"]


def test_no_exact_solve_is_no_success():
    """IPOPT stopped after 2 iterations every time: no exact solve, so no success, whatever the last
    relaxed solve reported, and the status says so."""
    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.3], [0.0, 0.0], 0.5, 25, mu=0.5)
    result = trajopt.solve_contact(prob, VI1, options={"max_iter": 2})
    assert not result.contact["finished"] and not result.success
    assert result.status.startswith("no exact solve succeeded; the last relaxed solve (epsilon = 1e-06)")


def test_checkpoint_resumes_the_homotopy_where_it_stopped(tmp_path):
    """A solve stopped after its first relaxed solve, resumed from its checkpoint: the same solves and
    the same solution as one uninterrupted solve; a checkpoint of another solve, a file that is no
    checkpoint and a folder that does not exist are refused."""
    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.3], [0.0, 0.0], 0.5, 25, mu=0.5)
    path = tmp_path / "drop.npz"
    stopped = trajopt.solve_contact(prob, VI1, time_limit=1e-3, checkpoint=path)
    assert stopped.contact["out_of_time"] and path.exists()
    resumed = trajopt.solve_contact(prob, VI1, checkpoint=path)
    whole = trajopt.solve_contact(prob, VI1)
    assert resumed.contact["solves"] == whole.contact["solves"] and resumed.contact["finished"]
    np.testing.assert_allclose(resumed.x, whole.x, rtol=0, atol=1e-12)
    assert not path.exists()                                     # finished: removed
    trajopt.solve_contact(prob, VI1, time_limit=1e-3, checkpoint=path)
    for kwargs, match in (({"epsilons": (1e-1, 1e-3)}, "epsilons"), ({"transcription": trajopt.VI(s=2)}, "another solve")):
        with pytest.raises(ValueError, match=match):
            trajopt.solve_contact(prob, **{"transcription": VI1, **kwargs}, checkpoint=path)
    (tmp_path / "notes.npz").write_text("not a checkpoint")
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    np.save(tmp_path / "array.npy", np.zeros(3))
    for name, match in (("notes.npz", "not a solve_contact checkpoint"), ("other.npz", "lacks"),
                        ("array.npy", "not a solve_contact checkpoint"),
                        ("missing/drop.npz", "folder does not exist")):
        with pytest.raises(ValueError, match=match):
            trajopt.solve_contact(prob, VI1, checkpoint=tmp_path / name)


def test_sides_from_a_trapezoidal_solution_lead_the_higher_order_solves():
    """The sliding block solved with s = 1, then with s = 2 and 3 from it: the exact solve on the
    sides its solution shows (it fails where the two place the stop differently, and the
    relaxation at FINISH_BELOW mends it): the same motion as the whole homotopy gives, with no
    relaxation above FINISH_BELOW."""
    mu, v0 = 0.5, 1.0
    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.0], [v0, 0.0], 0.4, 40, mu)
    coarse = trajopt.solve_contact(prob, VI1)
    for s in (2, 3):
        refined = trajopt.solve_contact(prob, trajopt.VI(s), sides_from=coarse)
        homotopy = trajopt.solve_contact(prob, trajopt.VI(s))
        assert refined.contact["finished"] and refined.contact["sides_from"] == coarse.transcription.name
        epsilons = [e for e, _, _ in refined.contact["solves"]]
        assert epsilons[0] == 0.0 and max(epsilons) <= FINISH_BELOW
        assert refined.contact["complementarity"] <= 1e-9 and refined.constraint_violation < 1e-8
        np.testing.assert_allclose(refined.trajectory["q"], homotopy.trajectory["q"], atol=1e-6)
        check_contact_result(refined)


def test_solves_on_another_solutions_sides_start_with_a_small_barrier(monkeypatch):
    """With sides_from every IPOPT solve gets NEAR_START_OPTIONS under the caller's options (a
    caller's mu_strategy is kept); without it none does."""
    from hovi.trajopt.solvers.contact_homotopy import NEAR_START_OPTIONS
    from hovi.trajopt.solvers.ipopt import Ipopt
    seen, solve_nlp = [], Ipopt.solve_nlp

    def spy(self, nlp, guess=None):
        seen.append(dict(self.options))
        return solve_nlp(self, nlp, guess)

    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.0], [1.0, 0.0], 0.4, 40, 0.5)
    coarse = trajopt.solve_contact(prob, VI1)
    monkeypatch.setattr(Ipopt, "solve_nlp", spy)
    trajopt.solve_contact(prob, trajopt.VI(2), sides_from=coarse)
    assert seen and all(o.items() >= NEAR_START_OPTIONS.items() for o in seen)
    seen.clear()
    trajopt.solve_contact(prob, trajopt.VI(2), sides_from=coarse, options={"mu_strategy": "adaptive"})
    assert seen and all(o["mu_strategy"] == "adaptive" and o["mu_init"] == NEAR_START_OPTIONS["mu_init"] for o in seen)
    seen.clear()
    trajopt.solve_contact(prob, trajopt.VI(2))
    assert seen and not any(k in o for o in seen for k in NEAR_START_OPTIONS)


def test_least_slack_lowers_only_the_free_sliding_slacks():
    """gamma raised where the mass flies (no force: psi = 0, gamma free above its bound) comes back to
    the least value its rows allow; the other variables and every row's feasibility are untouched."""
    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.3], [0.5, 0.0], 0.5, 25, mu=0.5)
    result = trajopt.solve_contact(prob, VI1)
    rows = ContactRows(contacts, result.transcription, 0.0)
    slack = rows.input_offsets("slack")
    raised = result.x.copy()
    raised[slack] += 100.0
    last, before = rows.hold_inputs()
    raised[last] = raised[before]
    lowered = least_slack(rows, raised)
    k = rows.quantities(lowered)
    changed = np.nonzero(lowered != raised)[0]
    assert set(changed) <= set(slack.ravel()) | set(last)
    np.testing.assert_allclose(k["gamma"], np.maximum(0, (-k["v"] @ contacts.D.T).max(-1)), atol=1e-12)
    assert k["zeta"].min() >= -1e-12 and rows.violations(lowered)["complementarity"] <= 1e-8
    np.testing.assert_array_less(lowered[slack], raised[slack] + 1e-15)


def test_sides_of_solution_give_each_pair_the_sides_of_the_coarse_pair_holding_its_point():
    """The sides of a trapezoidal solution at the pairs of s = 2, 3 and Hermite-Simpson: each fine
    pair's are those the coarse solution shows at the pair whose interval holds the fine point."""
    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.3], [0.5, 0.0], 0.5, 25, mu=0.5)
    coarse = trajopt.solve_contact(prob, VI1)
    crow = ContactRows(contacts, coarse.transcription, 0.0)
    B = sides_of(crow, canonical(crow, coarse.x))
    assert B.normal.any() and not B.normal.all()   # the mass flies, then lands
    for method in (trajopt.VI(2), trajopt.VI(3), trajopt.HermiteSimpson("implicit")):
        rows = ContactRows(contacts, method.transcribe(prob), 0.0)
        mapped = sides_of_solution(rows, coarse)
        for e, t in enumerate(rows.t[:-1]):
            k = max(i for i in range(crow.E) if crow.t[i] <= t + 1e-12)
            assert mapped.normal[e].tolist() == B.normal[k].tolist() and mapped.cone[e].tolist() == B.cone[k].tolist()
            assert mapped.friction[e].tolist() == B.friction[k].tolist()


def hermite_simpson_defects(result, contacts, mass=1.0):
    """The Hermite-Simpson equations of the planar point mass with its accelerations computed here from
    the optimised contact forces (a = F / m - g z, the slider massless), at every interval: the
    collocation residuals of q and v at the knot and the midpoint (Lobatto IIIA, separated form)."""
    tr, h = result.trajectory, result.transcription.dt
    q, v = tr["q"], tr["v"]
    a = contacts.forces(tr["u"])[:, 0, [0, 2]] / mass - [0.0, G]
    k, m, k1 = slice(0, -1, 2), slice(1, None, 2), slice(2, None, 2)
    return np.concatenate([
        v[k1] - v[k] - h / 6 * (a[k] + 4 * a[m] + a[k1]), q[k1] - q[k] - h / 6 * (v[k] + 4 * v[m] + v[k1]),
        v[m] - (v[k] + v[k1]) / 2 - h / 8 * (a[k] - a[k1]), q[m] - (q[k] + q[k1]) / 2 - h / 8 * (v[k] - v[k1])]).ravel()


@pytest.mark.parametrize("form", ["implicit", "explicit"])
def test_hermite_simpson_drop_with_the_same_contact_conditions(form):
    """Hermite-Simpson collocation with the VI's contact conditions on its knots and midpoints
    (the input at a point complementary to the gap at the next: hovi.trajopt.complementarity): the
    dropped mass falls freely (collocation is exact for a constant acceleration), lands without
    penetrating, and rests on the ground with the Simpson average of the normal force over each
    interval equal to its weight (the knot and midpoint forces themselves are not unique at rest:
    a_knot = c, a_mid = -c / 2 leaves every q and v unchanged). The impact inside an interval
    rebounds (as the VI's with s = 2), below the drop height."""
    model = planar_point_mass()
    z0, T, N = 0.3, 0.5, 25
    contacts, prob = contact_problem(model, [0.0, z0], [0.0, 0.0], T, N, mu=0.5)
    result = trajopt.solve_contact(prob, trajopt.HermiteSimpson(form))
    assert result.success and result.contact["finished"], result.status
    assert result.contact["penetration"] <= 1e-6 and result.contact["complementarity"] <= 1e-6
    np.testing.assert_allclose(hermite_simpson_defects(result, contacts), 0, atol=1e-8)
    t, z = result.trajectory["t"], result.trajectory["q"][:, 1]
    normal = result.trajectory["u"][:, contacts.input_index(0, "normal")]
    impact = np.sqrt(2 * z0 / G)
    before = t < impact - result.transcription.dt
    np.testing.assert_allclose(z[before], z0 - G * t[before] ** 2 / 2, atol=1e-8)
    np.testing.assert_allclose(normal[before], 0, atol=1e-5)
    assert z[t > impact].max() < 0.25 * z0  # the rebound loses energy
    end = t > T - 0.08
    np.testing.assert_allclose(z[end], 0, atol=1e-6)
    knots = np.flatnonzero(end[:-2] & (np.arange(len(t) - 2) % 2 == 0))  # intervals resting from their knot on
    simpson = (normal[knots] + 4 * normal[knots + 1] + normal[knots + 2]) / 6
    np.testing.assert_allclose(simpson, G, rtol=1e-6)


def test_hermite_simpson_sliding_block_stops_where_coulomb_friction_says():
    """The VI's sliding test with Hermite-Simpson: the same stopping distance and the cone saturated
    at every point while sliding. (The solution found puts the forces on the midpoints, about
    1.5 m g there and none at the knots: the non-unique knot/midpoint split of the drop test; the
    conditions hold the points on the ground but not the velocities at them, which oscillate by up
    to 1.3e-4 m/s.)"""
    model = planar_point_mass()
    mu, v0 = 0.5, 1.0
    contacts, prob = contact_problem(model, [0.0, 0.0], [v0, 0.0], 0.4, 40, mu)
    result = trajopt.solve_contact(prob, trajopt.HermiteSimpson("implicit"))
    assert result.success and result.contact["finished"], result.status
    assert result.contact["penetration"] <= 1e-6 and result.contact["complementarity"] <= 1e-6
    assert result.constraint_violation <= 1e-6
    # the collocation equations hold to the solution's own constraint violation (4.7e-8 here)
    np.testing.assert_allclose(hermite_simpson_defects(result, contacts), 0, atol=1.01 * result.constraint_violation)
    t, q = result.trajectory["t"], result.trajectory["q"]
    forces = contacts.forces(result.trajectory["u"])[:, 0]
    stop = v0 / (mu * G)
    assert q[-1, 0] == pytest.approx(v0 ** 2 / (2 * mu * G), rel=0.02)
    sliding = (t > 0) & (t < stop - 2 * result.transcription.dt)
    np.testing.assert_allclose(forces[sliding, 0], -mu * forces[sliding, 2], rtol=1e-3, atol=1e-8)  # saturated cone
    np.testing.assert_allclose(q[t > stop + 2 * result.transcription.dt, 0], q[-1, 0], atol=1e-6)  # at rest


def test_order_four_finds_the_unique_discrete_solution_which_rebounds():
    """With s = 2 every stage's conditions have one solution too (a P-matrix LCP), and solve_contact
    finds it; but an impact inside a stage rebounds (hovi.contact.contacts): dropped from 0.3 m with
    dt = 0.02 the mass lands at t = 0.25, rises to 3.3405 mm (time stepping the stage LCPs gives
    the same) and rests from t = 0.32 on."""
    model = planar_point_mass()
    contacts, prob = contact_problem(model, [0.0, 0.3], [0.0, 0.0], 0.5, 25, mu=0.5)
    result = trajopt.solve_contact(prob, trajopt.VI(s=2))
    check_contact_result(result)
    assert result.contact["finished"] and result.contact["epsilon"] == 0.0
    t, z = result.trajectory["t"], result.trajectory["q"][:, 1]
    assert z[t > 0.245].max() == pytest.approx(3.3405e-3, rel=1e-4)
    np.testing.assert_allclose(z[t > 0.315], 0, atol=1e-6)


def planar_hopper(k=200.0, c=15.0):
    """A planar hopper (Raibert's, without its actuators): a body (1 kg) on a planar base (x, z,
    pitch) with a leg (0.1 kg) sliding along it on a spring k and damper c at rest length 0; the
    foot is 0.5 m below the leg's joint (returns the model and the foot's point on the leg)."""
    model = hovi.Model()
    model.add_body("x", None, "prismatic", axis=(1, 0, 0))
    model.add_body("z", "x", "prismatic", axis=(0, 0, 1))
    model.add_body("body", "z", "revolute", axis=(0, 1, 0), mass=1.0, inertia=np.diag([0.02, 0.02, 0.01]))
    model.add_body("leg", "body", "prismatic", axis=(0, 0, 1), mass=0.1, com=(0, 0, -0.25),
                   inertia=np.diag([2e-3, 2e-3, 1e-4]))
    model.add_spring(3, k, 0.0)
    model.add_damper(3, c)
    return model, (0.0, 0.0, -0.5)


def test_dropped_planar_hopper_lands_on_its_foot_and_settles_on_its_spring():
    """Dropped upright from 0.1 m: free fall until the foot lands (the spring carries no load in
    flight), then the leg spring compresses and the damped motion settles where the spring holds
    the body, k q_leg = m_body g, with the ground carrying the whole weight; no schedule of the
    contact (the foot may lift off during the bounce) is given."""
    k, m_body, m_leg, h, T, N = 200.0, 1.0, 0.1, 0.1, 1.5, 75
    model, foot = planar_hopper(k)
    contacts = Contacts(model, [("leg", foot)], Terrain(), mu=0.8, plane="xz")
    prob = trajopt.Problem(contacts.with_inputs, N=N, T=T)
    prob.initial_state([0.0, 0.5 + h, 0.0, 0.0], np.zeros(4))
    prob.add_cost(trajopt.ControlEffort(weight=contacts.effort_weights(0.0)))
    prob.add_contacts(contacts)
    # L-BFGS keeps the solution exactly symmetric. The default exact Hessian's round-off leaves it
    # 1e-10 rad off upright and 1e-9 N sideways (both within IPOPT's tolerance), and the upright
    # hopper is unstable: the open-loop replay drifts 4.8e-5 rad by t = T.
    result = trajopt.solve_contact(prob, VI1, hessian="lbfgs")
    check_contact_result(result)
    t, q = result.trajectory["t"], result.trajectory["q"]
    normal = result.trajectory["u"][:, contacts.input_index(0, "normal")]
    impact = np.sqrt(2 * h / G)
    flight = t < impact - result.transcription.dt
    np.testing.assert_allclose(q[flight, 1], 0.5 + h - G * t[flight] ** 2 / 2, atol=1e-8)  # free fall
    np.testing.assert_allclose(q[flight, 3], 0, atol=1e-8)                                  # spring unloaded
    assert normal[t > impact + result.transcription.dt].max() > (m_body + m_leg) * G        # the landing
    np.testing.assert_allclose(q[:, [0, 2]], 0, atol=1e-8)                                  # upright, in place
    end = t > T - 0.2
    np.testing.assert_allclose(q[end, 3], m_body * G / k, rtol=1e-3)                        # k q_leg = m_body g
    np.testing.assert_allclose(q[end, 1] + q[end, 3] - 0.5, 0, atol=1e-6)                   # foot on the ground
    np.testing.assert_allclose(normal[end], (m_body + m_leg) * G, rtol=1e-3)                # ground carries all


def test_solve_contact_leaves_the_problem_unchanged():
    """The homotopy gives each NLP its relaxation (hovi.trajopt.ComplementarityRelaxation) and never
    writes to the Problem; the transcription must be a VI or HermiteSimpson (the old string spellings
    are gone); the exact conditions straight to an NLP are refused."""
    contacts, prob = contact_problem(planar_point_mass(), [0.0, 0.3], [0.0, 0.0], 0.5, 25, mu=0.5)
    before = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in vars(prob).items()}
    new = trajopt.solve_contact(prob, VI1)
    after = vars(prob)
    assert set(after) == set(before) and not hasattr(prob, "complementarity_epsilon")
    for key, value in before.items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(after[key], value)
        else:
            assert after[key] is value or after[key] == value, key
    assert new.transcription.method == VI1
    with pytest.raises(ValueError, match="not a string"):
        trajopt.solve_contact(prob, "vi")
    with pytest.raises(ValueError, match="solve_contact"):
        trajopt.NLP(prob, VI1, relaxation=hovi.trajopt.ComplementarityRelaxation(0.0))
    assert trajopt.NLP(prob, VI1, relaxation=hovi.trajopt.ComplementarityRelaxation(1e-2)).contact_rows.epsilon == 1e-2
