"""The paper's robots standing for 10 s in the contact simulator under joint PD control about their
nominal pose (hovi.examples.standing): base drift after the first second at most 1 mm, no
penetration beyond 1e-9 m at the configuration points, the weight carried by the contacts, and
contact forces without chatter (their step-to-step variation)."""
import numpy as np
import pytest

from hovi.examples.standing import standing

G = 9.81


@pytest.mark.parametrize("name", ["littledog", "spring_flamingo", "atlas"])
def test_robot_stands_for_ten_seconds(name):
    st = standing(name)
    dt = st.integrator.dt
    traj = st.integrator.rollout(st.q0, int(round(10.0 / dt)), u=st.u)
    base = 3 if st.robot.base == "euler" else 2
    k1 = int(round(1.0 / dt))
    assert np.abs(traj.q[-1, :base] - traj.q[k1, :base]).max() <= 1e-3     # base drift after settling
    assert np.abs(traj.q[-1] - st.q0).max() <= 0.01                         # still in its pose (rad, m)
    assert traj.contact.gaps.min() >= -1e-9                                 # no penetration at the points
    normal = traj.contact.normal
    np.testing.assert_allclose(normal[k1:].sum(1), st.model.total_mass * G * dt, rtol=1e-6)  # the weight
    loaded = normal[k1:].mean(0) > 1e-3 * normal[k1:].mean(0).max()
    chatter = np.abs(np.diff(normal[k1:, loaded], axis=0)).max(0) / normal[k1:, loaded].mean(0)
    assert chatter.max() <= 1e-4                                            # steady forces, step to step
    assert traj.contact.sliding[k1:].max() <= 1e-9                          # the feet stick


def test_unknown_robot_is_refused():
    with pytest.raises(ValueError, match="no standing scene"):
        standing("ur5")


# the held feet's horizontal positions: LittleDog's 4 point feet in x and y, the Flamingo's 2 feet (toe and heel
# points on one rigid foot) in x
@pytest.mark.parametrize("name, body, held", [("littledog", "body", 8), ("spring_flamingo", "base_link", 2)])
def test_lqr_with_the_stance_held_stands_the_bare_robot_up_to_a_push(name, body, held):
    """control.lqr at the rest pose of the robot without its PD (the contact forces part of the
    equilibrium, the stance held in the linearisation): the closed loop's only modes of modulus 1 are
    the held feet's horizontal positions, and a push of 0.1 m/s
    on the trunk is recovered from, back to the pose within 1e-3 after 3 s, feet on the ground."""
    from hovi import Linearizer, control
    scene = standing(name)
    plant, rest = scene.plant, scene.rest
    policy = control.lqr(plant, rest)
    u, p = policy.u_ref[0, 0], policy.x_ref[0, plant.n:]
    lin = Linearizer(plant).step_jacobians(rest, p, u, hold=True)
    moduli = np.abs(np.linalg.eigvals(lin.A - lin.B @ policy.gains[0]))
    assert np.sum(moduli > 1 - 1e-9) == held and moduli.max() <= 1 + 1e-9
    assert np.sort(moduli)[-held - 1] < 0.999
    push = control.Push(0.5, body, [0.1 * scene.model.total_mass, 0.0, 0.0])
    run = control.simulate(plant, policy, rest, int(round(3.5 / plant.dt)), pushes=[push])
    assert run.converged
    assert np.abs(run.trajectory.q - rest).max() > 1e-2                 # the push moved it
    assert np.abs(run.trajectory.q[-1] - rest).max() < 1e-3             # and it came back
    assert run.trajectory.contact.gaps.min() >= -1e-9
    open_loop = control.simulate(plant, policy.with_limits(policy.u_ref[0, 0], policy.u_ref[0, 0]), rest,
                                 int(round(3.5 / plant.dt)), pushes=[push])
    assert not open_loop.converged or np.abs(open_loop.trajectory.q[-1] - rest).max() > 0.1  # without feedback: falls


def test_lqr_refuses_a_pose_whose_feet_do_not_touch():
    from hovi import control
    scene = standing("littledog")
    with pytest.raises(ValueError, match=r"q is not an equilibrium .* contacts \[0, 1, 2, 3\] do not touch the "
                                         r"terrain at q \(gaps \[0.000346"):
        control.lqr(scene.plant, scene.q0)
