"""A trajectory-optimisation problem, independent of how it is transcribed and solved: the model,
the horizon, boundary conditions, bounds, costs, path and input constraints and contacts. No
solver changes it."""
from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .. import _core
from .._checks import real_array, real_number, whole_number
from ..contact.contacts import Contacts, check_robot
from ..contact.flat_foot import Stance, WrenchCone
from .costs import Cost
from .input_constraints import InputConstraint
from .path_constraints import PathConstraint, PoseHeld


class Problem:
    """Minimise the sum of ``costs`` over a fixed horizon ``T`` split into ``N`` stages, subject to
    the model's dynamics (transcribed by the solver's chosen transcription), the boundary
    conditions, bounds and path constraints.

    Bounds default to the model's URDF metadata: joint limits on q, effort limits on the controls
    of single-joint actuators (|u_k| <= effort_j / |gear|); override with ``q_bounds`` and
    ``u_bounds`` ((lower, upper) arrays or scalars; None for the default).

    controls: 'per_point' (a value at every sample point, continuous across stages) or 'held'
    (one value per stage).
    """

    def __init__(self, model: _core.Model, N: int, T: float, *, controls: str = "per_point",
                 q_bounds: tuple[npt.ArrayLike, npt.ArrayLike] | None = None,
                 u_bounds: tuple[npt.ArrayLike, npt.ArrayLike] | None = None):
        if not isinstance(model, _core.Model):
            raise TypeError(f"model must be a hovi.Model, got {type(model).__name__}")
        N = whole_number(N, "N", minimum=1)
        T = real_number(T, "T", minimum=0.0, strict_minimum=True)
        if not isinstance(controls, str) or controls not in ("per_point", "held"):
            raise ValueError(f"controls must be 'per_point' or 'held', got {controls!r}")
        self.model, self.N, self.T, self.controls = model, N, T, controls
        self.costs: list[Cost] = []
        self.path_constraints: list[PathConstraint] = []
        self.input_constraints: list[InputConstraint] = []
        self.contacts: Contacts | None = None  # see add_contacts
        self.q0 = self.qdot0 = self.qT = self.qdotT = None
        self.q_lower, self.q_upper = self._bounds(q_bounds, model.lower_limits, model.upper_limits, model.n, "q")
        self.u_lower, self.u_upper = self._bounds(u_bounds, *self._effort_bounds(), model.n_controls, "u")

    @property
    def dt(self) -> float:
        """The stage length T / N."""
        return self.T / self.N

    @staticmethod
    def _bounds(given, lo_default, hi_default, size, name):
        """(lower (size,), upper (size,)) from ``given`` = (lower, upper), each a number or ``size``
        numbers (+-inf allowed, not NaN, lower <= upper, lower < inf, upper > -inf)."""
        arg = f"{name}_bounds"
        if given is None:
            lo, hi = lo_default, hi_default
        else:
            if isinstance(given, (str, bytes)) or not hasattr(given, "__len__") or len(given) != 2:
                raise ValueError(f"{arg} must be a pair (lower, upper), each a number or {size} numbers, got {given!r}")
            lo, hi = given
        out = []
        for side, value in (("lower", lo), ("upper", hi)):
            v = real_array(value, f"{arg} ({side})", finite=False)
            if v.shape not in ((), (size,), (1,)):
                raise ValueError(f"{arg} ({side}) must be a number or {size} numbers (one per "
                                 f"{'joint' if name == 'q' else 'control'}), got shape {v.shape}")
            if np.any(np.isnan(v)):
                raise ValueError(f"{arg} ({side}) holds NaN at indices {np.nonzero(np.isnan(np.broadcast_to(v, (size,))))[0].tolist()}")
            out.append(np.broadcast_to(v, (size,)).copy())
        lo, hi = out
        if np.any(lo > hi):
            raise ValueError(f"{arg} with lower > upper at indices {np.nonzero(lo > hi)[0].tolist()}")
        if np.any(lo == np.inf) or np.any(hi == -np.inf):
            raise ValueError(f"{arg}: a lower bound of +inf or an upper bound of -inf leaves no value, at indices "
                             f"{np.nonzero((lo == np.inf) | (hi == -np.inf))[0].tolist()}")
        return lo, hi

    def _effort_bounds(self):
        """|u_k| <= effort_j / |gear| for a control acting on one joint j with a finite effort limit."""
        B, effort = self.model.actuation, self.model.effort_limits
        hi = np.full(self.model.n_controls, np.inf)
        for k in range(self.model.n_controls):
            joints = np.nonzero(B[:, k])[0]
            if len(joints) == 1 and np.isfinite(effort[joints[0]]) and effort[joints[0]] > 0:
                hi[k] = effort[joints[0]] / abs(B[joints[0], k])
        return -hi, hi

    def _state(self, q, qdot, what):
        n = self.model.n
        for name, value in (("configuration", q), ("velocity", qdot)):
            if value is None:
                continue
            a = real_array(value, f"the {what} {name}", finite=False)
            if a.shape != (n,) or not np.all(np.isfinite(a)):
                raise ValueError(f"the {what} {name} must be {n} finite numbers, got "
                                 f"{'shape ' + str(a.shape) if a.shape != (n,) else a.tolist()}")
            if np.abs(a).max() > 1e150:  # the model's limit (its arithmetic would overflow)
                raise ValueError(f"the {what} {name} has an entry beyond 1e150 in magnitude: {a.tolist()}")
        q = np.array(q, float)
        qdot = None if qdot is None else np.array(qdot, float)
        if self.model.n_constraints:
            h = self.model.constraint_values(q)
            if np.abs(h).max() > 1e-8:
                raise ValueError(f"the {what} configuration violates the model's constraints (|h| = "
                                 f"{np.abs(h).max():.2e}); use Integrator.project for a consistent state")
            if qdot is not None:
                v = self.model.constraint_jacobian(q) @ qdot
                if np.abs(v).max() > 1e-8 * (1 + np.abs(qdot).max()):
                    raise ValueError(f"the {what} velocity violates the model's constraints (|Dh qdot| = "
                                     f"{np.abs(v).max():.2e}); use Integrator.project for a consistent state")
        return q, qdot

    def initial_state(self, q0: npt.ArrayLike, qdot0: npt.ArrayLike | None = None) -> Problem:
        """Fix the initial configuration q0 (n,) and velocity qdot0 (n,) (default: at rest); returns self."""
        self.q0, self.qdot0 = self._state(q0, np.zeros(self.model.n) if qdot0 is None else qdot0, "initial")
        return self

    def final_state(self, q: npt.ArrayLike | None = None, qdot: npt.ArrayLike | None = None) -> Problem:
        """Fix the final configuration q (n,) and/or velocity qdot (n,) (a final velocity needs a final
        configuration); returns self."""
        if q is None and qdot is not None:
            raise ValueError("a final velocity needs a final configuration (give q as well, or use a TerminalCost)")
        self.qT, self.qdotT = (None, None) if q is None else self._state(q, qdot, "final")
        return self

    def add_cost(self, cost: Cost) -> Problem:
        """Add a cost term (ControlEffort, StateTracking, TerminalCost, CallbackCost); returns self."""
        if not isinstance(cost, Cost):
            raise TypeError(f"expected a hovi.trajopt cost term, got {type(cost).__name__}")
        self.costs.append(cost)
        return self

    def add_constraint(self, constraint: PathConstraint | InputConstraint | Stance | WrenchCone) -> Problem:
        """Add a path constraint (BodyPoint, Clearance, PoseHeld, CallbackPathConstraint), resolved
        against the model now, or an InputConstraint on the controls; a flat foot's ``stance()``
        becomes a PoseHeld and its ``cone()`` an InputConstraint. Returns self."""
        if isinstance(constraint, (Stance, WrenchCone)):
            check_robot(constraint.robot, self.model,
                        f"the flat foot's {'stance' if isinstance(constraint, Stance) else 'wrench cone'}")
        if isinstance(constraint, Stance):
            constraint = PoseHeld(constraint.body, constraint.q0, point=constraint.point, size=constraint.size)
        elif isinstance(constraint, WrenchCone):
            constraint = InputConstraint(constraint.A, constraint.lower, constraint.upper)
        if isinstance(constraint, InputConstraint):
            constraint.check(self.model.n_controls)
            self.input_constraints.append(constraint)
            return self
        if not isinstance(constraint, PathConstraint):
            raise TypeError(f"expected a hovi.trajopt path or input constraint, got {type(constraint).__name__}")
        self.path_constraints.append(constraint.bind(self.model))
        return self

    def add_contacts(self, contacts: Contacts) -> Problem:
        """Add rigid contacts with the terrain (``hovi.contact.Contacts``, built on this problem's
        robot; the Problem must be made with ``contacts.with_inputs``): their inputs get the bounds
        [0, inf) and the complementarity conditions are added to the NLP. Solve with
        ``hovi.trajopt.solve_contact``. Returns self."""
        if not isinstance(contacts, Contacts):
            raise TypeError(f"expected hovi.contact.Contacts, got {type(contacts).__name__}")
        if self.contacts is not None:
            raise ValueError("the problem has contacts already (put every contact point in one Contacts)")
        if contacts.with_inputs is not self.model:
            raise ValueError("build the Problem with contacts.with_inputs (the model with the contact force inputs)")
        if self.controls != "per_point":
            raise ValueError("contacts need controls='per_point' (a contact force at every control point)")
        lo, hi = contacts.input_bounds()
        self.u_lower[contacts.first_input:], self.u_upper[contacts.first_input:] = lo, hi
        self.contacts = contacts
        return self

    def check(self) -> None:
        """Raise ValueError if the problem is incomplete."""
        if self.q0 is None:
            raise ValueError("the problem has no initial state: call initial_state(q0, qdot0)")
        if not self.costs:
            raise ValueError("the problem has no cost: add one with add_cost (e.g. ControlEffort())")
        for name, q in (("initial", self.q0), ("final", self.qT)):
            if q is not None and (np.any(q < self.q_lower - 1e-12) or np.any(q > self.q_upper + 1e-12)):
                raise ValueError(f"the {name} configuration lies outside the joint bounds")
            if q is not None and self.contacts is not None:
                gaps = self.contacts.gaps(q)
                if gaps.min() < -1e-9:
                    c = int(np.argmin(gaps))
                    raise ValueError(f"the {name} configuration puts contact point {c} {-gaps[c]:.3g} below the terrain")
