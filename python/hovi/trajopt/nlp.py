"""The nonlinear program of a Problem under a transcription: objective and gradient from the cost
terms through the transcription's sample map; constraints and their sparse Jacobian from its C++
program (``program()``): the transcription, the path constraints on body points (one C++ block per
set of configurations they share), the contact complementarity rows (hovi.trajopt.complementarity,
under the relaxation it is given) and the linear boundary rows in C++, the path constraints written
in Python one vectorised call each. Knows nothing of the solver. Times its evaluations for the
solver's report."""
from __future__ import annotations

import time
import weakref

import numpy as np
import scipy.sparse as sp

from .. import _core
from .complementarity import ComplementarityRelaxation, ContactRows
from .costs import checked_cost
from .path_constraints import OnBodyPoints
from .problem import Problem
from .transcription import Transcription, TranscriptionMethod
from .transcriptions import DEFAULT_TRANSCRIPTION


class NLP:
    """The NLP of ``problem`` transcribed by ``transcription`` (a TranscriptionMethod such as
    ``VI(s=2)``, or a Transcription of that problem already made; ``NLP(tr)`` alone takes the
    problem from the Transcription ``tr``): variables x (n_variables,) within [lower, upper],
    constraints cl <= g(x) <= cu (n_constraints,) with a sparse Jacobian (jac_rows, jac_cols)
    (nnz,), and the objective; what a solver's callbacks evaluate.

    ``relaxation`` (a ``hovi.trajopt.ComplementarityRelaxation``) states the complementarity rows
    of a problem with contacts: their products bounded by epsilon, or one side of every pair
    fixed. A problem with contacts needs one that is not the exact conditions
    (``hovi.trajopt.solve_contact`` chooses them)."""

    def __init__(self, problem: Problem | Transcription, transcription: TranscriptionMethod | Transcription | None = None,
                 *, relaxation: ComplementarityRelaxation | None = None):
        if not isinstance(problem, (Problem, Transcription)):
            raise TypeError(f"problem must be a hovi.trajopt.Problem, got {type(problem).__name__}")
        if relaxation is not None and not isinstance(relaxation, ComplementarityRelaxation):
            raise TypeError(f"relaxation must be a hovi.trajopt.ComplementarityRelaxation, got {type(relaxation).__name__}")
        if isinstance(problem, Transcription):
            if transcription is not None:
                raise TypeError("give NLP(problem, transcription) or NLP(transcribed problem), not both")
            tr = problem
        elif isinstance(transcription, Transcription):
            if transcription.problem is not problem:
                raise ValueError("the Transcription given to NLP belongs to another problem")
            tr = transcription
        else:
            method = DEFAULT_TRANSCRIPTION if transcription is None else transcription
            if not isinstance(method, TranscriptionMethod):
                raise TypeError(f"transcription must be a hovi.trajopt.VI or HermiteSimpson, got {type(method).__name__}")
            tr = method.transcribe(problem)
        self.tr, self.problem, self.core = tr, tr.problem, tr.core
        self.transcription = tr
        self.relaxation = relaxation
        self.samples = tr.sample_map()
        self.lower, self.upper = tr.bounds()
        tq, offsets = tr.q_points()
        n, nv = tr.n, self.core.n_variables
        rows, cols = [np.asarray(a, dtype=np.int64) for a in self.core.structure]
        cl, cu = [np.zeros(self.core.n_constraints)], [np.zeros(self.core.n_constraints)]
        row0 = self.core.n_constraints
        self.paths = []  # (constraint, times (P,), configuration points (P, K), weights (P, K))
        for c in self.problem.path_constraints:
            idx = c.points(tq)
            groups = [(tq[idx], idx[:, None], np.ones((len(idx), 1)))]
            if c.between:
                ts, points, weights = tr.q_samples(c.between)
                keep = c.in_window(ts)
                groups.append((ts[keep], points[keep], weights[keep]))
            r = len(c.lower)
            for t, points, weights in groups:
                self.paths.append((c, t, points, weights))
                P, K = points.shape
                rows_c = np.repeat(row0 + np.arange(P * r), K * n)            # row (p, i): columns (k, j)
                cols_c = np.repeat((offsets[points][:, :, None] + np.arange(n)).reshape(P, 1, K * n), r, 1).ravel()
                rows, cols = np.concatenate([rows, rows_c]), np.concatenate([cols, cols_c])
                cl.append(np.tile(c.lower, P))
                cu.append(np.tile(c.upper, P))
                row0 += P * r
        self._group_body_points()
        self.contact_rows = None
        if self.problem.contacts is not None:
            if relaxation is None or relaxation.exact:
                raise ValueError("a problem with contacts needs hovi.trajopt.solve_contact (or an NLP with a "
                                 "relaxation, ComplementarityRelaxation(epsilon > 0) or sides): IPOPT cannot "
                                 "solve the exact complementarity conditions directly")
            cr = self.contact_rows = ContactRows(self.problem.contacts, tr, relaxation.epsilon, relaxation.sides)
            fixed = cr.fixed_inputs()
            self.lower[fixed] = self.upper[fixed] = 0.0
            rows, cols = np.concatenate([rows, row0 + cr.rows]), np.concatenate([cols, cr.cols])
            cl.append(cr.lower)
            cu.append(cr.upper)
            row0 += cr.count
        A_eq, b = tr.linear_rows()
        A_in, lower_in, upper_in = self._input_rows(tr)
        self.A = sp.vstack([A_eq, A_in]).tocsr()
        A = self.A.tocoo()
        rows, cols = np.concatenate([rows, row0 + A.row]), np.concatenate([cols, A.col])
        cl += [b, lower_in]
        cu += [b, upper_in]
        self.jac_rows, self.jac_cols = rows, cols
        self.cl, self.cu = np.concatenate(cl), np.concatenate(cu)
        self.n_variables, self.n_constraints = nv, len(self.cl)
        self.offsets = offsets
        self.eval_seconds = 0.0  # time in constraints() and jacobian()
        self._program = None
        bad = np.nonzero(self.lower > self.upper)[0]
        if len(bad):
            raise ValueError(f"inconsistent bounds on {len(bad)} variables (e.g. a boundary state outside the "
                             f"joint or control bounds)")

    def _group_body_points(self):
        """Gathers the path constraints on body points (OnBodyPoints) by the configurations they are
        evaluated at, into ``_point_groups``: (points, weights, bodies, local, their rows' forms
        stacked (c (R,), L and D (R, M, 3)), the points idx (R, M) each row reads, the group's first
        output value and Jacobian value); and where the groups' outputs, then the other constraints'
        (``_rest_values``, ``_rest_jac`` on), go among the NLP's path rows (constraint by constraint):
        ``_path_place`` (values) and ``_path_jac_place`` (Jacobian)."""
        groups, rest, n = {}, [], self.tr.n
        for e, (c, _, points, weights) in enumerate(self.paths):
            if not isinstance(c, OnBodyPoints):
                rest.append(e)
                continue
            key = (points.shape, points.tobytes(), weights.tobytes())
            groups.setdefault(key, (points, weights, []))[2].append(e)
        self._point_groups, self._path_rest = [], rest
        where = {}   # grouped entry -> (its group's offsets in the values and the Jacobian, the group's rows, its first row)
        at_values = at_jac = 0
        for points, weights, members in groups.values():
            forms = [self.paths[e][0].form() for e in members]
            M, R = max(L.shape[1] for _, L, _ in forms), sum(len(c) for c, _, _ in forms)
            idx, L, D = np.zeros((R, M), np.int64), np.zeros((R, M, 3)), np.zeros((R, M, 3))
            bodies, local, row = [], [], 0
            for e, (c0, Le, De) in zip(members, forms):
                r, m = Le.shape[:2]
                idx[row:row + r, :m] = len(bodies) + np.arange(m)
                L[row:row + r, :m], D[row:row + r, :m] = Le, De
                where[e] = (at_values, at_jac, R, row)
                bodies.extend(self.paths[e][0].bodies)
                local.extend(self.paths[e][0].local)
                row += r
            c = np.concatenate([c0 for c0, _, _ in forms])
            self._point_groups.append((points, weights, bodies, np.array(local), (c, L, D), idx, at_values, at_jac))
            P, K = points.shape
            at_values, at_jac = at_values + P * R, at_jac + P * R * K * n
        values, jac = [], []
        self._rest_values, self._rest_jac = at_values, at_jac
        for e, (c, _, points, _) in enumerate(self.paths):
            P, K = points.shape
            r = len(c.lower)
            if e in where:
                v0, j0, R, row = where[e]
                i = (np.arange(P)[:, None] * R + row + np.arange(r)).ravel()          # (p, i) in the group's (P, R)
                values.append(v0 + i)
                jac.append(j0 + (i[:, None] * (K * n) + np.arange(K * n)).ravel())    # (p, i, k, j)
            else:
                values.append(at_values + np.arange(P * r))
                jac.append(at_jac + np.arange(P * r * K * n))
                at_values, at_jac = at_values + P * r, at_jac + P * r * K * n
        # values and jac list the outputs row by row of the NLP; their inverses place each output
        self._path_place = np.argsort(np.concatenate([np.zeros(0, np.int64), *values]))
        self._path_jac_place = np.argsort(np.concatenate([np.zeros(0, np.int64), *jac]))

    def _configurations(self, x, points, weights):
        """The configurations (P, n) at x: sum_k weights[p, k] q(points[p, k])."""
        return np.einsum("pk,pkj->pj", weights, x[self.offsets[points][:, :, None] + np.arange(self.tr.n)])

    def _input_rows(self, tr: Transcription):
        """The input constraints at every control value u_j (offsets u_off + j m): (A (R, n_variables)
        sparse, lower (R,), upper (R,))."""
        blocks, lower, upper, nv = [], [np.zeros(0)], [np.zeros(0)], self.core.n_variables
        offsets = tr.u_off + np.arange(tr.n_u) * tr.m
        for c in self.problem.input_constraints:
            block = sp.kron(sp.eye(tr.n_u), sp.csr_matrix(c.A), format="csr")     # (n_u r, n_u m)
            shift = sp.csr_matrix((np.ones(tr.n_u * tr.m), (np.arange(tr.n_u * tr.m),
                                   (offsets[:, None] + np.arange(tr.m)).ravel())), (tr.n_u * tr.m, nv))
            blocks.append(block @ shift)
            lower.append(np.tile(c.lower, tr.n_u))
            upper.append(np.tile(c.upper, tr.n_u))
        A = sp.vstack(blocks) if blocks else sp.csr_matrix((0, nv))
        return A, np.concatenate(lower), np.concatenate(upper)

    @property
    def nnz(self) -> int:
        """Number of nonzeros of the constraint Jacobian."""
        return len(self.jac_rows)

    def _timed(self, f, x):
        t0 = time.perf_counter()
        out = f(x)
        self.eval_seconds += time.perf_counter() - t0
        return out

    def _cost_terms(self, x: np.ndarray, finite: bool = False, which: list[int] | None = None):
        """Each cost term's (value, dq, dv, du) at x (the terms of indices ``which``, default all),
        checked (``costs.checked_cost``: a real value and gradients of the samples' shapes; all finite
        with ``finite``)."""
        s = self.samples.evaluate(x)
        costs = self.problem.costs
        return [checked_cost(costs[i], s, f"cost {i} ({type(costs[i]).__name__})", finite=finite)
                for i in (range(len(costs)) if which is None else which)]

    def objective(self, x: np.ndarray) -> float:
        """The total cost at x (n_variables,)."""
        return float(sum(value for value, _, _, _ in self._cost_terms(x)))

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """The cost's gradient (n_variables,) at x (n_variables,)."""
        return self._pulled_back(self._cost_terms(x))

    def _pulled_back(self, terms) -> np.ndarray:
        """The gradient (n_variables,) in x of cost terms' (value, dq, dv, du)."""
        g = np.zeros(self.n_variables)
        for _, dq, dv, du in terms:
            g += self.samples.pullback(dq, dv, du)
        return g

    def check_start(self, x: np.ndarray) -> None:
        """Raise the errors of the costs, path constraints and dynamics at a starting point x
        (n_variables,) before a solver runs: x finite, every cost term a finite real value with
        finite gradients of the right shapes (ValueError naming the term), constraints and
        Jacobian evaluable."""
        x = np.asarray(x)
        if x.shape != (self.n_variables,):
            raise ValueError(f"guess: the starting point must have {self.n_variables} variables, got shape {x.shape}")
        if not np.all(np.isfinite(x)):
            bad = int(np.argmax(~np.isfinite(x)))
            raise ValueError(f"guess: the starting point holds NaN or infinity (variable {bad} of {self.n_variables}, "
                             f"{self.transcription.describe_variable(bad)})")
        try:
            self._cost_terms(x, finite=True)
        except ValueError as e:
            raise ValueError(f"{e} at the initial guess") from None
        self.constraints(x)
        self.jacobian(x)

    def _python_paths(self, x, with_jacobian):
        """The values, or Jacobian values, of the path constraints written in Python (not on body
        points), in their order (``_rest_values`` on)."""
        model, out = self.problem.model, [np.zeros(0)]
        for e in self._path_rest:
            c, t, points, weights = self.paths[e]
            values, jac = c.evaluate(model, t, self._configurations(x, points, weights))
            out.append(np.einsum("pk,prj->prkj", weights, jac).ravel() if with_jacobian else values.ravel())
        return np.concatenate(out)

    def constraints(self, x: np.ndarray) -> np.ndarray:
        """g(x) (n_constraints,): dynamics, path constraints, contact rows and linear boundary rows, at x (n_variables,)."""
        return self._timed(self.program().constraints, x)

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """The Jacobian's values (nnz,) at x (n_variables,), in (jac_rows, jac_cols) order."""
        return self._timed(self.program().jacobian, x)

    def violation(self, x: np.ndarray) -> float:
        """Largest violation of the constraints and bounds at x (n_variables,)."""
        g = self.constraints(x)
        return float(max(np.max(np.maximum(self.cl - g, 0), initial=0), np.max(np.maximum(g - self.cu, 0), initial=0),
                         np.max(np.maximum(self.lower - x, 0), initial=0), np.max(np.maximum(x - self.upper, 0), initial=0)))

    def program(self) -> _core.trajopt.Program:
        """This NLP as a C++ program (``hovi._core.trajopt.Program``, built once): the costs that give
        their ``curvature`` as weighted squares c + sum_i d_i (S x - r)_i^2 / 2, the transcription, the
        path constraints on body points and the contact rows (C++ row blocks with their own
        Hessians) and the linear rows in C++; the other costs and path constraints through the
        methods of a ``PythonTerms``, one call per evaluation. What the IPOPT adapter (solvers/_ipopt) solves."""
        if self._program is None:
            nv, s = self.n_variables, self.samples
            zero = s.evaluate(np.zeros(nv))
            c0, S, r, d, others = 0.0, [sp.csr_matrix((0, nv))], [np.zeros(0)], [np.zeros(0)], []
            for i, cost in enumerate(self.problem.costs):
                squares = self._squares(cost, i, zero)
                if squares is None:
                    others.append(i)
                    continue
                c0 += squares[0]
                for part, where in zip((S, r, d), squares[1:]):
                    part.append(where)
            rows0, nnz0 = self.core.n_constraints, self.core.nnz
            terms = PythonTerms(self, others)
            csr = [(M.indptr.astype(np.int32), M.indices.astype(np.int32), M.data) for M in (sp.vstack(S).tocsr(), self.A)]
            rest_rows = rows0 + self._path_place[self._rest_values:]
            rest_entries = nnz0 + self._path_jac_place[self._rest_jac:]
            has_rest = len(rest_rows) > 0
            self._program = _core.trajopt.Program(
                self.core, c0, csr[0], np.concatenate(r), np.concatenate(d), csr[1],
                self.jac_rows.astype(np.int32), self.jac_cols.astype(np.int32), self._blocks(),
                terms.cost if others else None, terms.constraints if has_rest else None,
                terms.jacobian if has_rest else None, rest_rows.astype(np.int32), rest_entries.astype(np.int32))
        return self._program

    def _blocks(self) -> list:
        """The C++ row blocks with their places (block, rows, entries): one per group of body-point
        path constraints, and the contact rows."""
        model, nv, n = self.problem.model, self.n_variables, self.tr.n
        rows0, nnz0 = self.core.n_constraints, self.core.nnz
        blocks = []
        for points, weights, bodies, local, (c, L, D), idx, v0, j0 in self._point_groups:
            (P, K), R = points.shape, len(c)
            block = _core.trajopt.BodyPointRows(model, nv, self.offsets[points].astype(np.int32), weights, bodies, local,
                                                c, L.reshape(-1, 3), D.reshape(-1, 3), idx.astype(np.int32))
            blocks.append((block, (rows0 + self._path_place[v0:v0 + P * R]).astype(np.int32),
                           (nnz0 + self._path_jac_place[j0:j0 + P * R * K * n]).astype(np.int32)))
        if self.contact_rows is not None:
            cr = self.contact_rows
            rows0, nnz0 = rows0 + len(self._path_place), nnz0 + len(self._path_jac_place)
            blocks.append((cr.block(nv), np.arange(rows0, rows0 + cr.count, dtype=np.int32),
                           np.arange(nnz0, nnz0 + len(cr.rows), dtype=np.int32)))
        return blocks

    def _squares(self, cost, i: int, zero):
        """A cost term with a ``curvature`` h as weighted squares of samples less references: (c, S, r,
        d) with cost(x) = c + sum d (S x - r)^2 / 2 (r = -gradient / h at x = 0); None for a term
        without a curvature, or with a linear part where h = 0 (not a sum of squares)."""
        h = cost.curvature(zero)
        if h is None:
            return None
        value, dq, dv, du = checked_cost(cost, zero, f"cost {i} ({type(cost).__name__})", finite=True)
        S, r, d = [], [], []
        for Sx, hx, gx in zip((self.samples.Sq, self.samples.Sv, self.samples.Su), h, (dq, dv, du)):
            hx, gx = np.ravel(hx), np.ravel(gx)
            if np.any((hx == 0) & (gx != 0)) or np.any(hx < 0):
                return None
            rows = np.nonzero(hx > 0)[0]
            S.append(Sx[rows])
            d.append(hx[rows])
            r.append(-gx[rows] / hx[rows])
        d, r = np.concatenate(d), np.concatenate(r)
        return value - 0.5 * float(d @ (r * r)), sp.vstack(S), r, d


class PythonTerms:
    """What the C++ program of an NLP leaves to Python: the costs without a ``curvature``
    (``cost(x) -> (value, gradient)``), and the path constraints written in Python
    (``constraints(x)``, ``jacobian(x)``), each one vectorised call. Holds its NLP weakly (the NLP
    holds the program)."""

    def __init__(self, nlp: NLP, costs: list[int]):
        self._nlp, self.costs = weakref.ref(nlp), costs

    @property
    def nlp(self) -> NLP:
        nlp = self._nlp()
        if nlp is None:
            raise RuntimeError("the NLP of this program no longer exists")
        return nlp

    def cost(self, x: np.ndarray) -> tuple[float, np.ndarray]:
        terms = self.nlp._cost_terms(x, which=self.costs)
        return float(sum(value for value, _, _, _ in terms)), self.nlp._pulled_back(terms)

    def constraints(self, x: np.ndarray) -> np.ndarray:
        return self.nlp._python_paths(x, False)

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        return self.nlp._python_paths(x, True)
