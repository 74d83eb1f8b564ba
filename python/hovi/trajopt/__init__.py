"""Trajectory optimisation with hovi's integrators as the dynamics (the paper's Sec. 6).

A ``Problem`` says what to optimise (model, horizon, boundary states, bounds, costs, path
constraints); a transcription turns it into an NLP (the Galerkin VI of any order, or implicit /
explicit Hermite-Simpson collocation for comparison); ``solve`` hands the NLP to IPOPT::

    from hovi import trajopt
    prob = trajopt.Problem(model, N=40, T=2.0)
    prob.initial_state(q0).final_state(qT, qdot=zeros)
    prob.add_cost(trajopt.ControlEffort())
    result = trajopt.solve(prob, "vi", s=2)        # or "hs-implicit", "hs-explicit"
    traj = result.replay()                          # the same integrator, simulating the controls
"""
from .contact_solve import solve_contact
from .costs import CallbackCost, ControlEffort, Cost, StateTracking, TerminalCost
from .ipopt import solve, transcribe
from .input_constraints import InputConstraint
from .nlp import NLP
from .path_constraints import BodyPoint, CallbackPathConstraint, Clearance, PathConstraint, PoseHeld
from .problem import Problem
from .result import Result

__all__ = ["Problem", "solve", "solve_contact", "transcribe", "NLP", "Result", "Cost", "ControlEffort", "StateTracking", "TerminalCost",
           "CallbackCost", "PathConstraint", "BodyPoint", "Clearance", "CallbackPathConstraint", "PoseHeld",
           "InputConstraint"]
