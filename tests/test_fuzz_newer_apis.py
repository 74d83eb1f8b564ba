"""Property tests of the newer APIs with hypothesis: trajectory-optimisation problems
and their bounds, terrain and contacts, trajectory files (random bytes, truncated files, mutated
arrays) and batches. Any input ends either in a documented exception with a message (ValueError,
TypeError, FileNotFoundError, hovi.ModelError, hovi.ConvergenceError) or in a finite,
consistent result: never a crash, a hang or silent garbage. Kept small (the file runs in well
under a minute)."""
import io
import warnings
import zipfile

import numpy as np
import pytest

import hovi
from hovi import trajopt
from hovi.contact import Box, Contacts, Gap, Terrain

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

EXPECTED = (ValueError, TypeError, hovi.ConvergenceError)  # hovi.ModelError is a ValueError
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                          HealthCheck.function_scoped_fixture])

N = 2
MODEL = hovi.examples.models.pendulum(N)
MODEL.add_actuator(0)
INTEG = hovi.Integrator(MODEL, s=2, dt=0.01)

values = st.one_of(st.floats(-3, 3), st.sampled_from([np.nan, np.inf, -np.inf, 1e300, -1e300, 0.0, 1e-300]))
scalars = st.one_of(values, st.integers(-5, 5), st.booleans(), st.none(), st.text(max_size=3),
                    st.complex_numbers(max_magnitude=3), st.sampled_from([[1.0, 2.0], (0.5,), [[1.0]], {}]))


@st.composite
def arrays(draw, shapes, kinds=("plain", "float32", "int", "list", "complex", "object", "bool")):
    """Arrays of one of ``shapes`` with hostile values, in one of ``kinds`` of dtype or container."""
    shape = draw(st.sampled_from(shapes))
    a = draw(hnp.arrays(np.float64, shape, elements=values))
    kind = draw(st.sampled_from(kinds))
    if kind == "float32":
        with np.errstate(over="ignore"):
            return a.astype(np.float32)
    if kind == "int":
        return np.clip(np.nan_to_num(a, nan=0, posinf=7, neginf=-7), -7, 7).astype(np.int64)
    if kind == "list":
        return a.tolist()
    if kind == "complex":
        return a + 1j * draw(st.sampled_from([0.0, 1.0]))
    if kind == "object":
        return np.array([draw(st.sampled_from(["x", 1.0, None]))] * a.size, dtype=object).reshape(a.shape)
    if kind == "bool":
        return a > 0
    return a


def finite(*xs):
    return all(np.all(np.isfinite(np.asarray(x, dtype=float))) for x in xs)


def refused_with_a_message(call):
    """call() -> (True, None) if it raised a documented exception with a message, else (False, result)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", np.exceptions.ComplexWarning)  # a silent complex cast is a failure
            return False, call()
    except EXPECTED as e:
        assert str(e), f"{type(e).__name__} without a message"
        return True, None


# --- trajectory optimisation: problems, bounds, guesses --------------------------------------

bounds = st.one_of(st.none(), scalars, st.tuples(st.one_of(scalars, arrays([(N,), (N + 1,), (1,), ()])),
                                                 st.one_of(scalars, arrays([(N,), (N + 1,), (1,), ()]))))


@SETTINGS
@given(st.one_of(st.integers(-2, 6), scalars), st.one_of(values, scalars), bounds, bounds,
       st.sampled_from(["per_point", "held", "sometimes", None]))
def test_problems_are_refused_or_have_consistent_bounds(n_stages, T, q_bounds, u_bounds, controls):
    refused, prob = refused_with_a_message(lambda: trajopt.Problem(MODEL, n_stages, T, q_bounds=q_bounds,
                                                                   u_bounds=u_bounds, controls=controls or "x"))
    if refused:
        return
    assert isinstance(prob.N, int) and prob.N >= 1 and np.isfinite(prob.T) and prob.T > 0
    for lo, hi, size in ((prob.q_lower, prob.q_upper, N), (prob.u_lower, prob.u_upper, 1)):
        assert lo.shape == hi.shape == (size,) and lo.dtype == hi.dtype == np.float64
        assert not np.any(np.isnan(lo)) and not np.any(np.isnan(hi)) and np.all(lo <= hi)
        assert np.all(lo < np.inf) and np.all(hi > -np.inf)


guess_functions = st.tuples(*[st.sampled_from([
    lambda t: np.zeros((len(t), N)), lambda t: np.zeros((len(t), 1)), lambda t: np.zeros(len(t)),
    lambda t: np.full((len(t), N), np.nan), lambda t: np.zeros((N, len(t))), lambda t: "x",
    lambda t: np.zeros((len(t), N), dtype=complex) + 1j, lambda t: 0.0, lambda t: None])] * 3)


@SETTINGS
@given(st.one_of(guess_functions, scalars, st.sampled_from(["rollout", "linear", "roll", ""])),
       st.one_of(arrays([(N,), (N + 1,)]), st.just(np.zeros(N))))
def test_guesses_and_states_are_refused_or_give_a_finite_start(guess, q0):
    refused, prob = refused_with_a_message(lambda: trajopt.Problem(MODEL, 3, 0.3).initial_state(q0)
                                           .add_cost(trajopt.ControlEffort()))
    if refused:
        return
    nlp = trajopt.NLP(prob, trajopt.VI(s=1))
    refused, x0 = refused_with_a_message(lambda: nlp.transcription.initial_guess(guess))
    if refused:
        return
    assert x0.shape == (nlp.n_variables,) and finite(x0)
    refused_with_a_message(lambda: nlp.check_start(np.clip(x0, nlp.lower, nlp.upper)))


@SETTINGS
@given(st.one_of(scalars, arrays([(), (1,), (2,)])), st.sampled_from(["value", "dq", "tuple"]))
def test_costs_returning_anything_are_refused_or_finite(value, where):
    def fun(t, w, q, v, u):
        if where == "tuple":
            return value
        if where == "dq":
            return 0.0, value, np.zeros_like(v), np.zeros_like(u)
        return value, np.zeros_like(q), np.zeros_like(v), np.zeros_like(u)

    prob = trajopt.Problem(MODEL, 3, 0.3).initial_state(np.zeros(N)).add_cost(trajopt.CallbackCost(fun))
    nlp = trajopt.NLP(prob, trajopt.VI(s=1))
    x0 = nlp.transcription.initial_guess("linear")
    refused, _ = refused_with_a_message(lambda: nlp.check_start(x0))
    if refused:
        return
    assert np.isfinite(nlp.objective(x0)) and finite(nlp.gradient(x0))


# --- contact ---------------------------------------------------------------------------------

@SETTINGS
@given(st.one_of(values, scalars), st.lists(st.tuples(st.one_of(values, scalars), st.one_of(values, scalars),
                                                      st.one_of(values, scalars)), max_size=2),
       st.lists(st.tuples(values, values, values), max_size=2))
def test_terrain_is_refused_or_gives_finite_gaps(ground, gaps, boxes):
    def make():
        return Terrain(ground=ground, gaps=[Gap(*g) for g in gaps], boxes=[Box(*b) for b in boxes])

    refused, terrain = refused_with_a_message(make)
    if refused:
        return
    points = np.array([[x, 0.0, 0.3] for x in np.linspace(-3, 3, 13)])
    assert finite(terrain.gap(points))


@SETTINGS
@given(st.one_of(values, scalars), st.one_of(st.sampled_from(["mass", "slider", "nobody", 0, 1, 2, -1, 1.0, None]),
                                             scalars),
       st.one_of(arrays([(3,), (2,), (4,), ()]), scalars), st.sampled_from(["", "xz", "yz", "xy", None]),
       arrays([(1, 4), (2, 6), (6,), (4,), (2, 5), (0, 4), (3, 2, 6)], kinds=("plain", "list", "int", "bool")))
def test_contacts_are_refused_or_give_finite_forces(mu, body, point, plane, u):
    model = hovi.Model()
    model.add_body("slider", None, "prismatic", axis=(1, 0, 0))
    model.add_body("mass", "slider", "prismatic", axis=(0, 0, 1), mass=1.0, inertia=np.eye(3) * 1e-3)
    refused, contacts = refused_with_a_message(lambda: Contacts(model, [(body, point)], Terrain(), mu=mu, plane=plane))
    if refused:
        return
    assert 0 <= contacts.mu <= 1e3 and finite(contacts.points[0].point)
    refused, forces = refused_with_a_message(lambda: contacts.forces(u))
    if refused:
        return
    assert forces.shape == (np.atleast_2d(u).shape[0], 1, 3) and finite(forces)


# --- trajectory files ------------------------------------------------------------------------

TRAJ = INTEG.rollout(np.array([0.3, -0.2]), 4)
FILE = io.BytesIO()
TRAJ.save(FILE)
GOOD = FILE.getvalue()
with np.load(io.BytesIO(GOOD)) as f:
    ARRAYS = {k: f[k] for k in f.files}


def check_loaded(path):
    """load_trajectory(path) (with and without the integrator): a documented error with a
    message, or a trajectory whose arrays fit the model and each other and are finite."""
    for integrator in (None, INTEG):
        try:
            traj = hovi.load_trajectory(path, integrator)
        except (ValueError, TypeError, FileNotFoundError) as e:
            assert str(e)
            continue
        K = traj.steps
        assert traj.q.shape == traj.p.shape == (K + 1, N) and traj.control_points.shape == (K, 3, N)
        assert finite(traj.t, traj.q, traj.p, traj.control_points)
        assert len(traj.status) in (K, K + 1) and traj.iterations.shape == (len(traj.status),)
        if integrator is not None:
            assert finite(traj.energy)


@SETTINGS
@given(st.binary(max_size=300))
def test_random_bytes_are_not_a_trajectory(tmp_path_factory, data):
    path = tmp_path_factory.mktemp("bytes") / "random.npz"
    path.write_bytes(data)
    check_loaded(path)


@SETTINGS
@given(st.integers(0, len(GOOD)))
def test_truncated_files_are_refused_or_whole(tmp_path_factory, cut):
    path = tmp_path_factory.mktemp("cut") / "cut.npz"
    path.write_bytes(GOOD[:cut])
    check_loaded(path)


@SETTINGS
@given(st.sampled_from(sorted(ARRAYS) + ["extra"]),
       st.one_of(arrays([(), (1,), (5,), (4,), (5, 2), (4, 3, 2), (6, 5), (4, 2, 2)],
                        kinds=("plain", "float32", "int", "complex", "bool")),
                 st.sampled_from([np.array("x"), np.array(["a", "b"]), np.array(1), np.array(99), None])),
       st.booleans())
def test_mutated_arrays_are_refused_or_consistent(tmp_path_factory, name, value, compressed):
    arrays = dict(ARRAYS)
    if value is None:
        arrays.pop(name, None)
    else:
        arrays[name] = np.asarray(value)
    path = tmp_path_factory.mktemp("mutated") / "mutated.npz"
    (np.savez_compressed if compressed else np.savez)(path, **arrays)
    check_loaded(path)


@SETTINGS
@given(st.integers(0, 2000), st.integers(0, 255))
def test_flipped_bytes_are_refused_or_consistent(tmp_path_factory, position, byte):
    data = bytearray(GOOD)
    data[position % len(data)] = byte
    path = tmp_path_factory.mktemp("flip") / "flip.npz"
    path.write_bytes(bytes(data))
    try:
        check_loaded(path)
    except zipfile.BadZipFile as e:  # pragma: no cover - must have been turned into a ValueError
        pytest.fail(f"BadZipFile escaped load_trajectory: {e}")


# --- batches ---------------------------------------------------------------------------------

real_kinds = ("plain", "float32", "int", "list", "bool")


def check_rollout_batch(q0s, u, steps):
    refused, batch = refused_with_a_message(lambda: INTEG.rollout_batch(q0s, steps, u=u, threads=1))
    if refused:
        return
    B = len(batch.status)
    assert batch.q.shape == (B, steps + 1, N)
    for b in range(B):
        k = int(batch.steps[b])
        assert finite(batch.q[b, :k + 1], batch.p[b, :k + 1])
        assert batch.status[b] == "converged" or k < steps


def check_step_batch(qs, ps, u):
    refused, out = refused_with_a_message(lambda: INTEG.step_batch(qs, ps, u, threads=1))
    if refused:
        return
    assert out.q_next.shape == (len(out.status), N)
    for b in range(len(out.status)):
        assert not out.converged[b] or finite(out.q_next[b], out.p_next[b])


batch_states = [(2, N), (1, N), (2, N + 1), (N,), (0, N), (2, 1, N)]
batch_controls = [(2, 1), (2, 3, 1), (2, 3, 3, 1), (1,), (2, 2), (3, 1)]


@SETTINGS
@given(arrays(batch_states, real_kinds), st.one_of(st.none(), arrays(batch_controls, real_kinds)),
       st.integers(-1, 3))  # non-int step counts: tests/test_batch.py (rollout_batch refuses them like rollout)
def test_rollout_batch_of_real_input_is_refused_or_finite(q0s, u, steps):
    check_rollout_batch(q0s, u, steps)


@SETTINGS
@given(arrays(batch_states, real_kinds), st.one_of(st.none(), arrays(batch_states, real_kinds)),
       st.one_of(st.none(), arrays([(2, 1), (2, 3, 1), (1, 1), (2,)], real_kinds)))
def test_step_batch_of_real_input_is_refused_or_finite(qs, ps, u):
    check_step_batch(qs, ps, u)


# Complex input with a nonzero imaginary part and object arrays: refused in every batch argument
# (_core.real_array refuses complex numbers and names the argument of object arrays).
def complex_input(shape):
    return np.full(shape, 0.1) + 0.5j


def object_input(shape):
    return np.full(shape, "x", dtype=object)


HOSTILE = [("q0s", complex_input), ("q0s", object_input), ("u", complex_input), ("u", object_input)]


@pytest.mark.parametrize("argument, make", HOSTILE, ids=[f"{a}-{m.__name__}" for a, m in HOSTILE])
def test_rollout_batch_refuses_complex_and_object_input(argument, make):
    q0s, u = np.full((2, N), 0.1), np.zeros((2, 1))
    with pytest.raises((ValueError, TypeError), match=argument):
        if argument == "q0s":
            INTEG.rollout_batch(make((2, N)), 2, u=u, threads=1)
        else:
            INTEG.rollout_batch(q0s, 2, u=make((2, 1)), threads=1)


@pytest.mark.parametrize("argument, make", HOSTILE, ids=[f"{a}-{m.__name__}" for a, m in HOSTILE])
def test_step_batch_refuses_complex_and_object_input(argument, make):
    qs = np.full((2, N), 0.1)
    with pytest.raises((ValueError, TypeError), match="qs" if argument == "q0s" else "u"):
        if argument == "q0s":
            INTEG.step_batch(make((2, N)), None, np.zeros((2, 1)), threads=1)
        else:
            INTEG.step_batch(qs, None, make((2, 1)), threads=1)


# --- serialised models: pickled bytes with any change are refused, never loaded as another model ---

import pickle  # noqa: E402

MODEL_BYTES = pickle.dumps(hovi.examples.models.acrobot())
# what pickle itself raises on damaged framing (opcodes, lengths, the names of globals; a changed
# frame length can ask for more memory than there is)
PICKLE_ERRORS = (pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError, KeyError, IndexError,
                 ImportError, UnicodeDecodeError, OverflowError, MemoryError)


@SETTINGS
@given(st.data())
def test_changed_model_bytes_are_refused(data):
    """Bytes written by pickle with one to three bytes changed, a cut or an insertion somewhere in
    them: unpickling raises (hovi.ModelError for a damaged payload, pickle's own error when the
    pickle framing itself is broken), or, if the change fell outside the payload, gives the same
    model (or, where the change rewrote pickle's own opcodes, an object that is no model at all)."""
    raw = bytearray(MODEL_BYTES)
    kind = data.draw(st.sampled_from(["change", "cut", "insert"]))
    at = data.draw(st.integers(0, len(raw) - 1))
    if kind == "change":
        for k in range(data.draw(st.integers(1, 3))):
            i = (at + 7 * k) % len(raw)
            raw[i] = (raw[i] + data.draw(st.integers(1, 255))) % 256
    elif kind == "cut":
        del raw[at:at + data.draw(st.integers(1, 16))]
    else:
        raw[at:at] = data.draw(st.binary(min_size=1, max_size=8))
    try:
        loaded = pickle.loads(bytes(raw))
    except hovi.ModelError as e:  # the payload reached hovi and was refused with a message
        assert "model" in str(e)
        return
    except PICKLE_ERRORS:         # the pickle framing around it was broken: pickle's own refusal
        return
    if isinstance(loaded, hovi.Model):  # never another model (pickle's framing, broken, may give another object)
        assert pickle.dumps(loaded) == MODEL_BYTES
