#include "hovi/control/riccati.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <string>

#include "hovi/errors.hpp"

namespace hovi {
namespace {

void check_lqr_sizes(const MatX& A, const MatX& B, const MatX& Q, const MatX& R, const char* where) {
  const long n = A.rows(), m = B.cols();
  const std::string at = std::string(" (") + where + ")";
  if (A.cols() != n || B.rows() != n) throw InputError("A must be (n, n) and B (n, m)" + at);
  if (Q.rows() != n || Q.cols() != n) throw InputError("Q must be (n, n) with n = " + std::to_string(n) + at);
  if (R.rows() != m || R.cols() != m) throw InputError("R must be (m, m) with m = " + std::to_string(m) + at);
  if (!A.allFinite() || !B.allFinite() || !Q.allFinite() || !R.allFinite())
    throw InputError("A, B, Q and R must be finite" + at);
}

// (R + B^T P B)^{-1} B^T P A by Cholesky; throws if R + B^T P B is not positive definite.
MatX lqr_gain(const MatX& A, const MatX& B, const MatX& R, const MatX& P) {
  const MatX PB = P * B;
  const MatX S = R + B.transpose() * PB;
  const Eigen::LLT<MatX> llt(0.5 * (S + S.transpose()));
  if (llt.info() != Eigen::Success) throw InputError("R + B^T P B is not positive definite (R must be)");
  return llt.solve(PB.transpose() * A);
}

}  // namespace

void discrete_are(const MatX& A, const MatX& B, const MatX& Q, const MatX& R, MatX& P, MatX& K, int* iterations) {
  check_lqr_sizes(A, B, Q, R, "discrete_are");
  const long n = A.rows();
  const Eigen::LLT<MatX> r(0.5 * (R + R.transpose()));
  if (r.info() != Eigen::Success) throw InputError("R must be symmetric positive definite (discrete_are)");
  // SDA (Chu, Fan, Lin 2005): A_{j+1} = A_j W^{-1} A_j, G_{j+1} = G_j + A_j W^{-1} G_j A_j^T,
  // H_{j+1} = H_j + A_j^T H_j W^{-1} A_j with W = I + G_j H_j; H_j -> P.
  MatX Aj = A, G = B * r.solve(B.transpose()), H = 0.5 * (Q + Q.transpose());
  G = 0.5 * (G + G.transpose());
  const MatX I = MatX::Identity(n, n);
  int it = 0;
  for (; it < 100; ++it) {
    const Eigen::PartialPivLU<MatX> W(I + G * H);
    const MatX WA = W.solve(Aj), WG = W.solve(G);
    const MatX Hn = H + Aj.transpose() * H * WA;
    G += Aj * WG * Aj.transpose();
    G = 0.5 * (G + G.transpose());
    Aj = Aj * WA;
    const double change = (Hn - H).cwiseAbs().maxCoeff(), size = Hn.cwiseAbs().maxCoeff();
    H = 0.5 * (Hn + Hn.transpose());
    if (!H.allFinite()) break;
    if (change <= 1e-15 * size) break;
  }
  if (!H.allFinite() || it == 100)
    throw InputError("the discrete Riccati equation has no stabilising solution: (A, B) not stabilisable or "
                     "(A, Q) not detectable (discrete_are)");
  P = H;
  K = lqr_gain(A, B, R, P);
  if (iterations) *iterations = it + 1;
}

void backward_riccati(const std::vector<MatX>& A, const std::vector<MatX>& B, const std::vector<MatX>& Q,
                      const std::vector<MatX>& R, const MatX& QN, std::vector<MatX>& K, std::vector<MatX>& P) {
  const std::size_t N = A.size();
  if (B.size() != N) throw InputError("backward_riccati needs as many B as A");
  if (Q.size() != N && Q.size() != 1) throw InputError("backward_riccati needs one Q per stage, or one");
  if (R.size() != N && R.size() != 1) throw InputError("backward_riccati needs one R per stage, or one");
  if (N == 0) throw InputError("backward_riccati needs at least one stage");
  K.assign(N, MatX());
  P.assign(N + 1, MatX());
  P[N] = 0.5 * (QN + QN.transpose());
  if (QN.rows() != A[0].rows() || QN.cols() != A[0].rows() || !QN.allFinite())
    throw InputError("QN must be finite and (n, n) with n = " + std::to_string(A[0].rows()) + " (backward_riccati)");
  for (std::size_t j = N; j-- > 0;) {
    const MatX& Qk = Q[Q.size() == 1 ? 0 : j];
    const MatX& Rk = R[R.size() == 1 ? 0 : j];
    check_lqr_sizes(A[j], B[j], Qk, Rk, ("stage " + std::to_string(j)).c_str());
    K[j] = lqr_gain(A[j], B[j], Rk, P[j + 1]);
    const MatX Acl = A[j] - B[j] * K[j];
    const MatX Pk = Qk + K[j].transpose() * Rk * K[j] + Acl.transpose() * P[j + 1] * Acl;
    P[j] = 0.5 * (Pk + Pk.transpose());
  }
}

}  // namespace hovi
