"""Trajectory optimisation with hovi's integrators as the dynamics (the paper's Sec. 6).

A ``Problem`` says what to optimise (model, horizon, boundary states, bounds, costs, path and
input constraints, contacts) and no solver changes it; a transcription (``VI(s)``, the Galerkin VI
of order 2s, or ``HermiteSimpson(form)``, implicit / explicit collocation for comparison) turns it
into an ``NLP``; a solver (``Ipopt``; ``ContactHomotopy`` for contacts, over ``Ipopt``) solves it::

    from hovi import trajopt
    prob = trajopt.Problem(model, N=40, T=2.0)
    prob.initial_state(q0).final_state(qT, qdot=zeros)
    prob.add_cost(trajopt.ControlEffort())
    result = trajopt.solve(prob, trajopt.VI(s=2))   # or trajopt.HermiteSimpson("implicit")
    traj = result.replay()                          # the same integrator, simulating the controls
"""
from .complementarity import Sides, ComplementarityRelaxation, ContactRows
from .costs import CallbackCost, ControlEffort, Cost, StateTracking, TerminalCost
from .hermite_simpson import HermiteSimpson
from .input_constraints import InputConstraint
from .nlp import NLP
from .path_constraints import BodyPoint, CallbackPathConstraint, Clearance, PathConstraint, PoseHeld
from .problem import Problem
from .result import Result
from .solvers import FDDP, ContactHomotopy, Ipopt, NLPSolver, Solver, solve, solve_contact
from .transcription import Guess, Transcription, TranscriptionMethod
from .transcriptions import DEFAULT_TRANSCRIPTION
from .variational import VI

__all__ = ["Problem", "VI", "HermiteSimpson", "DEFAULT_TRANSCRIPTION", "TranscriptionMethod", "Transcription",
           "NLP", "Solver", "NLPSolver", "Ipopt", "FDDP", "ContactHomotopy", "solve", "solve_contact", "Result", "Guess",
           "Cost", "ControlEffort", "StateTracking", "TerminalCost", "CallbackCost", "PathConstraint", "BodyPoint",
           "Clearance", "CallbackPathConstraint", "PoseHeld", "InputConstraint", "ContactRows", "Sides",
           "ComplementarityRelaxation"]
