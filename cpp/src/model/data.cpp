#include "hovi/model/data.hpp"

namespace hovi {
Data::Data(const Model& model)
    : g(model.n()), Sbar(model.n()), Mbar(model.n()), v(model.n()), Sdot(model.n()), mu(model.n()), a(model.n()), c(model.n()),
      IA(model.n()), pA(model.n()), U(model.n()), D(model.n()), u(model.n()), qdd(model.n()),
      tau(model.n()), Mq(model.n(), model.n()), Kvv(model.n(), model.n()), Kvq(model.n(), model.n()),
      Kqv(model.n(), model.n()), Kqq(model.n(), model.n()), Vqq(model.n(), model.n()),
      sigma_m(model.n()), sigma_p(model.n()) {
  if (model.rotation_chart >= 0) chart_placement = model.g_parent0[model.rotation_chart];
}
}  // namespace hovi
