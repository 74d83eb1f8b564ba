// Built-in models.
#pragma once
#include "hovi/model/model.hpp"

namespace hovi::models {

// The paper's n-link pendulum benchmark (Sec. 5): a serial chain of identical uniform solid
// cylinders (length, mass, radius) hanging along -z at q = 0, joint i at the lower end of
// link i-1, revolute axes alternating between x (odd joints 1, 3, ...) and y (even joints),
// gravity (0, 0, -9.81).
Model pendulum(int n, double length = 0.5, double mass = 1.0, double radius = 0.02);

}  // namespace hovi::models
