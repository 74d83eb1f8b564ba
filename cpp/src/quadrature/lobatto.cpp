#include "hovi/quadrature/lobatto.hpp"

#include <cmath>

#include "hovi/errors.hpp"

namespace hovi {

Quadrature::Quadrature(int s_) : s(s_) {
  if (s < 1 || s > 16) throw InputError("the number of Lobatto intervals s must be between 1 and 16, got " + std::to_string(s));
  const int N = s;  // Legendre degree: nodes are ±1 and the roots of P_N'
  VecX x(N + 1), P_N(N + 1);
  // Newton iteration from the Chebyshev-Gauss-Lobatto points on (x P_N - P_{N-1}) = 0,
  // whose roots are the Lobatto nodes; Legendre polynomials by their three-term recurrence.
  for (int j = 0; j <= N; ++j) x[j] = -std::cos(M_PI * j / N);
  for (int iter = 0; iter < 100; ++iter) {
    double change = 0;
    for (int j = 0; j <= N; ++j) {
      double p0 = 1, p1 = x[j];
      for (int k = 2; k <= N; ++k) {
        const double p2 = ((2 * k - 1) * x[j] * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      // p1 = P_N(x), p0 = P_{N-1}(x)
      const double dx = (x[j] * p1 - p0) / ((N + 1) * p1);
      x[j] -= dx;
      P_N[j] = p1;
      change = std::max(change, std::abs(dx));
    }
    if (change < 1e-16) break;
  }
  c = (x.array() + 1) / 2;
  c[0] = 0;
  c[N] = 1;
  w.resize(N + 1);
  for (int j = 0; j <= N; ++j) w[j] = 1.0 / (N * (N + 1) * P_N[j] * P_N[j]);  // 2/(N(N+1)P^2) halved
  // Barycentric weights and the differentiation matrix b^{ab} = l_b'(c^a).
  VecX lam = VecX::Ones(N + 1);
  for (int j = 0; j <= N; ++j)
    for (int k = 0; k <= N; ++k)
      if (k != j) lam[j] /= (c[j] - c[k]);
  b = MatX::Zero(N + 1, N + 1);
  for (int i = 0; i <= N; ++i) {
    for (int j = 0; j <= N; ++j)
      if (i != j) b(i, j) = lam[j] / lam[i] / (c[i] - c[j]);
    b(i, i) = -b.row(i).sum();
  }
  a.resize(N + 1, N + 1);
  for (int i = 0; i <= N; ++i)
    for (int j = 0; j <= N; ++j) a(i, j) = w[j] * b(j, i);
}

VecX Quadrature::basis(double x) const {
  VecX l = VecX::Ones(s + 1);
  for (int j = 0; j <= s; ++j)
    for (int k = 0; k <= s; ++k)
      if (k != j) l[j] *= (x - c[k]) / (c[j] - c[k]);
  return l;
}

VecX Quadrature::basis_derivative(double x) const {
  VecX d = VecX::Zero(s + 1);
  for (int j = 0; j <= s; ++j)
    for (int m = 0; m <= s; ++m) {  // the product rule: the factor of node m differentiated
      if (m == j) continue;
      double term = 1.0 / (c[j] - c[m]);
      for (int k = 0; k <= s; ++k)
        if (k != j && k != m) term *= (x - c[k]) / (c[j] - c[k]);
      d[j] += term;
    }
  return d;
}

}  // namespace hovi
