#include "hovi/algorithms/del_workspace.hpp"

namespace hovi {

DelWorkspace::DelWorkspace(const Model& model, const Quadrature& quad) : n(model.n()), s(quad.s) {
  const std::size_t N = static_cast<std::size_t>(n) * (s + 1);
  g.resize(N);
  Sbar.resize(N);
  Sdot.resize(N);
  Mbar.resize(N);
  v.resize(N);
  mu.resize(N);
  F.resize(N);
  Gamma.resize(N);
  qdot.resize(n, s + 1);
  u.resize(model.n_controls(), s + 1);
  wrenches.resize(n);
  for (const auto& w : model.wrenches) wrenches[w->body()].push_back(w.get());
  if (model.rotation_chart >= 0) {
    chart_placement = model.g_parent0[model.rotation_chart];
    chart_G.resize(3, s + 1);
    chart_P.resize(3, s + 1);
  }
}

void DelWorkspace::kinematics_at(int a, Data& data) const {
  for (int i = 0; i < n; ++i) {
    const int k = at(i, a);
    data.g[i] = g[k];
    data.Sbar[i] = Sbar[k];
    data.Mbar[i] = Mbar[k];
    data.v[i] = v[k];
  }
}

}  // namespace hovi
