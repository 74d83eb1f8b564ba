"""Solvers of a transcribed Problem, as adapters with one interface
(``solve(problem, transcription, guess) -> Result``): ``Ipopt`` on the NLP, ``FDDP`` shooting on the VI, and ``ContactHomotopy``,
the contact-implicit strategy over ``Ipopt``. ``solve`` and ``solve_contact`` are their one-call
entries."""
from .base import NLPSolver, Solver
from .contact_homotopy import ContactHomotopy, solve_contact
from .fddp import FDDP
from .ipopt import Ipopt, solve

__all__ = ["Solver", "NLPSolver", "Ipopt", "FDDP", "ContactHomotopy", "solve", "solve_contact"]
