"""Property tests (hypothesis) of the constructors and entry points of hovi.control (Policy, Push,
lqr, tvlqr, simulate, simulate_batch, MPC) and the FDDP solver, and of the contact constructors
(Contacts, ContactPoint, FlatFoot): random garbage (wrong types and shapes, NaN, infinity, negative
and huge numbers, text, ragged nested lists) either raises ValueError or TypeError with a message, or
gives a finite, consistent result; never another exception, a crash or a hang. Kept small (a few
seconds)."""
import warnings

import numpy as np
import pytest

import hovi
from hovi import control, trajopt
from hovi.contact import ContactPoint, Contacts, FlatFoot, Terrain
from hovi.examples import models
from conftest import planar_point_mass

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from test_fuzz_newer_apis import arrays  # noqa: E402  (hostile arrays of any dtype or container)

EXPECTED = (ValueError, TypeError)  # hovi.ModelError is a ValueError
TOO_BIG = "more than this machine's"  # the MemoryError of runs that cannot fit in memory (as Integrator.rollout's)
SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])

CARTPOLE = models.cartpole()  # n = 2, m = 1
PLANT = hovi.Integrator(CARTPOLE, s=1, dt=0.01)
LQR = control.lqr(PLANT, [0.0, np.pi])
U5 = np.full((5, 1), 0.5)
TRAJ = PLANT.rollout([0.0, 3.0], 5, u=U5)
FDDP_PROBLEM = trajopt.Problem(CARTPOLE, 5, 0.05, controls="held", q_bounds=(-np.inf, np.inf), u_bounds=(-20, 20)) \
    .initial_state([0.0, 3.0]).add_cost(trajopt.ControlEffort(0.01)).add_cost(trajopt.TerminalCost([0.0, np.pi], 10.0))
MPC_ = control.MPC(FDDP_PROBLEM, max_iterations=2)

values = st.one_of(st.floats(-3, 3), st.sampled_from([np.nan, np.inf, -np.inf, 1e300, -1e300, 0.0, -1.0, 1e-300]))
garbage = st.one_of(values, st.integers(-5, 5), st.sampled_from([2**40, -2**63]), st.booleans(), st.none(),
                    st.text(max_size=3), st.complex_numbers(max_magnitude=3),
                    st.sampled_from([[1.0, 2.0], [[1.0]], [[1.0, 2.0], [3.0]], {}, (), "x", b"x", object()]))


def hostile(shapes):
    return st.one_of(garbage, arrays(shapes))


def finite(*xs):
    """Each of xs is real numbers (no text, complex or objects), all finite."""
    return all(np.asarray(x).dtype.kind in "iuf" and np.all(np.isfinite(x)) for x in xs)


def refused_with_a_message(call):
    """call() -> (True, None) if it raised ValueError or TypeError with a message, else (False, result)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", np.exceptions.ComplexWarning)  # a silent complex cast is a failure
            warnings.simplefilter("ignore", RuntimeWarning)               # a run that ended early (flagged)
            return False, call()
    except EXPECTED as e:
        assert str(e), f"{type(e).__name__} without a message"
        return True, None
    except MemoryError as e:
        assert TOO_BIG in str(e)
        return True, None


def check_run(run, steps):
    """A closed-loop or MPC run: finite, and either all its steps or flagged where it stopped."""
    tr = run.trajectory
    assert finite(tr.q, tr.p, run.u) and tr.q.shape[1] == 2
    assert (tr.steps == steps) == (run.failure is None)
    if run.failure is not None:
        assert run.failure.startswith(f"step {tr.steps} of {steps}")


# --- Policy -----------------------------------------------------------------------------------

FIELDS = {"x_ref": [(1, 4), (2, 4), (1, 3), (4,)], "u_ref": [(1, 2, 1), (1, 3, 1), (1, 2), (2, 2, 1)],
          "gains": [(1, 1, 4), (1, 1, 3), (1, 4), (2, 1, 4), (0, 1, 4)], "lower": [(1,), (), (2,)],
          "upper": [(1,), (), (2,)], "cost_to_go": [(1, 4, 4), (2, 4, 4), (4, 4), (1, 3, 3)], "dt": [(), (1,)],
          "s": [(), (1,)]}


@SETTINGS
@given(st.data())
def test_policies_are_refused_or_consistent(data):
    changes = {name: data.draw(hostile(FIELDS[name]), label=name)
               for name in data.draw(st.sets(st.sampled_from(sorted(FIELDS)), min_size=1, max_size=3))}
    refused, p = refused_with_a_message(lambda: control.Policy(**{**LQR.__dict__, **changes}))
    if refused:
        return
    S, m, n2 = p.gains.shape
    assert p.x_ref.shape == (S, n2) and p.u_ref.shape == (S, p.s + 1, m) and p.lower.shape == p.upper.shape == (m,)
    assert finite(p.x_ref, p.u_ref, p.gains, p.cost_to_go) and np.all(p.lower <= p.upper)
    assert isinstance(p.s, int) and p.s >= 1 and np.isfinite(p.dt) and p.dt > 0
    refused, run = refused_with_a_message(lambda: control.simulate(PLANT, p, [0.0, 3.0], 3))
    if not refused:
        check_run(run, 3)


@SETTINGS
@given(st.one_of(garbage, st.integers(-3, 30)), hostile([(2,), (3,), (1, 2)]), hostile([(2,), (3,)]))
def test_policy_control_is_refused_or_finite(k, q, p):
    refused, u = refused_with_a_message(lambda: LQR.control(k, q, p))
    assert refused or (u.shape == (2, 1) and finite(u))


@SETTINGS
@given(hostile([(5, 1), (5, 2, 1), (5,), (5, 3, 1), (0, 1), (5, 2)]), garbage, st.one_of(garbage, st.integers(0, 3)))
def test_open_loop_policies_are_refused_or_run(u, dt, s):
    refused, p = refused_with_a_message(lambda: control.Policy.open_loop(u, dt, s, 2))
    if refused:
        return
    assert p.u_ref.shape[1:] == (p.s + 1, p.m) and np.all(p.gains == 0) and finite(p.u_ref)
    refused, run = refused_with_a_message(lambda: control.simulate(PLANT, p, [0.0, 3.0], 4))
    if not refused:
        check_run(run, 4)


# --- Push, simulate, simulate_batch -------------------------------------------------------------

pushes = st.builds(control.Push, st.one_of(garbage, st.floats(0, 0.1)),
                   st.one_of(garbage, st.sampled_from(["pole", "cart", "nobody", 0, 1, 2, -1, 1.0])),
                   hostile([(3,), (2,), (3, 1)]), hostile([(3,), (4,)]), st.one_of(garbage, st.floats(0, 0.1)),
                   hostile([(3,), (2,)]))
push_arguments = st.one_of(st.lists(pushes, max_size=2), pushes, garbage)


@SETTINGS
@given(push_arguments, hostile([(2,), (1, 2), (3,), ()]), st.one_of(garbage, st.integers(-2, 6)),
       st.one_of(st.none(), hostile([(2,), (3,)])))
def test_simulate_is_refused_or_finite(push, q0, steps, qdot0):
    refused, run = refused_with_a_message(lambda: control.simulate(PLANT, LQR, q0, steps, qdot0=qdot0, pushes=push))
    if not refused:
        check_run(run, steps)


@SETTINGS
@given(st.one_of(st.lists(st.lists(pushes, max_size=2), max_size=3), push_arguments),
       hostile([(2,), (3, 2), (2, 2), (3, 3)]), st.one_of(st.none(), garbage, st.integers(-1, 4)),
       st.one_of(st.none(), garbage, st.integers(-1, 3)), st.sampled_from([PLANT, [PLANT, PLANT], [], [PLANT, "x"], 3]))
def test_simulate_batch_is_refused_or_finite(push, q0, runs, threads, plants):
    refused, out = refused_with_a_message(lambda: control.simulate_batch(plants, LQR, q0, 3, pushes=push, runs=runs,
                                                                         threads=threads))
    if refused:
        return
    assert len(out) >= 1
    for run in out:
        check_run(run, 3)


# --- lqr, tvlqr ----------------------------------------------------------------------------------

weights = st.one_of(st.just(1.0), garbage, arrays([(), (1,), (2,), (2, 2), (3,), (4, 4)]))
limits = st.one_of(st.none(), garbage, st.tuples(st.one_of(garbage, arrays([(1,), ()])),
                                                 st.one_of(garbage, arrays([(1,), ()]))))


@SETTINGS
@given(st.one_of(st.just([0.0, np.pi]), hostile([(2,), (3,)])), st.one_of(st.none(), hostile([(1,), (2,)])),
       weights, weights, weights, limits)
def test_lqr_is_refused_or_finite(q_eq, u_eq, q_weight, v_weight, u_weight, u_limits):
    refused, p = refused_with_a_message(lambda: control.lqr(PLANT, q_eq, u_eq, q_weight=q_weight, v_weight=v_weight,
                                                            u_weight=u_weight, u_limits=u_limits))
    assert refused or (finite(p.gains, p.cost_to_go, p.x_ref, p.u_ref) and p.gains.shape == (1, 1, 4))


@SETTINGS
@given(st.one_of(st.just(U5), hostile([(5, 1), (5, 2, 1), (4, 1), (1,)])), weights, weights, weights,
       st.one_of(st.none(), weights), limits, st.one_of(st.just(0.0), garbage))
def test_tvlqr_is_refused_or_finite(u, q_weight, u_weight, Q, final_weight, u_limits, smoothing):
    refused, p = refused_with_a_message(lambda: control.tvlqr(
        PLANT, TRAJ, u, q_weight=q_weight, u_weight=u_weight, Q=None if np.ndim(Q) < 2 else Q,
        final_weight=final_weight, u_limits=u_limits, smoothing=smoothing))
    assert refused or (finite(p.gains, p.cost_to_go) and p.gains.shape == (5, 1, 4))


# --- MPC and FDDP --------------------------------------------------------------------------------

@SETTINGS
@given(st.one_of(st.just(1), garbage), st.one_of(st.integers(0, 7), garbage), st.one_of(st.just(2), garbage),
       st.one_of(st.just(1e-8), garbage), st.one_of(st.just(0.0), garbage), st.sampled_from([None, "ground", 3]))
def test_mpc_constructors_are_refused_or_work(s, period, max_iterations, tol, smoothing, contacts):
    refused, mpc = refused_with_a_message(lambda: control.MPC(FDDP_PROBLEM, s, period=period,
                                                              max_iterations=max_iterations, tol=tol,
                                                              contacts=contacts, smoothing=smoothing))
    assert refused or (1 <= mpc.period <= 5 and mpc.max_iterations >= 1 and mpc.tol > 0)


@SETTINGS
@given(hostile([(2,), (3,), (1, 2)]), st.one_of(garbage, st.integers(-1, 4)), st.one_of(st.none(), hostile([(2,)])),
       push_arguments, st.one_of(st.none(), hostile([(5, 1), (5,), (4, 1), (1,)])))
def test_mpc_runs_are_refused_or_finite(q0, steps, qdot0, push, warm_start):
    refused, run = refused_with_a_message(lambda: MPC_.run(PLANT, q0, steps, qdot0=qdot0, pushes=push,
                                                           warm_start=warm_start))
    if not refused:
        check_run(run, steps)


guesses = st.one_of(st.none(), garbage, arrays([(5, 1), (1,), (4, 1), (5,)]),
                    st.tuples(*[st.sampled_from([lambda t: np.zeros((len(t), 1)), lambda t: np.zeros(len(t)),
                                                 lambda t: np.full((len(t), 1), np.nan), lambda t: "x",
                                                 lambda t: np.zeros((3, 3)), lambda t: None])] * 3))


@SETTINGS
@given(st.one_of(st.just(3), garbage), st.one_of(st.just(1e-9), garbage), st.one_of(st.just(1), garbage),
       guesses, st.one_of(st.just(1), garbage))
def test_fddp_is_refused_or_finite(max_iterations, tol, threads, guess, s):
    def solve():
        return trajopt.FDDP(max_iterations, tol, threads).solve(FDDP_PROBLEM, trajopt.VI(s), guess)
    refused, r = refused_with_a_message(solve)
    assert refused or (np.isfinite(r.cost) and finite(r.solver["us"], r.solver["xs"]))


# --- contact constructors (python/hovi/contact) -----------------------------------------------------

BLOCK = planar_point_mass(2.0, actuated=True)


@SETTINGS
@given(st.one_of(st.sampled_from(["mass", "slider", "nobody", 0, 1, 2, -1, 1.0, None]), garbage),
       hostile([(3,), (2,), (4,)]), st.one_of(st.just(0.0), garbage), st.one_of(st.just(0.5), garbage),
       st.one_of(st.sampled_from(["", "xz", "yz", "xy"]), garbage), st.booleans())
def test_contacts_are_refused_or_consistent(body, point, radius, mu, plane, as_contact_point):
    def make():
        entry = ContactPoint(body, point, radius) if as_contact_point else (body, point, radius)
        return Contacts(BLOCK, [entry], Terrain(), mu=mu, plane=plane)
    refused, contacts = refused_with_a_message(make)
    if refused:
        return
    c = contacts.points[0]
    assert 0 <= contacts.mu and finite(c.point) and c.point.shape == (3,) and c.radius >= 0
    assert finite(contacts.gaps(np.zeros(2)))


@SETTINGS
@given(st.one_of(st.sampled_from(["mass", 0]), garbage), hostile([(3,), (2,)]), st.one_of(st.just(0.0), garbage))
def test_contact_points_are_refused_or_consistent(body, point, radius):
    refused, c = refused_with_a_message(lambda: ContactPoint(body, point, radius))
    assert refused or (isinstance(c.body, (str, int)) and finite(c.point) and np.shape(c.point) == (3,)
                       and np.isfinite(c.radius) and c.radius >= 0)


@SETTINGS
@given(st.one_of(st.sampled_from(["mass", "slider", "nobody", 1, 5]), garbage), hostile([(3,), (2,)]),
       st.one_of(st.just(0.1), garbage), st.one_of(st.just(0.05), garbage), st.one_of(st.just(0.5), garbage),
       hostile([(2,), (3,)]), st.one_of(st.none(), garbage))
def test_flat_feet_are_refused_or_consistent(body, centre, X, Y, mu, q0, scale):
    refused, foot = refused_with_a_message(lambda: FlatFoot(BLOCK, body, centre, X, Y, mu, q0, scale))
    if refused:
        return
    assert finite(foot.centre, foot.q0, foot.X, foot.Y, foot.mu, foot.scale) and foot.X > 0 and foot.Y > 0
    assert foot.scale > 0 and foot.with_inputs.n_controls == BLOCK.n_controls + 6
