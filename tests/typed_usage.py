"""hovi with type annotations: checked by ``mypy --strict tests/typed_usage.py`` (tests/test_typing.py
runs it, and runs this script). A 3-link pendulum: one step, a rollout, its linearisation, and a
trajectory saved and loaded again."""
from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import numpy.typing as npt

import hovi


def main() -> float:
    """Run everything; returns the largest relative energy error of the rollout."""
    model: hovi.Model = hovi.examples.models.pendulum(3)
    n: int = model.n
    q0: npt.NDArray[np.float64] = np.full(n, 0.3)
    qdot0: npt.NDArray[np.float64] = np.zeros(n)
    poses: npt.NDArray[np.float64] = model.body_poses(q0)  # (n, 4, 4)
    assert poses.shape == (n, 4, 4)

    integ: hovi.Integrator = hovi.Integrator(model, s=2, dt=0.01)
    p0: npt.NDArray[np.float64] = integ.momentum(q0, qdot0)
    q1: npt.NDArray[np.float64]
    p1: npt.NDArray[np.float64]
    info: hovi.StepInfo
    q1, p1, info = integ.step(q0, p0)
    assert info.converged and q1.shape == (n,) and p1.shape == (n,)

    traj: hovi.Trajectory = integ.rollout(q0, 200, qdot0=qdot0)
    energy: npt.NDArray[np.float64] = traj.energy
    drift: float = float(np.max(np.abs(energy - energy[0])) / abs(energy[0]))

    lin: hovi.Linearizer = hovi.Linearizer(integ)
    step: hovi.StepLinearization = lin.step_jacobians(q0, p0)
    A: npt.NDArray[np.float64] | None = step.A
    assert A is not None and A.shape == (2 * n, 2 * n)
    As: npt.NDArray[np.float64] | None
    As, _ = lin.rollout_jacobians(traj, B=False)
    assert As is not None and As.shape == (traj.steps, 2 * n, 2 * n)

    with tempfile.TemporaryDirectory() as tmp:
        path: Path = Path(tmp) / "pendulum.npz"
        traj.save(path)
        loaded: hovi.Trajectory = hovi.load_trajectory(path, integ)
    assert np.array_equal(loaded.q, traj.q) and loaded.status == traj.status
    return drift


if __name__ == "__main__":
    error: float = main()
    print(f"typed_usage: ok, relative energy error {error:.2e}")

