"""Property tests of the Python API with hypothesis: any shape, dtype, memory order or
value (NaN, inf, huge) passed to the main calls ends either in a documented exception (ValueError,
hovi.ModelError, hovi.ConvergenceError, TypeError for a non-numeric type) or in a finite result;
never a crash, and never NaN reported as a converged step."""
import numpy as np
import pytest

import hovi

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

N = 3
MODEL = hovi.examples.models.pendulum(N)
INTEG = hovi.Integrator(MODEL, s=2, dt=0.01)
LIN = hovi.Linearizer(INTEG)
EXPECTED = (ValueError, TypeError, hovi.ConvergenceError)
SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])

# Hostile values; entries beyond 1e150 are refused (their products would overflow), up to it must work.
values = st.one_of(st.floats(-3, 3), st.sampled_from([np.nan, np.inf, -np.inf, 1e300, -1e300, 1e150, -1e150, 0.0,
                                                      1e-300]))


@st.composite
def arrays(draw, length=N):
    """Arrays of a near-right or wrong shape, any dtype, C, Fortran or strided, hostile values."""
    shape = draw(st.sampled_from([(length,), (length,), (length,), (length - 1,), (length + 1,), (), (1, length),
                                  (length, 1), (0,)]))
    a = draw(hnp.arrays(np.float64, shape, elements=values))
    kind = draw(st.sampled_from(["plain", "float32", "int", "fortran", "strided", "list", "complex", "object"]))
    if kind == "float32":
        return a.astype(np.float32)
    if kind == "int":
        return np.nan_to_num(a, posinf=7, neginf=-7).astype(np.int64)
    if kind == "fortran":
        return np.asfortranarray(a)
    if kind == "strided" and a.ndim == 1:
        return np.repeat(a, 2)[::2]
    if kind == "list":
        return a.tolist()
    if kind == "complex":
        return a.astype(complex)
    if kind == "object":
        return np.array(["x"] * a.size, dtype=object).reshape(a.shape)
    return a


def finite(*xs):
    return all(np.all(np.isfinite(np.asarray(x, dtype=float))) for x in xs)


@SETTINGS
@given(arrays(), arrays())
def test_step_raises_or_returns_a_finite_converged_step(q, p):
    try:
        q1, p1, info = INTEG.step(q, p)
    except EXPECTED:
        return
    assert info.converged and finite(q1, p1)


@SETTINGS
@given(arrays(), arrays())
def test_step_without_raising_never_reports_nan_as_converged(q, p):
    try:
        q1, p1, info = INTEG.step(q, p, raise_on_failure=False)
    except EXPECTED:
        return
    assert not info.converged or finite(q1, p1)


@SETTINGS
@given(arrays(), arrays(), arrays())
def test_dynamics_raise_or_are_finite(q, v, tau):
    for f, args in ((MODEL.mass_matrix, (q,)), (MODEL.forward_dynamics, (q, v, tau)), (MODEL.energy, (q, v)),
                    (MODEL.joint_placements, (q,))):
        try:
            out = f(*args)
        except EXPECTED:
            continue
        assert finite(out), f.__name__


@SETTINGS
@given(arrays(), arrays())
def test_linearisation_raises_or_is_finite(q, v):
    try:
        traj = INTEG.rollout(q, 2, qdot0=v, raise_on_failure=False)
    except EXPECTED:
        return
    if traj.steps < 2:
        return
    try:
        As, _ = LIN.rollout_jacobians(traj, B=False)
        step = LIN.step_jacobians(traj.q[0], traj.p[0])
    except EXPECTED:
        return
    assert finite(As, step.A)


@SETTINGS
@given(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-5, 5)),
       st.one_of(st.integers(-3, 40), st.floats(0, 5)))
def test_integrator_options_are_checked(dt, s):
    try:
        integ = hovi.Integrator(MODEL, s=s, dt=dt)
    except EXPECTED:
        return
    assert integ.dt > 0 and np.isfinite(integ.dt) and integ.s == s and 1 <= integ.s <= 16


@SETTINGS
@given(st.floats(1.0, 1e8), st.floats(-2, 2))
def test_stiff_springs_converge_or_fail_explicitly(k, q0):
    model = hovi.examples.models.pendulum(2)
    model.add_spring(0, k, 0.0)
    integ = hovi.Integrator(model, s=1, dt=0.01)
    traj = integ.rollout(np.array([q0, 0.0]), 20, raise_on_failure=False)
    assert finite(traj.q, traj.p)
    assert traj.steps == 20 or traj.status[-1] != "converged"


def test_empty_model_is_refused():
    with pytest.raises(hovi.ModelError):
        hovi.Integrator(hovi.Model(), s=1, dt=0.01)
