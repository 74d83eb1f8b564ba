// The Python-side integrator shared by the bindings.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "hovi/errors.hpp"
#include "hovi/integrators/galerkin_integrator.hpp"
#include "py_model.hpp"

namespace hovi::py_bind {

// A solve's statistics as the Python StepInfo takes them (status, converged, iterations,
// factorizations, residual_evaluations, residual).
inline StrDict info_dict(const SolveInfo& info) {
  StrDict d;
  d["status"] = to_string(info.status);
  d["converged"] = info.converged();
  d["iterations"] = info.iterations;
  d["factorizations"] = info.factorizations;
  d["residual_evaluations"] = info.residual_evaluations;
  d["residual"] = info.residual;
  return d;
}

// A rollout as the Python dict hovi.Integrator reads: q, p, control_points, iterations,
// factorizations, residual, status, multipliers, steps, seconds (and controls, chosen by a StepHook;
// with contacts pivots, impulses, gaps, impact and step_p, RolloutContacts).
inline StrDict rollout_dict(const Rollout& r, double seconds) {
  StrDict d;
  const int attempted = static_cast<int>(r.status.size());
  d["q"] = MatX(r.q.topRows(r.steps + 1));
  d["p"] = MatX(r.p.topRows(r.steps + 1));
  d["control_points"] = MatX(r.control_points.topRows(r.steps));
  d["iterations"] = Eigen::VectorXi(r.iterations.head(attempted));
  d["factorizations"] = Eigen::VectorXi(r.factorizations.head(attempted));
  d["residual"] = VecX(r.residual.head(attempted));
  py::list st;
  for (SolveStatus x : r.status) st.append(to_string(x));
  d["status"] = st;
  d["multipliers"] = r.multipliers.rows() >= r.steps ? MatX(r.multipliers.topRows(r.steps)) : MatX(r.steps, 0);
  d["steps"] = r.steps;
  d["seconds"] = seconds;
  if (r.controls.size()) d["controls"] = MatX(r.controls.topRows(attempted));
  const RolloutContacts& c = r.contact;
  if (c.pivots.size() || c.step_p.size()) {
    d["pivots"] = Eigen::VectorXi(c.pivots.head(attempted));
    d["impulses"] = MatX(c.impulses.topRows(r.steps));
    d["gaps"] = MatX(c.gaps.topRows(r.steps));
    d["impact"] = VecX(c.impact.head(r.steps));
    d["step_p"] = MatX(c.step_p.topRows(r.steps + 1));
  }
  return d;
}

// The core integrator (safe for concurrent calls: each leases its own workspace) and a watch on
// the model it copied: every call goes through integ(), which raises once the model has changed.
class PyIntegrator {
 public:
  PyIntegrator(std::shared_ptr<const PyModel> m, int s, double dt, const SolverOptions& opt, ContactModel contacts,
               const ContactOptions& contact_options)
      : integ_(m->model, s, dt, opt, std::move(contacts), contact_options), watch_(std::move(m), "Integrator") {}
  const GalerkinIntegrator& integ() const {
    watch_.check();
    return integ_;
  }
  // The contact unknowns of one step (0 without contacts).
  int nz() const { return integ_.contacts().unknowns(); }
  // Fixed at construction, readable even after the model changed (repr, sizes).
  double dt() const { return integ_.dt(); }
  const Quadrature& quad() const { return integ_.quadrature(); }
  int n() const { return integ_.model().n(); }
  int nq() const { return integ_.model().nq(); }
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
  // The controls of `steps` steps (of each of `batch` states; batch < 0: one state) as the core's
  // rollouts take them, lead + (steps, (s+1) m) with lead = () or (batch,), from lead + (m,) held
  // throughout, lead + (steps, m) held per step or lead + (steps, s+1, m) per control point; None
  // for None. InputError (ValueError) for a model without controls, another shape or NaN/infinity.
  py::object rollout_controls(const py::handle& u, long steps, long batch) const {
    if (u.is_none()) return py::none();
    const long S1 = s() + 1, M = m(), L = batch < 0 ? 0 : 1, B = batch < 0 ? 1 : batch;
    if (M == 0) throw InputError("the model has no controls (add actuators or controls first), but u was given");
    const RealArray a = real_array(u, "u");
    const std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    auto is = [&](std::vector<py::ssize_t> tail) {
      if (L) tail.insert(tail.begin(), batch);
      return shape == tail;
    };
    auto text = [&](std::vector<py::ssize_t> t) {
      if (L) t.insert(t.begin(), batch);
      std::string out = "(";
      for (std::size_t k = 0; k < t.size(); ++k) out += (k ? ", " : "") + std::to_string(t[k]);
      return out + (t.size() == 1 ? ",)" : ")");
    };
    const int kind = is({M}) ? 0 : is({steps, M}) ? 1 : is({steps, S1, M}) ? 2 : -1;
    if (kind < 0) {
      std::vector<py::ssize_t> got(shape.begin(), shape.end());
      std::string g = "(";
      for (std::size_t k = 0; k < got.size(); ++k) g += (k ? ", " : "") + std::to_string(got[k]);
      g += got.size() == 1 ? ",)" : ")";
      throw InputError("u must have shape " + text({M}) + ", " + text({steps, M}) + ", " + text({steps, S1, M}) +
                       ", got " + g);
    }
    const double* in = a.data();
    for (py::ssize_t k = 0; k < a.size(); ++k)
      if (!std::isfinite(in[k])) throw InputError("u contains NaN or infinity");
    std::vector<py::ssize_t> out_shape{steps, S1 * M};
    if (L) out_shape.insert(out_shape.begin(), batch);
    py::array_t<double> out(out_shape);
    double* o = out.mutable_data();
    for (long b = 0; b < B; ++b)
      for (long k = 0; k < steps; ++k)
        for (long a_ = 0; a_ < S1; ++a_) {
          const double* src = kind == 0 ? in + b * M : kind == 1 ? in + (b * steps + k) * M : in + ((b * steps + k) * S1 + a_) * M;
          std::copy(src, src + M, o + ((b * steps + k) * S1 + a_) * M);
        }
    return std::move(out);
  }
  // The controls of one step from each of `count` states, (count, m) held or (count, s+1, m) per
  // control point, as the core takes them: (count, (s+1) m); None for None.
  py::object step_controls(const py::handle& u, long count) const {
    if (u.is_none()) return py::none();
    const long S1 = s() + 1, M = m();
    RealArray a = real_array(u, "u");
    const bool held = a.ndim() == 2 && a.shape(0) == count && a.shape(1) == M;
    const bool per_point = a.ndim() == 3 && a.shape(0) == count && a.shape(1) == S1 && a.shape(2) == M;
    if (M && !held && !per_point) {
      std::string g = "(";
      for (py::ssize_t k = 0; k < a.ndim(); ++k) g += (k ? ", " : "") + std::to_string(a.shape(k));
      g += a.ndim() == 1 ? ",)" : ")";
      throw InputError("u must have shape (" + std::to_string(count) + ", " + std::to_string(M) + ") or (" +
                       std::to_string(count) + ", " + std::to_string(S1) + ", " + std::to_string(M) + "), got " + g);
    }
    py::object per_step = rollout_controls(per_point ? py::object(a.reshape({count, 1L, S1, M})) : py::object(a), 1, count);
    return per_step.attr("reshape")(count, -1);
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
