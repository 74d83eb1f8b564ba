"""The typed argument classes of the bindings (numpy.typing.ArrayLike, int | str, ... in the stubs)
accept what the untyped ones did and still reject bad input with clear exceptions."""
import numpy as np
import pytest

import hovi


def test_array_arguments_accept_lists_tuples_and_arrays():
    model = hovi.examples.models.pendulum(3)
    M = model.mass_matrix(np.zeros(3))
    assert np.array_equal(model.mass_matrix([0, 0, 0]), M) and np.array_equal(model.mass_matrix((0.0, 0.0, 0.0)), M)


@pytest.mark.parametrize("q,message", [("abc", "q must be an array of real numbers"),
                                       ([0.0, 0.0], r"q must be a 1-D array of length 3, got shape \(2,\)"),
                                       ([0.0, np.nan, 0.0], "q contains NaN or infinity")])
def test_array_arguments_reject_bad_input(q, message):
    with pytest.raises(ValueError, match=message):
        hovi.examples.models.pendulum(3).mass_matrix(q)


def test_point_constraint_needs_a_target():
    """`target` follows the defaulted `point`, so it has a default (None) too; leaving it out is an error."""
    model = hovi.examples.models.pendulum(3)
    with pytest.raises(ValueError, match=r"add_point_constraint: target \(a world point, \(3,\)\) is required"):
        model.add_point_constraint(2, point=[0, 0, -0.5])
    assert model.n_constraints == 0
    model.add_point_constraint(2, [0, 0, -0.5], [0, 0, -1.5], "z")  # positional, as before
    assert model.n_constraints == 1


def test_joint_and_body_arguments_by_index_or_name():
    model = hovi.examples.models.acrobot()
    model.add_spring("shoulder", 1.0)
    model.add_spring(1, 2.0)
    assert np.array_equal(model.stiffness, [1.0, 2.0])
    with pytest.raises(hovi.ModelError, match="no joint named 'knee'"):
        model.add_damper("knee", 1.0)
