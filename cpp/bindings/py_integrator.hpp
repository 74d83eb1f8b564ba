// The Python-side integrator shared by the bindings.
#pragma once
#include "hovi/algorithms/energy.hpp"
#include "hovi/errors.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "py_model.hpp"

namespace hovi::py_bind {

struct PyIntegrator {
  PyIntegrator(const PyModel& m, int s, double dt, const SolverOptions& opt) : integ(m.model, s, dt, opt), data(integ.model()) {}
  GalerkinIntegrator integ;
  Data data;  // for energies
  int n() const { return integ.model().n(); }
  int s() const { return integ.quadrature().s; }
  int m() const { return integ.model().n_controls(); }

  // (s+1, n) Python array -> n x (s+1)
  MatX control_points(const py::handle& x, const char* name) { return as_matrix(x, name, s() + 1, n()).transpose(); }
  // None | (m,) | (s+1, m) -> m x (s+1)
  MatX controls(const py::handle& u) {
    const int S1 = s() + 1, M = m();
    if (u.is_none()) return MatX::Zero(M, S1);
    const py::array a = py::array::ensure(u);
    if (M == 0) throw InputError("the model has no controls (add actuators or controls first), but u was given");
    if (a && a.ndim() == 1) return as_vector(u, "u", M).replicate(1, S1);
    return as_matrix(u, "u (one row per control point)", S1, M).transpose();
  }
  ConstrainedSolver& constrained() {
    if (!integ.constrained()) throw InputError("the model has no constraints");
    return *integ.constrained();
  }
  // (s, m_c) Python array -> m_c x s
  MatX multipliers_arg(const py::handle& x) {
    return as_matrix(x, "multipliers", s(), integ.model().n_constraints()).transpose();
  }
  double energy(const VecX& q, const VecX& p) {
    const VecX qd = integ.velocity(q, p);
    return kinetic_energy(integ.model(), data, q, qd) + potential_energy(integ.model(), data, q);
  }
};

}  // namespace hovi::py_bind
