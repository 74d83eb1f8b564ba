"""Hostile input to the newer APIs: trajectory files, trajectory optimisation, contact.
Each refusal is a ValueError (TypeError for an object of the wrong class, FileNotFoundError for a missing file)
whose message names the argument and the problem; nothing is accepted silently."""
import numpy as np
import pytest

import hovi
from hovi import trajopt
from hovi.contact import Box, Contacts, FlatFoot, Gap, Terrain
from hovi.examples import swingups
from conftest import planar_point_mass


# --- trajectory files ------------------------------------------------------------------------

def saved(tmp_path, n=3, s=2):
    integ = hovi.Integrator(hovi.examples.models.pendulum(n), s=s, dt=0.01)
    traj = integ.rollout(np.full(n, 0.2), 5)
    path = tmp_path / "t.npz"
    traj.save(path)
    return integ, traj, path


def mutated(tmp_path, path, **changes):
    with np.load(path) as f:
        arrays = {k: f[k] for k in f.files}
    arrays.update(changes)
    for k in [k for k, v in changes.items() if v is None]:
        del arrays[k]
    out = tmp_path / "mutated.npz"
    np.savez(out, **arrays)
    return out


@pytest.mark.parametrize("name, value, match", [
    ("q", np.zeros((6, 5)), r"q must have shape \(6, 3\), got \(6, 5\)"),
    ("p", np.zeros((6, 2)), r"p must have shape \(6, 3\)"),
    ("control_points", np.zeros((2, 7)), r"control_points must have shape \(5, 3, 3\), got \(2, 7\)"),
    ("t", np.arange(6) * 0.02, r"t must be k dt \(dt = 0.01\)"),
    ("iterations", np.zeros(3, dtype=int), r"iterations must have shape \(5,\)"),
    ("iterations", np.zeros(5), "iterations must be an array of integers"),
    ("residuals", np.zeros((5, 2)), r"residuals must have shape \(5,\)"),
    ("status", np.array(["converged"] * 7), "status must have one entry per attempted step"),
    ("status", np.arange(5), "status must be a 1-D array of strings"),
    ("multipliers", np.zeros((5, 2, 1)), "multipliers"),
    ("format_version", np.array(99), "written by a newer hovi"),
    ("format_version", np.array("one"), "format_version must be an integer"),
    ("format_version", np.array(1.5), "format_version must be an integer"),
    ("format_version", None, "missing format_version"),
    ("s", np.array(0), "s must be >= 1"),
    ("dt", np.array(np.nan), "dt must be positive and finite"),
    ("joint_names", np.array([], dtype=str), "joint_names must be a non-empty"),
    ("solve_seconds", np.array(-1.0), "solve_seconds must be finite and >= 0"),
    ("extra", np.zeros(2), r"unknown entries \['extra'\]"),
])
def test_trajectory_files_whose_arrays_do_not_fit_are_refused(tmp_path, name, value, match):
    integ, traj, path = saved(tmp_path)
    bad = mutated(tmp_path, path, **{name: value})
    if name != "multipliers":   # without the model, multipliers (K, s, 1) may be those of a constrained one
        with pytest.raises(ValueError, match=match):
            hovi.load_trajectory(bad)
    if name not in ("format_version", "extra"):
        with pytest.raises(ValueError, match=match):
            hovi.load_trajectory(bad, integ)


def test_nan_and_mutated_values_in_a_file_are_refused(tmp_path):
    integ, traj, path = saved(tmp_path)
    q = traj.q.copy()
    q[2, 1] = np.nan
    with pytest.raises(ValueError, match=r"q holds NaN or infinity \(at index \(2, 1\)\)"):
        hovi.load_trajectory(mutated(tmp_path, path, q=q))
    q = traj.q.copy()
    q[3, 0] += 0.1                                        # no longer where the control points end
    with pytest.raises(ValueError, match="control_points must start at q"):
        hovi.load_trajectory(mutated(tmp_path, path, q=q))
    with pytest.raises(ValueError, match="q must be an array of real numbers, got complex"):
        hovi.load_trajectory(mutated(tmp_path, path, q=traj.q.astype(complex)))


def test_missing_empty_damaged_and_foreign_files(tmp_path):
    integ, traj, path = saved(tmp_path)
    with pytest.raises(FileNotFoundError, match="no trajectory file at .*nowhere.npz"):
        hovi.load_trajectory(tmp_path / "nowhere.npz")
    (tmp_path / "empty.npz").write_bytes(b"")
    with pytest.raises(ValueError, match="the file is empty"):
        hovi.load_trajectory(tmp_path / "empty.npz")
    data = path.read_bytes()
    (tmp_path / "cut.npz").write_bytes(data[:len(data) // 2])
    with pytest.raises(ValueError, match="cut.npz"):
        hovi.load_trajectory(tmp_path / "cut.npz")
    np.save(tmp_path / "array.npy", np.zeros(3))
    with pytest.raises(ValueError, match="a single array"):
        hovi.load_trajectory(tmp_path / "array.npy")
    with pytest.raises(ValueError, match="is a directory"):
        hovi.load_trajectory(tmp_path)
    with pytest.raises(TypeError, match="integrator must be a hovi.Integrator"):
        hovi.load_trajectory(path, "pendulum")


def test_save_refuses_an_inconsistent_trajectory_and_writes_nothing(tmp_path):
    integ, traj, _ = saved(tmp_path)
    traj.q = np.zeros((6, 5))
    out = tmp_path / "bad.npz"
    with pytest.raises(ValueError, match=r"cannot save this trajectory \(nothing written\): q must have shape"):
        traj.save(out)
    assert not out.exists()


def test_good_files_still_round_trip_including_a_failed_last_step(tmp_path):
    integ = hovi.Integrator(hovi.examples.models.pendulum(32), s=1, dt=0.5)
    rng = np.random.default_rng(3)
    traj = integ.rollout(rng.uniform(-1.5, 1.5, 32), 50, qdot0=rng.uniform(-5, 5, 32), raise_on_failure=False)
    assert not traj.converged and len(traj.status) == traj.steps + 1
    traj.save(tmp_path / "failed.npz")
    back = hovi.load_trajectory(tmp_path / "failed.npz", integ)
    assert back.status == traj.status
    np.testing.assert_array_equal(back.q, traj.q)


# --- trajectory optimisation ---------------------------------------------------------------

def actuated(n=2):
    model = hovi.examples.models.pendulum(n)
    for j in range(n):
        model.add_actuator(j)
    return model


@pytest.mark.parametrize("kwargs, error, match", [
    ({"q_bounds": ([0, 0, 0], [1, 1, 1])}, ValueError, r"q_bounds \(lower\) must be a number or 2 numbers"),
    ({"u_bounds": (-1.0, [1, 1, 1])}, ValueError, r"u_bounds \(upper\) must be a number or 2 numbers"),
    ({"u_bounds": (-1.0, 1.0, 2.0)}, ValueError, r"u_bounds must be a pair \(lower, upper\)"),
    ({"u_bounds": 1.0}, ValueError, r"u_bounds must be a pair"),
    ({"q_bounds": (np.nan, 1.0)}, ValueError, r"q_bounds \(lower\) holds NaN"),
    ({"q_bounds": ("low", 1.0)}, ValueError, r"q_bounds \(lower\) must be an array of real numbers"),
    ({"q_bounds": (np.inf, np.inf)}, ValueError, "q_bounds: a lower bound of \\+inf"),
    ({"u_bounds": (1j, 2.0)}, ValueError, r"u_bounds \(lower\) must be real, got a complex number"),
    ({"N": True}, ValueError, "N must be a whole number"),
    ({"N": 2.5}, ValueError, "N must be a whole number"),
    ({"N": "10"}, ValueError, "N must be a whole number"),
    ({"T": "2"}, ValueError, "T must be a real number"),
    ({"T": np.nan}, ValueError, "T must be a finite number"),
    ({"T": -1.0}, ValueError, "T must be > 0"),
])
def test_problem_arguments_are_named(kwargs, error, match):
    args = {"N": 10, "T": 1.0, **kwargs}
    with pytest.raises(error, match=match):
        trajopt.Problem(actuated(), **args)


def test_states_references_and_costs_are_named():
    prob = trajopt.Problem(actuated(), 10, 1.0)
    with pytest.raises(ValueError, match="the initial configuration must be 2 finite numbers"):
        prob.initial_state([0.0, np.nan])
    with pytest.raises(ValueError, match="the initial configuration must be an array of real numbers, got complex"):
        prob.initial_state(np.array([0.0, 1j]))
    with pytest.raises(ValueError, match=r"StateTracking q_ref must be a number or a vector \(one per coordinate\), got shape \(2, 2\)"):
        trajopt.StateTracking(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="StateTracking q_ref must be an array of real numbers"):
        trajopt.StateTracking("upright")
    with pytest.raises(ValueError, match="TerminalCost weight must be non-negative"):
        trajopt.TerminalCost([0, 0], weight=-1.0)
    with pytest.raises(ValueError, match="ControlEffort weight must be finite"):
        trajopt.ControlEffort(weight=np.nan)
    with pytest.raises(TypeError, match="CallbackCost fun must be callable"):
        trajopt.CallbackCost(3.0)


def swingup_with(cost):
    return swingups.pendulum_swingup(N=5).add_cost(cost)


@pytest.mark.parametrize("value, match", [
    (np.nan, r"cost 1 \(CallbackCost\) returned the cost value nan \(not finite\) at the initial guess"),
    ("cheap", "CallbackCost returned a cost value that is not a real number: 'cheap'"),
    (np.zeros(2), "CallbackCost returned a cost value that is not a real number"),
    (1j, "CallbackCost returned a cost value that is not a real number"),
])
def test_a_cost_returning_a_non_number_is_named(value, match):
    cost = trajopt.CallbackCost(lambda t, w, q, v, u: (value, np.zeros_like(q), np.zeros_like(v), np.zeros_like(u)))
    with pytest.raises(ValueError, match=match):
        trajopt.solve(swingup_with(cost), verbose=False)


def test_a_cost_term_of_another_kind_returning_garbage_is_named():

    class Broken(trajopt.Cost):
        def __call__(self, s):
            return 1.0, np.zeros((3, 3)), np.zeros_like(s.v), np.zeros_like(s.u)

    with pytest.raises(ValueError, match=r"cost 1 \(Broken\): its gradient dq must have shape"):
        trajopt.solve(swingup_with(Broken()), verbose=False)
    with pytest.raises(ValueError, match=r"StateTracking q_ref .* must have shape \(\d+, 1\), got shape \(\d+, 2\)"):
        trajopt.solve(swingup_with(trajopt.StateTracking(lambda t: np.zeros((len(t), 2)))), verbose=False)
    with pytest.raises(ValueError, match=r"TerminalCost q_target must be a number or 1 numbers, got shape \(2,\)"):
        trajopt.solve(swingup_with(trajopt.TerminalCost([0.0, 1.0])), verbose=False)
    with pytest.raises(ValueError, match=r"StateTracking q_ref must be 1 values .*got shape \(3,\)"):
        trajopt.solve(swingup_with(trajopt.StateTracking([0.0, 1.0, 2.0])), verbose=False)


@pytest.mark.parametrize("guess, match", [
    (0.5, "guess must be None, 'rollout', 'linear', a Result or"),
    ("rolout", "guess must be None, 'rollout', 'linear'"),
    ((lambda t: np.zeros((len(t), 1)),), "a tuple guess must be three functions"),
    ((lambda t: np.zeros((len(t), 2)), lambda t: np.zeros((len(t), 1)), lambda t: np.zeros((len(t), 1))),
     r"guess q\(t\) at the \d+ times t must have shape \(\d+, 1\), got shape \(\d+, 2\)"),
    ((lambda t: np.zeros((len(t), 1)), lambda t: np.zeros(len(t)), lambda t: np.zeros((len(t), 1))),
     r"guess v\(t\) at the \d+ times t must have shape"),
    ((lambda t: np.zeros((len(t), 1)), lambda t: np.zeros((len(t), 1)), lambda t: np.full((len(t), 1), np.nan)),
     r"guess u\(t\) at the \d+ times t must be finite"),
    ((lambda t: np.zeros((len(t), 1)), lambda t: np.zeros((len(t), 1)), lambda t: 0.0),
     r"guess u\(t\) at the \d+ times t must have shape"),
])
def test_bad_guesses_are_named(guess, match):
    with pytest.raises(ValueError, match=match):
        trajopt.solve(swingups.pendulum_swingup(N=5), guess=guess, verbose=False)


def test_a_result_of_another_problem_is_refused_as_a_guess():
    small = trajopt.solve(swingups.pendulum_swingup(N=5), trajopt.VI(s=1), verbose=False, options={"max_iter": 2})
    with pytest.raises(ValueError, match=r"guess: the Result comes from another problem .*N = 5.*N = 8.*as_guess"):
        trajopt.solve(swingups.pendulum_swingup(N=8), trajopt.VI(s=1), guess=small, verbose=False)
    with pytest.raises(ValueError, match="guess: the Result comes from another problem or transcription"):
        trajopt.solve(swingups.pendulum_swingup(N=5), trajopt.VI(s=2), guess=small, verbose=False)


@pytest.mark.parametrize("options, error, match", [
    ({"tols": 1e-6}, ValueError, "unknown IPOPT option 'tols' \\(did you mean 'tol'\\?\\)"),
    ({"max_itr": 10}, ValueError, "unknown IPOPT option 'max_itr' \\(did you mean 'max_iter'"),
    ({"max_iter": 10.5}, ValueError, "IPOPT option 'max_iter' takes an integer, got a number 10.5"),
    ({"tol": "small"}, ValueError, "IPOPT option 'tol' takes a number, got a string 'small'"),
    ({"mu_strategy": "fastest"}, ValueError, "IPOPT refused the value 'fastest' of option 'mu_strategy'"),
    ({"tol": [1e-6]}, ValueError, "IPOPT option 'tol': the value must be a string, an integer or a number"),
    ({1: 2}, TypeError, "IPOPT option names are strings"),
    ("tol=1e-6", TypeError, "options must be a dict"),
])
def test_bad_ipopt_options_are_named(options, error, match):
    with pytest.raises(error, match=match):
        trajopt.Ipopt(options)
    with pytest.raises(error, match=match):
        trajopt.solve(swingups.pendulum_swingup(N=5), options=options, verbose=False)


def test_numpy_scalars_are_good_ipopt_options():
    r = trajopt.solve(swingups.pendulum_swingup(N=5), options={"max_iter": np.int64(3), "tol": np.float32(1e-6)},
                      verbose=False)
    assert r.iterations <= 3


# --- contact --------------------------------------------------------------------------------

@pytest.mark.parametrize("make, error, match", [
    (lambda: Terrain(ground=np.nan), ValueError, "Terrain ground must be a finite number, got nan"),
    (lambda: Terrain(ground="flat"), ValueError, "Terrain ground must be a real number"),
    (lambda: Terrain(ground=1j), ValueError, "Terrain ground must be a real number"),
    (lambda: Gap(np.nan, 1.0), ValueError, "Gap.x0 must be a finite number"),
    (lambda: Gap(0.0, "1"), ValueError, "Gap.x1 must be a real number"),
    (lambda: Gap(0.0, 1.0, depth=np.inf), ValueError, "Gap.depth must be a finite number"),
    (lambda: Box(0.0, 1.0, top=np.nan), ValueError, "Box.top must be a finite number"),
    (lambda: Box(0.0, 1.0, top=0.1, y0=np.nan), ValueError, "Box.y0 must be a finite number|Box.y0"),
    (lambda: Terrain(gaps=[(0.0, 1.0)]), TypeError, r"Terrain gaps\[0\] must be a hovi.contact.Gap"),
    (lambda: Terrain(boxes=Box(0, 1, 0.1)), TypeError, "Terrain boxes must be a list of hovi.contact.Box"),
])
def test_bad_terrain_is_named(make, error, match):
    with pytest.raises(error, match=match):
        make()


def test_a_terrain_is_not_changed_after_construction():
    import dataclasses
    g = Gap(0.0, 1.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        g.depth = np.nan
    with pytest.raises(ValueError, match=r"Gap.depth must be a finite number"):
        Gap(0.0, 1.0, np.nan)


@pytest.mark.parametrize("mu, error, match", [
    (-0.1, ValueError, "mu must be >= 0"), (np.nan, ValueError, "mu must be a finite number"),
    (np.inf, ValueError, "mu must be a finite number"), (1e300, ValueError, "mu must be at most 1000"),
    ("0.5", ValueError, "mu must be a real number"), (None, ValueError, "mu must be a real number"),
    (True, ValueError, "mu must be a real number"),
])
def test_bad_friction_is_named(mu, error, match):
    with pytest.raises(error, match=match):
        Contacts(planar_point_mass(), [("mass", (0, 0, 0))], Terrain(), mu=mu, plane="xz")


def test_bad_contact_points_and_bodies_are_named():
    model, terrain = planar_point_mass(), Terrain()
    for points, error, match in (
            ([("foot", (0, 0, 0))], ValueError, "unknown contact body 'foot' \\(the model's bodies: slider, mass\\)"),
            ([(1.5, (0, 0, 0))], TypeError, "contact body must be a body name or an integer index, got float"),
            ([(None, (0, 0, 0))], TypeError, "contact body must be a body name or an integer index"),
            ([("mass", (0, 0, "x"))], ValueError, r"contact point 0 \('mass'\)"),
            ([("mass", (0, 0, 1j))], ValueError, r"contact point 0 \('mass'\) must be an array of real numbers"),
            ([("mass", (0, 0, np.inf))], ValueError, "3 finite numbers"),
            ([5], ValueError, "contact point 0: a contact point is"),
            ("mass", TypeError, "points must be a list")):
        with pytest.raises(error, match=match):
            Contacts(model, points, terrain, mu=0.5, plane="xz")


def test_contact_forces_refuse_the_wrong_input_width():
    contacts = Contacts(planar_point_mass(), [("mass", (0, 0, 0))], Terrain(), mu=0.5, plane="xz")
    m = contacts.with_inputs.n_controls
    assert contacts.forces(np.ones((3, m))).shape == (3, 1, 3)
    for u in (np.ones((3, m + 1)), np.ones((3, m - 1)), np.ones(m + 2), np.ones((2, 3, m))):
        with pytest.raises(ValueError, match=rf"u must be the controls of the contact model, \(P, {m}\)"):
            contacts.forces(u)
    with pytest.raises(ValueError, match="u must be finite"):
        contacts.forces(np.full(m, np.nan))
    with pytest.raises(ValueError, match=r"q must have shape \(2,\)"):
        contacts.gaps(np.zeros(3))


def test_flat_foot_friction_and_body_are_named():
    from test_flat_foot import block_model
    model = block_model()
    q0 = np.array([0.0, 0.0, 0.1, 0.0, 0.0, 0.0])
    for kwargs, error, match in (({"mu": 1e300}, ValueError, "mu must be at most 1000"),
                                 ({"mu": 0.0}, ValueError, "mu must be > 0"),
                                 ({"body": 0.0}, TypeError, "foot body must be a body name or an integer index"),
                                 ({"X": "wide"}, ValueError, "the sole's half-size X must be a real number")):
        args = {"body": "block", "centre": (0, 0, -0.1), "X": 0.1, "Y": 0.1, "mu": 0.5, "q0": q0, **kwargs}
        with pytest.raises(error, match=match):
            FlatFoot(model, **args)


@pytest.mark.parametrize("args, error, match", [
    (("foot", [0.0, 0.0]), ValueError, r"ContactPoint point must have shape \(3,\), got shape \(2,\)"),
    (("foot", (0.0, 0.0, np.nan)), ValueError, "ContactPoint point must be finite, got nan"),
    (("foot", (0, 0, 0), -0.01), ValueError, "ContactPoint radius must be >= 0"),
    ((True, (0, 0, 0)), TypeError, "ContactPoint body must be a body name or an integer index"),
    (("foot", (0, 0, 0), 0.0, 3), TypeError, "ContactPoint name must be a string"),
])
def test_a_contact_point_is_checked_when_made(args, error, match):
    from hovi.contact import ContactPoint
    with pytest.raises(error, match=match):
        ContactPoint(*args)
