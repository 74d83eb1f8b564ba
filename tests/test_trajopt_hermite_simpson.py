"""The Hermite-Simpson transcription against the Hermite-Simpson simulator of the baselines: a
rollout of the simulator, filled into the NLP's variables, satisfies the transcription's
constraints (both forms); and Table 1's counts."""
import numpy as np
import pytest

import hovi
from hovi import trajopt
from hovi.baselines import HermiteSimpson



@pytest.mark.parametrize("implicit", [True, False])
def test_simulated_trajectory_satisfies_the_collocation_constraints(implicit):
    model = hovi.examples.models.pendulum(4)
    model.add_spring(1, 3.0, 0.2)
    model.add_damper(2, 0.4)
    model.armature = [0.1, 0.0, 0.3, 0.05]
    N, h = 6, 0.02
    q0 = np.array([0.3, -0.2, 0.1, 0.4])
    sim = HermiteSimpson(model, h, tol=1e-13).rollout(q0, np.zeros(4), N)
    q, v = sim["q"], sim["v"]

    def fd(x, y):  # forward dynamics with the springs and dampers
        return model.forward_dynamics(x, y, model.force_jacobians(x, y)[0])

    a = np.array([fd(qk, vk) for qk, vk in zip(q, v)])
    qm = (q[:-1] + q[1:]) / 2 + h / 8 * (v[:-1] - v[1:])
    vm = (v[:-1] + v[1:]) / 2 + h / 8 * (a[:-1] - a[1:])
    am = np.array([fd(x, y) for x, y in zip(qm, vm)])
    P = 2 * N + 1
    Q, V, A = np.zeros((P, 4)), np.zeros((P, 4)), np.zeros((P, 4))
    Q[::2], V[::2], A[::2] = q, v, a
    Q[1::2], V[1::2], A[1::2] = qm, vm, am
    tr = hovi._core.trajopt.HermiteSimpsonTranscription(model, N, h, "per_point", implicit)
    x = np.concatenate([Q.ravel(), V.ravel()] + ([A.ravel()] if implicit else []))
    assert len(x) == tr.n_variables
    g = tr.constraints(x)
    assert np.abs(g).max() < 1e-9 * (1 + np.abs(x).max())


def test_table1_counts():
    """Variables and constraints of the built NLPs against the paper's Table 1 (N stages, n DoF
    fully actuated, m constraint equations). Hermite-Simpson: the paper's variables exactly; its
    constraints impose h, ḣ and ḧ at every point, which over-determines the collocation (4m more
    equations than unknowns per interval): hovi keeps ḧ at every point and h, ḣ at t = 0."""
    N, n, m = 7, 4, 2
    model = hovi.examples.models.pendulum(n)
    for j in range(n):
        model.add_actuator(j)
    tip = model.joint_placements(np.zeros(n))[-1] @ np.array([0, 0, -0.5, 1.0])
    model.add_point_constraint(n - 1, point=[0, 0, -0.5], target=tip[:3], axes="xy")
    implicit = hovi._core.trajopt.HermiteSimpsonTranscription(model, N, 0.1, "per_point", True)
    explicit = hovi._core.trajopt.HermiteSimpsonTranscription(model, N, 0.1, "per_point", False)
    assert implicit.n_variables == (8 * N + 4) * n + (2 * N + 1) * m
    assert implicit.n_constraints == (6 * N + 1) * n + (2 * N + 1) * m + 2 * m
    assert explicit.n_variables == (6 * N + 3) * n + (2 * N + 1) * m
    assert explicit.n_constraints == 4 * N * n + (2 * N + 1) * m + 2 * m
    vi = hovi._core.trajopt.VariationalTranscription(model, 2, N, 0.1, "per_point")
    # q at 2N + 1 points, p at N + 1 knots, u at 2N + 1 points, λ at 2N points (λ^{k,2} = 0)
    assert vi.n_variables == (2 * N + 1) * n + (N + 1) * n + (2 * N + 1) * n + 2 * N * m
    assert vi.n_constraints == 3 * N * n + (2 * N + 1) * m  # the paper's count exactly
