"""Property tests of the contact simulator with hypothesis: random throws of a box onto a
random terrain (ground, gaps, boxes), random friction, step sizes, orders and hostile states. Any
input ends either in a documented exception with a message (ValueError, TypeError,
hovi.ConvergenceError) or in a rollout whose every converged step keeps its contact points out of
the terrain and its complementarity conditions: never a crash, a hang or silent garbage."""
import numpy as np
import pytest

import hovi
from hovi.contact import Box, Contacts, Gap, Terrain
from test_contact_simulation import box_model

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

EXPECTED = (ValueError, TypeError, hovi.ConvergenceError)
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
MODEL, CORNERS = box_model()

finite = st.floats(-3, 3)
hostile = st.one_of(finite, st.sampled_from([np.nan, np.inf, -np.inf, 1e300, 0.0]))


@st.composite
def terrains(draw):
    gaps = [Gap(x, x + draw(st.floats(0.05, 0.5)), draw(st.floats(0.05, 1.0)))
            for x in draw(st.lists(st.floats(-1, 1), max_size=2))]
    boxes = [Box(x, x + draw(st.floats(0.05, 0.5)), draw(st.floats(-0.1, 0.2)))
             for x in draw(st.lists(st.floats(-1, 1), max_size=2))]
    return Terrain(ground=draw(st.floats(-0.2, 0.2)), gaps=gaps, boxes=boxes)


@SETTINGS
@given(terrain=terrains(), mu=st.floats(0.0, 2.0), dt=st.sampled_from([0.002, 0.005, 0.01, 0.03]),
       s=st.sampled_from([1, 1, 2]), q=st.lists(finite, min_size=6, max_size=6),
       v=st.lists(st.floats(-5, 5), min_size=6, max_size=6))
def test_random_throws_keep_the_contact_conditions(terrain, mu, dt, s, q, v):
    q = np.array(q)
    q[2] = 0.4 + 0.05 * abs(q[2])                                 # above every terrain piece drawn: it lands
    v = np.array(v)
    v[2] = -abs(v[2])                                             # thrown downwards
    integ = hovi.Integrator(MODEL, s=s, dt=dt, contacts=Contacts(MODEL, CORNERS, terrain, mu=mu))
    try:
        traj = integ.rollout(q, int(1.0 / dt), qdot0=v, raise_on_failure=False)
    except hovi.ModelError as e:  # the Euler angles of the floating base at gimbal lock (pitch +-pi/2)
        assert "mass matrix is singular" in str(e)
        return
    c = traj.contact
    assert traj.steps < int(1.0 / dt) or c.active.any()           # it landed (or a step failed)
    assert np.all(np.isfinite(traj.q)) and np.all(np.isfinite(c.impulses))
    if traj.steps:
        assert c.gaps.min() >= -1e-9
        lam = c.normal
        assert lam.min() >= 0 and np.abs(lam * c.gaps).max() <= 1e-9 * max(1.0, lam.max())
    if not traj.converged:
        assert traj.status[-1] in ("lcp_failed", "line_search_failed", "max_iterations", "singular_jacobian",
                                   "non_finite", "continuation_stalled")


@SETTINGS
@given(q=st.lists(hostile, min_size=6, max_size=6), v=st.lists(hostile, min_size=6, max_size=6),
       u=st.one_of(st.none(), st.lists(hostile, min_size=1, max_size=2)))
def test_hostile_states_are_refused_or_simulated(q, v, u):
    integ = hovi.Integrator(MODEL, s=1, dt=0.01, contacts=Contacts(MODEL, CORNERS, Terrain(), mu=0.5))
    try:
        traj = integ.rollout(np.array(q), 5, qdot0=np.array(v), u=None if u is None else np.array(u),
                             raise_on_failure=False)
    except EXPECTED as e:
        assert str(e)
        return
    assert np.all(np.isfinite(traj.q))
    if traj.steps:
        assert traj.contact.gaps.min() >= -1e-9


@SETTINGS
@given(mu=hostile, tol=hostile, ground=hostile)
def test_hostile_contact_settings_are_refused(mu, tol, ground):
    try:
        contacts = Contacts(MODEL, CORNERS, Terrain(ground=ground), mu=mu)
        hovi.Integrator(MODEL, s=1, dt=0.01, contacts=contacts, contact_tol=tol)
    except EXPECTED as e:
        assert str(e)
        return
    assert np.isfinite(mu) and 0 <= mu <= 1e3 and np.isfinite(ground) and 0 < tol <= 1e-3
