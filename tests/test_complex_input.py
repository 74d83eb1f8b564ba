"""Arrays that are not real numbers (hostile input): complex (whose imaginary part a cast
would drop), object (None would read as NaN) and text (which a cast would parse) arrays are refused by
every entry point of the integrator, single and batched, with a ValueError naming the argument;
nothing is cast silently."""
import numpy as np
import pytest

import hovi
from hovi import _core

N, B = 3, 2


@pytest.fixture(scope="module")
def integ():
    model = hovi.examples.models.pendulum(N)
    model.add_actuator(0)
    return hovi.Integrator(model, s=2, dt=0.01)


def complex_(shape):
    return np.full(shape, 0.1 + 1e-3j)  # a nonzero imaginary part


def objects(shape):
    a = np.zeros(shape).astype(object)
    a.flat[0] = None  # np.asarray(a, dtype=float) reads it as NaN
    return a


def text(shape):
    return np.full(shape, "0.1")  # np.asarray(a, dtype=float) parses it


HOSTILE = [(complex_, "complex"), (objects, "an object array"), (text, "text")]

Z, ZB = np.zeros(N), np.zeros((B, N))
# (entry point, argument name in the message, call with the hostile array x in that argument's place)
CALLS = {
    "step q": ("q", lambda i, f: i.step(f((N,)), Z)),
    "step p": ("p", lambda i, f: i.step(Z, f((N,)))),
    "step u": ("u", lambda i, f: i.step(Z, Z, f((1,)))),
    "step guess": ("guess", lambda i, f: i.step(Z, Z, guess=f((i.s + 1, N)))),
    "rollout q0": ("q0", lambda i, f: i.rollout(f((N,)), 2)),
    "rollout qdot0": ("qdot0", lambda i, f: i.rollout(Z, 2, qdot0=f((N,)))),
    "rollout p0": ("p0", lambda i, f: i.rollout(Z, 2, p0=f((N,)))),
    "rollout u": ("u", lambda i, f: i.rollout(Z, 2, u=f((1,)))),
    "rollout u per step": ("u", lambda i, f: i.rollout(Z, 2, u=f((2, 1)))),
    "rollout_batch q0s": ("q0s", lambda i, f: i.rollout_batch(f((B, N)), 2)),
    "rollout_batch p0s": ("p0s", lambda i, f: i.rollout_batch(ZB, 2, p0s=f((B, N)))),
    "rollout_batch qdot0s": ("qdot0s", lambda i, f: i.rollout_batch(ZB, 2, qdot0s=f((B, N)))),
    "rollout_batch u": ("u", lambda i, f: i.rollout_batch(ZB, 2, u=f((B, 1)))),
    "step_batch qs": ("qs", lambda i, f: i.step_batch(f((B, N)))),
    "step_batch ps": ("ps", lambda i, f: i.step_batch(ZB, f((B, N)))),
    "step_batch qdots": ("qdots", lambda i, f: i.step_batch(ZB, qdots=f((B, N)))),
    "step_batch u": ("u", lambda i, f: i.step_batch(ZB, None, f((B, 1)))),
    "check_rollout_batch q0s": ("q0s", lambda i, f: i.check_rollout_batch(f((B, N)), 2)),
    "check_step_batch u": ("u", lambda i, f: i.check_step_batch(ZB, None, f((B, 1)))),
    "momentum qdot": ("qdot", lambda i, f: i.momentum(Z, f((N,)))),
    "mass_matrix q": ("q", lambda i, f: i.model.mass_matrix(f((N,)))),
}


@pytest.mark.parametrize("make, what", HOSTILE, ids=[w for _, w in HOSTILE])
@pytest.mark.parametrize("call", list(CALLS))
def test_every_entry_point_refuses_arrays_that_are_not_real_numbers(integ, call, make, what):
    name, f = CALLS[call]
    with pytest.raises(ValueError, match=rf"^{name} must be an array of real numbers, got {what}"):
        f(integ, make)


@pytest.mark.parametrize("call", list(CALLS))
def test_the_same_calls_with_real_arrays_run(integ, call):
    CALLS[call][1](integ, np.zeros)


def test_lists_of_complex_numbers_and_complex_scalars_are_refused_too(integ):
    with pytest.raises(ValueError, match="^q0 must be an array of real numbers, got complex"):
        integ.rollout([0.1 + 1j, 0.0, 0.0], 2)
    with pytest.raises(ValueError, match="^qs must be an array of real numbers, got complex"):
        integ.step_batch([[1j, 0, 0], [0, 0, 0]])
    with pytest.raises(ValueError, match="^u must be real, got a complex number"):
        integ.rollout(Z, 2, u=1j)


def test_an_object_batch_is_refused_not_reported_as_nan(integ):
    q0s = np.array([[0.1, None, 0.0], [0.0, 0.0, 0.0]], dtype=object)
    with pytest.raises(ValueError, match=r"^q0s must be an array of real numbers, got an object array \(dtype object, "
                                         r"e.g. 0.1\)"):
        integ.rollout_batch(q0s, 2)
    with pytest.raises(ValueError, match="^qs must be an array of real numbers, got an object array"):
        integ.step_batch(np.zeros((B, N)).astype(object))  # even of floats: never cast


def test_real_array_names_the_argument_and_the_problem():
    np.testing.assert_array_equal(_core.real_array([[1, 2], [3, 4]], "x"), [[1.0, 2.0], [3.0, 4.0]])
    assert _core.real_array(np.arange(3, dtype=np.int32), "x").dtype == np.float64
    assert np.isnan(_core.real_array([np.nan], "x")[0])  # the values are the callers' to check
    for value, pattern in [(None, "got None"), ([[1, 2], [3]], "numpy cannot read it as an array"),
                           ([True, False], "got booleans"), (np.zeros(2, dtype="datetime64[s]"), "got dtype"),
                           (["1", "2"], r"got text \(<U1\)"), (3j, "must be real, got a complex number")]:
        with pytest.raises(ValueError, match=f"^thing .*{pattern}"):
            _core.real_array(value, "thing")
