"""Every example hovi ships, in one place, with one registry (``REGISTRY``) that the command line
and the documentation read:

- ``hovi.examples.models``: built-in models (the paper's n-link pendulum, an acrobot, a cart-pole,
  a four-bar, a slider-crank, a quadrotor on the free joint), ``hovi simulate NAME``;
- ``hovi.examples.robots``: the paper's three robots from the URDFs shipped as ``hovi/urdf``
  (Spring Flamingo, LittleDog, Atlas), ``hovi simulate NAME``;
- ``hovi.examples.swingups``: trajectory optimisations (swing-ups, a slider-crank to a target),
  ``hovi optimize NAME``;
- ``hovi.examples.paper``: the paper's Sec. 6 trajectory optimisations on the three robots,
  ``hovi example NAME``.

Importing this package loads nothing heavy: an entry's module is imported when it is built.
"""
from __future__ import annotations

from dataclasses import dataclass
from importlib import import_module
from typing import Any, Dict, Tuple

MODEL, ROBOT, OPTIMIZATION, ROBOT_EXAMPLE = "model", "robot", "optimization", "robot_example"
KINDS = (MODEL, ROBOT, OPTIMIZATION, ROBOT_EXAMPLE)
"""What an example is: a ``hovi.Model``; a ``hovi.examples.robots.Robot``; a ``hovi.trajopt.Problem``;
a ``hovi.examples.paper.Example`` (a problem with its guess, checks and scenery)."""


@dataclass(frozen=True)
class Entry:
    """One example: its ``name`` (unique within its ``kind``), what it is (``kind``, one of KINDS),
    how to build it (``target``, 'module:function' under hovi.examples) and a one-line
    ``description``."""
    kind: str
    name: str
    target: str
    description: str

    @property
    def function(self) -> Any:
        """The function that builds this example (its module imported now)."""
        module, _, function = self.target.partition(":")
        return getattr(import_module(f"{__name__}.{module}"), function)

    def build(self, *args: Any, **kwargs: Any) -> Any:
        """The example: ``function(*args, **kwargs)``."""
        return self.function(*args, **kwargs)


REGISTRY: Tuple[Entry, ...] = (
    Entry(MODEL, "pendulum", "models:pendulum", "the paper's n-link 3D pendulum benchmark (Sec. 5), 'pendulum:N'"),
    Entry(MODEL, "acrobot", "models:acrobot", "a planar double pendulum actuated at the elbow"),
    Entry(MODEL, "cartpole", "models:cartpole", "a cart on a rail with a hanging pole, pushed at the cart"),
    Entry(MODEL, "fourbar", "models:fourbar", "a planar crank-rocker four-bar: a closed chain (loop constraint)"),
    Entry(MODEL, "slider_crank", "models:slider_crank", "a planar slider-crank: a closed chain (point constraint)"),
    Entry(MODEL, "quadrotor", "models:quadrotor", "a quadrotor on the free joint (SE(3)), four thrust controls"),
    Entry(ROBOT, "spring_flamingo", "robots:spring_flamingo", "Spring Flamingo: planar 9-DoF biped with ankle springs"),
    Entry(ROBOT, "littledog", "robots:littledog", "LittleDog: 18-DoF quadruped with spherical feet"),
    Entry(ROBOT, "atlas", "robots:atlas", "Atlas v5: floating-base humanoid with flat feet"),
    Entry(OPTIMIZATION, "pendulum", "swingups:pendulum_swingup", "swing-up of a 1-link pendulum, |u| <= 4 N m"),
    Entry(OPTIMIZATION, "acrobot", "swingups:acrobot_swingup", "swing-up of the acrobot, elbow torque only"),
    Entry(OPTIMIZATION, "cartpole", "swingups:cartpole_swingup", "swing-up of the cart-pole, cart back at the origin"),
    Entry(OPTIMIZATION, "slider_crank", "swingups:slider_crank_to_target",
          "a slider-crank driven to a target crank angle (constraint multipliers as variables)"),
    Entry(ROBOT_EXAMPLE, "spring_flamingo", "paper.flamingo:build",
          "Spring Flamingo jumps over an obstacle (contact-implicit, Sec. 6)"),
    Entry(ROBOT_EXAMPLE, "littledog", "paper.littledog:build",
          "LittleDog walks over terrain with two gaps (contact-implicit, Sec. 6)"),
    Entry(ROBOT_EXAMPLE, "atlas", "paper.atlas:build",
          "Atlas picks a ball with its left hand while balancing on its right foot (Sec. 6)"),
)


def entries(kind: str) -> Dict[str, Entry]:
    """The examples of one ``kind`` by name, in the registry's order."""
    if kind not in KINDS:
        raise ValueError(f"unknown kind of example '{kind}' (choose from {', '.join(KINDS)})")
    return {e.name: e for e in REGISTRY if e.kind == kind}


def names(kind: str) -> Tuple[str, ...]:
    """The names of the examples of one ``kind``."""
    return tuple(entries(kind))


def get(kind: str, name: str) -> Entry:
    """The entry ``name`` of ``kind``; ValueError naming the choices for an unknown name."""
    found = entries(kind)
    if name not in found:
        raise ValueError(f"unknown {kind.replace('_', ' ')} '{name}' (choose from {', '.join(found)})")
    return found[name]


def build(kind: str, name: str, *args: Any, **kwargs: Any) -> Any:
    """The example ``name`` of ``kind`` built with the arguments of its function."""
    return get(kind, name).build(*args, **kwargs)


from . import models, robots  # noqa: E402 (light: the built-in models and robots load with hovi)

__all__ = ["models", "robots", "REGISTRY", "Entry", "KINDS", "MODEL", "ROBOT", "OPTIMIZATION", "ROBOT_EXAMPLE", "entries", "names",
           "get", "build"]
