"""Feedback control on hovi's integrator: LQR at an equilibrium and time-varying LQR along a
trajectory from the exact step Jacobians, MPC with the FDDP solver on the VI, and closed-loop runs
in C++ (saturation, pushes, model mismatch, contacts, Monte-Carlo batches)::

    from hovi import control
    policy = control.lqr(integrator, q_upright)                  # or control.tvlqr(integrator, traj, u)
    run = control.simulate(plant, policy, q0, steps=500, pushes=[control.Push(1.0, "pole", [0.5, 0, 0])])
"""
from .closed_loop import ClosedLoop, Push, simulate, simulate_batch
from .lqr import equilibrium_controls, lqr, rest_momentum, riccati_policy, tvlqr
from .mpc import MPC, MpcRun
from .policy import Policy
from .statics import static_controls

__all__ = ["Policy", "lqr", "tvlqr", "riccati_policy", "equilibrium_controls", "rest_momentum", "static_controls", "Push", "ClosedLoop", "simulate", "simulate_batch", "MPC", "MpcRun"]
