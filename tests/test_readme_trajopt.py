"""The README's worked trajectory-optimisation example runs as written."""
import os

import pytest

README = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "README.md")


def test_worked_example_runs():
    pytest.importorskip("cyipopt")
    text = open(README).read()
    start = text.index("```python", text.index("### Trajectory optimisation")) + len("```python")
    code = text[start:text.index("```", start)]
    exec(compile(code, "README.md (trajectory optimisation)", "exec"), {})
