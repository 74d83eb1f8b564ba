"""Built-in models."""
from . import _core


def pendulum(n: int, length: float = 0.5, mass: float = 1.0, radius: float = 0.02) -> "_core.Model":
    """The paper's n-link 3D pendulum benchmark (Fan et al. 2018, Sec. 5).

    A serial chain of ``n`` identical uniform solid cylinders (``length`` m, ``mass`` kg,
    ``radius`` m) hanging along -z at q = 0. Joint 1 is at the world origin and joint i at the
    lower end of link i-1; the revolute axes alternate between x (joints 1, 3, ...) and y
    (joints 2, 4, ...), so the chain moves in 3D. Gravity is (0, 0, -9.81).
    """
    return _core.pendulum(int(n), float(length), float(mass), float(radius))
