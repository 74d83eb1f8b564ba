"""Step Jacobians through contact (hovi.Linearizer of an Integrator with contacts; the C++
ContactJacobians, its contact part) against central differences of the contact step, away from contact switches:
a planar body on two contact points in stance (four rows on three freedoms: the friction
impulses undetermined, the motion not), sliding and flight, and a box sliding. A box flat on four
corners is at a switch (the LCP loads two, a tilt loads the others), as a flat sole is: not
differentiable there. Nor is a box resting on a tripod of three sticking points, where central
differences agree only to O(h) (2e-6 at h = 1e-6, 2e-7 at 1e-7 on entries of 10): tilted by h, the
three points' horizontal distances shrink by O(h^2), so nine stick rows on six freedoms can no longer
all hold, and which point slips (by O(h^2)) depends on the sign of h, a kink at second order."""
import numpy as np
import pytest

import hovi
from hovi.contact import Contacts, Terrain
from test_contact_simulation import box_model


def planar_body():
    m = hovi.Model()
    m.add_body("x", None, "prismatic", axis=(1, 0, 0))
    m.add_body("z", "x", "prismatic", axis=(0, 0, 1))
    m.add_body("body", "z", "revolute", axis=(0, 1, 0), mass=1.0, inertia=np.diag([0.02, 0.02, 0.01]))
    m.add_actuator(2)
    contacts = Contacts(m, [("body", (0.1, 0, -0.05)), ("body", (-0.1, 0, -0.05))], Terrain(), mu=0.5, plane="xz")
    return hovi.Integrator(m, s=1, dt=0.01, contacts=contacts)


def central_differences(integ, q, p, u, h=1e-6):
    """(A, B_held) of the step map (q, p, u) -> (q', p') by central differences (u held over the step)."""
    n, m = len(q), len(u)

    def f(x, uu):  # the C++ step: Integrator.step refuses the states tilted into the terrain
        qc, pn, info = integ.core.step(x[:n], x[n:], uu, None, None, None)
        assert info["converged"]
        return np.r_[qc[-1], pn]
    x = np.r_[q, p]
    A = np.column_stack([(f(x + h * e, u) - f(x - h * e, u)) / (2 * h) for e in np.eye(2 * n)])
    B = np.column_stack([(f(x, u + h * e) - f(x, u - h * e)) / (2 * h) for e in np.eye(m)])
    return A, B


def check(integ, q, qdot, u, state):
    p = integ.momentum(q, qdot)
    lin = hovi.Linearizer(integ)
    L = lin.step_jacobians(q, p, u, hold=True)
    _, _, info = integ.step(q, p, u)
    lam, gamma = info.impulses[:, 0], info.impulses[:, -1]
    assert state(lam, gamma), (lam, gamma)  # the contact state the case is about
    A, B = central_differences(integ, q, p, u)
    assert np.abs(L.A - A).max() <= 1e-8 * max(1.0, np.abs(A).max())
    assert np.abs(L.B - B).max() <= 1e-8 * max(1.0, np.abs(B).max())


def test_planar_body_in_stance():
    check(planar_body(), np.array([0.0, 0.05, 0.0]), np.zeros(3), np.array([0.1]),
          lambda lam, gamma: np.all(lam > 0) and np.all(gamma <= 1e-12))


def test_planar_body_sliding():
    check(planar_body(), np.array([0.0, 0.05, 0.0]), np.array([0.5, 0.0, 0.0]), np.array([0.1]),
          lambda lam, gamma: np.all(lam > 0) and np.all(gamma > 0))


def test_planar_body_in_flight():
    check(planar_body(), np.array([0.0, 0.15, 0.0]), np.array([0.0, 1.0, 0.0]), np.array([0.1]),
          lambda lam, gamma: np.all(lam == 0))


def box_integrator(points=None):
    model, corners = box_model()
    model.add_actuator(3)
    return hovi.Integrator(model, s=1, dt=0.005, contacts=Contacts(model, points or corners, Terrain(), mu=0.6))


def test_box_sliding():
    check(box_integrator(), np.array([0.0, 0.0, 0.05, 0.1, 0.0, 0.0]), np.array([0.5, 0.2, 0.0, 0.3, 0.0, 0.0]),
          np.array([0.01]), lambda lam, gamma: np.all(gamma[lam > 0] > 0))


def test_rollout_jacobians_are_the_step_jacobians_along_a_landing():
    integ = planar_body()
    u = np.array([0.1])
    traj = integ.rollout(np.array([0.0, 0.06, 0.1]), 30, qdot0=np.array([0.3, 0.0, 0.0]), u=u)
    assert traj.contact.active.any() and not traj.contact.active.all()   # flight, landing, stance
    lin = hovi.Linearizer(integ)
    As, Bs = lin.rollout_jacobians(traj, u, hold=True)
    for k in (0, 10, 29):
        L = lin.step_jacobians(traj.q[k], traj.p[k] if k == 0 else traj_state_momentum(integ, traj, k), u, hold=True)
        np.testing.assert_allclose(As[k], L.A, rtol=0, atol=1e-10 * np.abs(L.A).max())


def traj_state_momentum(integ, traj, k):
    """The momentum the step k starts from (Trajectory.p carries half the knot impulse for 0 < k < K)."""
    _, p, _ = integ.step(traj.q[k - 1], traj_state_momentum(integ, traj, k - 1) if k > 1 else traj.p[0],
                         np.array([0.1]))
    return p


def test_rollout_jacobians_need_the_contact_record():
    integ = planar_body()
    traj = integ.rollout(np.array([0.0, 0.05, 0.0]), 3, u=np.array([0.1]))
    traj.contact = None
    with pytest.raises(ValueError, match="contact impulses"):
        hovi.Linearizer(integ).rollout_jacobians(traj, np.array([0.1]))


def test_steps_split_at_an_impact_are_refused():
    integ = hovi.Integrator(planar_body().model, s=2, dt=0.01, contacts=planar_body().contacts)
    traj = integ.rollout(np.array([0.0, 0.1, 0.0]), 20, u=np.array([0.1]))
    assert np.any(traj.contact.impact > 0)
    with pytest.raises(ValueError, match="split at an impact"):
        hovi.Linearizer(integ).rollout_jacobians(traj, np.array([0.1]))


def test_smoothed_jacobians_agree_away_from_switches():
    """The central-path linearisation with a small smoothing is the held-state one where each pair is far
    from its switch (stance: 1e-12; sliding)."""
    integ = planar_body()
    lin = hovi.Linearizer(integ)
    u = np.array([0.1])
    for qdot in (np.zeros(3), np.array([0.5, 0.0, 0.0])):
        q = np.array([0.0, 0.05, 0.0])
        p = integ.momentum(q, qdot)
        held = lin.step_jacobians(q, p, u, hold=True)
        smooth = lin.step_jacobians(q, p, u, hold=True, smoothing=1e-14)
        np.testing.assert_allclose(smooth.A, held.A, rtol=0, atol=1e-6 * np.abs(held.A).max())
        np.testing.assert_allclose(smooth.B, held.B, rtol=0, atol=1e-6 * np.abs(held.B).max())


def test_smoothed_jacobian_blends_the_sides_of_a_switch():
    """A weightless block touching the ground (gap 0, no load): pushed down it stays, pulled up it
    leaves: the height after a step has the one-sided derivatives 0 and dt/m in the vertical
    momentum. Held, the step's state (no load: flight) gives dt/m; smoothed, half of it."""
    model = hovi.Model()
    model.add_body("slider", None, "prismatic", axis=(1, 0, 0))
    model.add_body("mass", "slider", "prismatic", axis=(0, 0, 1), mass=2.0, inertia=np.eye(3) * 1e-3)
    model.gravity = (0.0, 0.0, 0.0)
    dt = 0.01
    integ = hovi.Integrator(model, s=1, dt=dt, contacts=Contacts(model, [("mass", (0, 0, 0))], Terrain(), mu=0.5,
                                                                  plane="xz"))
    q, p = np.zeros(2), np.zeros(2)
    h = 1e-6
    up = (integ.step(q, p + [0, h])[0][1] - integ.step(q, p)[0][1]) / h
    down = (integ.step(q, p)[0][1] - integ.step(q, p - [0, h])[0][1]) / h
    assert abs(up - dt / 2.0) < 1e-9 and abs(down) < 1e-9                  # the two sides: dt/m and 0
    lin = hovi.Linearizer(integ)
    held = lin.step_jacobians(q, p).A[1, 3]
    smooth = lin.step_jacobians(q, p, smoothing=1e-12).A[1, 3]
    assert abs(held - dt / 2.0) < 1e-12                                    # held: the side of the step
    assert abs(smooth - 0.5 * (up + down)) < 1e-6                          # smoothed: between the sides
    with pytest.raises(ValueError, match="smoothing"):
        lin.step_jacobians(q, p, smoothing=-1.0)
