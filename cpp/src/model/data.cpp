#include "hovi/model/data.hpp"

namespace hovi {
Data::Data(const Model& model)
    : g(model.n()), Sbar(model.n()), Mbar(model.n()), v(model.n()), a(model.n()), c(model.n()),
      IA(model.n()), pA(model.n()), U(model.n()), D(model.n()), u(model.n()), qdd(model.n()),
      tau(model.n()), Mq(model.n(), model.n()) {}
}  // namespace hovi
