"""What a trajectory-optimisation solver is: ``solve(problem, transcription, guess) -> Result``.

``NLPSolver`` is a solver of the transcribed NLP (``hovi.trajopt.NLP``): it only adds
``solve_nlp(nlp, guess)`` (IPOPT: ``Ipopt``). A solver that works on the problem's structure
instead of a generic NLP (a shooting method such as FDDP) implements ``solve`` itself and uses
the transcription for its layout; neither kind changes the transcriptions or the Problem."""
from __future__ import annotations

import time

from ..nlp import NLP
from ..problem import Problem
from ..result import Result
from ..transcription import Guess, TranscriptionMethod
from ..transcriptions import DEFAULT_TRANSCRIPTION


class Solver:
    """Base of the solvers: ``solve(problem, transcription, guess) -> Result``."""

    def solve(self, problem: Problem, transcription: TranscriptionMethod = DEFAULT_TRANSCRIPTION,
              guess: Guess = None) -> Result:
        """Solve ``problem`` transcribed by ``transcription`` from ``guess`` (see
        ``Transcription.initial_guess``)."""
        raise NotImplementedError


class NLPSolver(Solver):
    """A solver of the NLP of a transcribed problem: ``solve`` builds the NLP and calls ``solve_nlp``."""

    def solve(self, problem: Problem, transcription: TranscriptionMethod = DEFAULT_TRANSCRIPTION,
              guess: Guess = None) -> Result:
        """Solve the NLP of ``problem`` transcribed by ``transcription`` from ``guess``; the time to
        build the NLP joins the result's ``timing['setup']``."""
        t0 = time.perf_counter()
        nlp = NLP(problem, transcription)
        built = time.perf_counter() - t0
        result = self.solve_nlp(nlp, guess)
        result.timing["setup"] = result.timing.get("setup", 0.0) + built
        return result

    def solve_nlp(self, nlp: NLP, guess: Guess = None) -> Result:
        """Solve ``nlp`` from ``guess`` (the start x0 is ``nlp.transcription.initial_guess(guess)``)."""
        raise NotImplementedError
