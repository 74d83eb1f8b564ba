// The Python-side contact simulator shared by the bindings (bind_contact, bind_control).
#pragma once
#include "hovi/contact/contact_integrator.hpp"
#include "hovi/contact/contact_linearizer.hpp"
#include "py_integrator.hpp"

namespace hovi::py_bind {

// The contact model of hovi.contact.Contacts' arrays: bodies (C,), points (C, 3) in the bodies' joint
// frames, the terrain's ground, gaps (G, 3) and boxes (B, 5), mu, friction directions (d, 3).
ContactModel contact_model(const std::vector<int>& bodies, const ArrayLike& points, double ground,
                           const ArrayLike& gaps, const ArrayLike& boxes, double mu, const ArrayLike& directions);

// The contact simulator over the model, s, dt and options of an Integrator; every call goes
// through core(), which raises once the Integrator's model has changed.
class PyContactIntegrator {
 public:
  PyContactIntegrator(const PyIntegrator& integrator, ContactModel contacts, double tol, bool locate_impacts)
      : py_(integrator),
        core_(py_.integ().model(), std::move(contacts), py_.s(), py_.dt(), py_.integ().options, tol, locate_impacts),
        lin_(core_.integrator().model(), core_.integrator().quadrature(), core_.integrator().dt(), core_.contacts()) {}
  const ContactIntegrator& core() const {
    py_.integ();  // the model watch
    return core_;
  }
  const ContactLinearizer& lin() const {
    py_.integ();
    return lin_;
  }
  const PyIntegrator& py() const { return py_; }

 private:
  const PyIntegrator& py_;  // kept alive by the binding (keep_alive)
  ContactIntegrator core_;
  ContactLinearizer lin_;
};

// A contact rollout as the Python dict hovi.Integrator reads (q, p, control points, impulses, gaps, ...).
inline StrDict rollout_dict(const ContactRollout& r, double seconds) {
  StrDict d = rollout_dict(static_cast<const Rollout&>(r), seconds);
  const int attempted = static_cast<int>(r.status.size());
  d["pivots"] = Eigen::VectorXi(r.pivots.head(attempted));
  d["impulses"] = MatX(r.impulses.topRows(r.steps));
  d["gaps"] = MatX(r.gaps.topRows(r.steps));
  d["impact"] = VecX(r.impact.head(r.steps));
  d["step_p"] = MatX(r.step_p.topRows(r.steps + 1));
  return d;
}


}  // namespace hovi::py_bind
