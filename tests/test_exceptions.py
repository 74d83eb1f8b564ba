"""Every error of the C++ core reaches Python as an exception of a documented type (never an abort):
one test per mapping, each from a real call."""
import numpy as np
import pytest

import hovi


def test_model_errors_are_model_error_and_value_error():
    model = hovi.Model()
    with pytest.raises(hovi.ModelError, match="not positive definite") as err:
        model.add_body("b", None, mass=1.0, inertia=-np.eye(3))
    assert isinstance(err.value, ValueError)


def test_urdf_errors_are_urdf_error_a_model_error():
    with pytest.raises(hovi.URDFError, match="malformed or invalid URDF") as err:
        hovi.Model.from_urdf("<robot name='r'><link name='a'></robot>")
    assert isinstance(err.value, hovi.ModelError) and isinstance(err.value, ValueError)
    with pytest.raises(hovi.URDFError, match="cannot open URDF file"):
        hovi.Model.from_urdf("/nonexistent/robot.urdf")


def test_bad_arguments_are_value_errors():
    integ = hovi.Integrator(hovi.examples.models.pendulum(3), s=2, dt=0.01)
    with pytest.raises(ValueError, match="q must be a 1-D array of length 3"):
        integ.step(np.zeros(4), np.zeros(3))
    with pytest.raises(ValueError, match="NaN or infinity"):
        integ.step(np.array([0.0, np.nan, 0.0]), np.zeros(3))
    with pytest.raises(ValueError):
        hovi.Integrator(hovi.examples.models.pendulum(3), s=2, dt=-0.01)
    with pytest.raises(ValueError, match="q must be an array of real numbers, got complex"):  # not cast silently
        integ.step(np.zeros(3, dtype=complex), np.zeros(3))
    with pytest.raises(ValueError, match="beyond 1e150 in magnitude"):  # would overflow to inf
        hovi.examples.models.pendulum(3).energy(np.zeros(3), np.full(3, 1e200))


def test_a_changed_model_is_a_model_error():
    model = hovi.examples.models.pendulum(2)
    integ = hovi.Integrator(model, s=1, dt=0.01)
    model.add_damper(0, 0.1)
    with pytest.raises(hovi.ModelError, match="the model was changed"):
        integ.step(np.zeros(2), np.zeros(2))


def test_a_failed_solve_is_a_convergence_error_with_the_partial_trajectory():
    integ = hovi.Integrator(hovi.examples.models.pendulum(32), s=1, dt=0.5)
    rng = np.random.default_rng(3)
    with pytest.raises(hovi.ConvergenceError) as err:
        integ.rollout(rng.uniform(-1.5, 1.5, 32), 50, qdot0=rng.uniform(-5, 5, 32))
    assert isinstance(err.value, RuntimeError) and err.value.trajectory is not None
    assert not err.value.trajectory.converged or err.value.trajectory.steps < 50


def test_a_rollout_too_long_for_the_memory_is_a_memory_error_before_allocating():
    integ = hovi.Integrator(hovi.examples.models.pendulum(2), s=1, dt=0.01)
    with pytest.raises(MemoryError, match="simulate in pieces"):
        integ.rollout(np.zeros(2), 10 ** 15)
