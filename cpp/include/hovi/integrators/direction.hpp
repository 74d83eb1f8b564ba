// Which Newton direction a step solver takes (shared by newton_solver.hpp, which chooses, and
// dense_direction.hpp, which computes the dense one).
#pragma once

namespace hovi {

// The Newton direction: Algorithms A.1/A.2 (recursive, O(s^3 n)), a dense LU of the DEL
// Jacobian from the linearisation (O(s^2 n^2) + O(s^3 n^3), cheaper for small n), or the
// cheaper of the two for this model and s (dense_direction.hpp's crossover).
enum class Direction { Auto, Recursive, Dense };

}  // namespace hovi
