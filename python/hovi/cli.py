"""The ``hovi`` command line."""
import argparse
import sys

import numpy as np

from . import Model, models


def load_model(spec: str, base: str = "fixed") -> Model:
    """'pendulum:N' for the built-in N-link pendulum, otherwise a URDF path."""
    if spec.startswith("pendulum"):
        _, _, n = spec.partition(":")
        return models.pendulum(int(n) if n else 32)
    return Model.from_urdf(spec, base=base)


def cmd_info(args) -> int:
    model = load_model(args.model, args.base)
    print(model.summary(), end="")
    rng = np.random.default_rng(args.seed)
    q = rng.uniform(-np.pi / 2, np.pi / 2, model.n)
    qd = rng.uniform(-1, 1, model.n)
    K, V = model.kinetic_energy(q, qd), model.potential_energy(q)
    print(f"random state (seed {args.seed}): K = {K:.6g} J, V = {V:.6g} J, E = {K + V:.6g} J")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="hovi", description="Higher-order variational integrators for robots.")
    sub = parser.add_subparsers(dest="command", required=True)
    info = sub.add_parser("info", help="describe a model and print its energy at a random state")
    info.add_argument("model", nargs="?", default="pendulum:32",
                      help="'pendulum:N' (built-in N-link pendulum) or a URDF path (default pendulum:32)")
    info.add_argument("--base", default="fixed", choices=["fixed", "floating", "planar"],
                      help="how a URDF's root link is attached to the world (default fixed)")
    info.add_argument("--seed", type=int, default=0, help="seed of the random state (default 0)")
    info.set_defaults(func=cmd_info)
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())
