#include "hovi/forces/contact_inputs.hpp"

#include <memory>

#include "hovi/forces/builtin_wrenches.hpp"

namespace hovi {

Model with_contact_inputs(const Model& model, const ContactModel& contacts) {
  contacts.check(model);
  Model out = model;
  auto force_input = [&](int c, const Vec3& direction) {
    const int u = out.add_control();
    const Vec3 r = out.point_in_com_frame(contacts.points[c].body, contacts.points[c].point);
    out.add_wrench(std::make_shared<PointWrench>(contacts.points[c].body, r, direction, Vec3::Zero(),
                                                 PointWrench::Frame::World, u));
  };
  for (int c = 0; c < contacts.size(); ++c) {
    force_input(c, Vec3::UnitZ());                                             // λ_c
    for (int i = 0; i < contacts.d(); ++i) force_input(c, contacts.D.row(i));  // β_c,i
    out.add_control();                                                         // γ_c
  }
  return out;
}

}  // namespace hovi
