// Exceptions thrown by the core. The bindings map each to a Python exception class.
#pragma once
#include <stdexcept>
#include <string>

namespace hovi {
// An invalid model description (bad inertia, unknown parent, ...): Python hovi.ModelError.
struct ModelError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
// A URDF that cannot be read or uses something hovi does not support: Python hovi.URDFError.
struct UrdfError : ModelError {
  using ModelError::ModelError;
};
// Wrong sizes or non-finite values passed to an algorithm: Python ValueError.
struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
}  // namespace hovi
