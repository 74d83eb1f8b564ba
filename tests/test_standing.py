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
    base = 3 if st.robot.base == "floating" else 2
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
