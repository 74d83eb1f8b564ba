"""Run every benchmark in full mode (slow)."""
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = ["speed.py", "linearization.py", "constraints.py", "constrained_energy.py", "fig2_quasi_newton.py", "fig3_autodiff.py",
           "fig4_hermite_simpson.py", "stability.py", "trajopt.py", "pareto.py", "energy_runtime.py",
           "direction_crossover.py", "jacobian_reuse.py", "step_floor.py", "scaling.py"]

if __name__ == "__main__":
    extra = sys.argv[1:]
    for script in SCRIPTS:
        print(f"== {script}", flush=True)
        subprocess.run([sys.executable, os.path.join(HERE, script), *extra], check=True)
