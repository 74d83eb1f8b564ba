#include "hovi/algorithms/kinematics.hpp"

#include <sstream>

#include "hovi/errors.hpp"

namespace hovi {

void check_vector(const char* name, const Eigen::Ref<const VecX>& x, int n) {
  if (x.size() != n) {
    std::ostringstream os;
    os << name << " must have " << n << " entries (one per joint), got " << x.size();
    throw InputError(os.str());
  }
  if (!x.allFinite()) throw InputError(std::string(name) + " contains NaN or infinity");
}

void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q) {
  check_vector("q", q, model.n());
  for (int i = 0; i < model.n(); ++i) {
    const int p = model.parent[i];
    const SE3& g0 = i == model.rotation_chart ? data.chart_placement : model.g_parent0[i];
    const SE3 gpi = g0 * exp_twist(model.S[i], q[i]);
    data.g[i] = p >= 0 ? data.g[p] * gpi : gpi;
    data.Sbar[i] = Ad(data.g[i], model.S[i]);
    data.Mbar[i] = model.M[i].transformed(data.g[i]);
  }
}

void forward_kinematics(const Model& model, Data& data, const Eigen::Ref<const VecX>& q,
                        const Eigen::Ref<const VecX>& qdot) {
  forward_kinematics(model, data, q);
  check_vector("qdot", qdot, model.n());
  for (int i = 0; i < model.n(); ++i) {
    const int p = model.parent[i];
    data.v[i] = data.Sbar[i] * qdot[i];
    if (p >= 0) data.v[i] += data.v[p];
  }
}

SE3 joint_placement(const Model& model, const Data& data, int i) {
  return data.g[i] * SE3::Translation(-model.spec[i].com);
}

Wrench gravity_wrench(const Model& model, const Data& data, int i) {
  Wrench F;
  F.tail<3>() = model.M[i].m * model.gravity;
  F.head<3>() = data.g[i].p.cross(F.tail<3>());
  return F;
}

}  // namespace hovi
