// The Python-side integrator shared by the bindings.
#pragma once
#include "hovi/errors.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "py_model.hpp"

namespace hovi::py_bind {

// The core integrator (safe for concurrent calls: each leases its own workspace) and a watch on
// the model it copied: every call goes through integ(), which raises once the model has changed.
class PyIntegrator {
 public:
  PyIntegrator(std::shared_ptr<const PyModel> m, int s, double dt, const SolverOptions& opt)
      : integ_(m->model, s, dt, opt), watch_(std::move(m), "Integrator") {}
  const GalerkinIntegrator& integ() const {
    watch_.check();
    return integ_;
  }
  // Fixed at construction, readable even after the model changed (repr, sizes).
  double dt() const { return integ_.dt(); }
  const Quadrature& quad() const { return integ_.quadrature(); }
  int n() const { return integ_.model().n(); }
  int s() const { return integ_.quadrature().s; }
  int m() const { return integ_.model().n_controls(); }
  int mc() const { return integ_.model().n_constraints(); }

  // (s+1, n) Python array -> n x (s+1)
  MatX control_points(const py::handle& x, const char* name) const { return as_matrix(x, name, s() + 1, n()).transpose(); }
  // None | (m,) | (s+1, m) -> m x (s+1)
  MatX controls(const py::handle& u) const {
    const int S1 = s() + 1, M = m();
    if (u.is_none()) return MatX::Zero(M, S1);
    const py::array a = py::array::ensure(u);
    if (M == 0) throw InputError("the model has no controls (add actuators or controls first), but u was given");
    if (a && a.ndim() == 1) return as_vector(u, "u", M).replicate(1, S1);
    return as_matrix(u, "u (one row per control point)", S1, M).transpose();
  }
  // (s, m_c) Python array -> m_c x s
  MatX multipliers_arg(const py::handle& x) const {
    if (!mc()) throw InputError("multipliers were given but the model has no constraints");
    return as_matrix(x, "multipliers", s(), mc()).transpose();
  }

 private:
  GalerkinIntegrator integ_;
  ModelWatch watch_;
};

}  // namespace hovi::py_bind
