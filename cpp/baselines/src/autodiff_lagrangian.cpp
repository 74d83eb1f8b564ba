#include "hovi/baselines/autodiff_lagrangian.hpp"

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <type_traits>
#include <unsupported/Eigen/AutoDiff>

#include "hovi/errors.hpp"

namespace hovi {
namespace {

using AD1 = Eigen::AutoDiffScalar<Eigen::VectorXd>;  // value and gradient (first-order passes)

// ---- Scalar primitives, recursive over the nesting level --------------------------------------
// All return Eigen expressions referring to their arguments: use them inside one statement only.

// x c for a double constant c, without promoting c to an active scalar.
inline double cm(double x, double c) { return x * c; }
template <class Der>
inline auto cm(const Eigen::AutoDiffScalar<Der>& x, double c) {
  using S = typename Eigen::internal::traits<typename Eigen::internal::remove_all<Der>::type>::Scalar;
  return Eigen::MakeAutoDiffScalar(S(cm(x.value(), c)), x.derivatives() * c);
}

// r x with r either a double constant or an active scalar.
template <class RT, class T>
inline auto mul(const RT& r, const T& x) {
  if constexpr (std::is_same_v<RT, double>)
    return cm(x, r);
  else
    return r * x;
}

// sin x and 1 - cos x (the exponential of a joint twist, Rodrigues' formula).
inline void sin_omc(double x, double& s, double& omc) {
  s = std::sin(x);
  omc = 1 - std::cos(x);
}
template <class Der>
void sin_omc(const Eigen::AutoDiffScalar<Der>& x, Eigen::AutoDiffScalar<Der>& s, Eigen::AutoDiffScalar<Der>& omc) {
  using S = typename Der::Scalar;
  sin_omc(x.value(), s.value(), omc.value());
  const S c = 1.0 - omc.value();                  // cos x
  s.derivatives() = x.derivatives() * c;          // d sin x = cos x dx
  omc.derivatives() = x.derivatives() * s.value();  // d (1 - cos x) = sin x dx
}

// Sizing (once), zeroing and seeding of the active scalars. n_in: first-level derivatives
// (the gradient), n_out: second-level (the Hessian's columns).
template <class Der>
constexpr bool is_nested() {
  return !std::is_same_v<typename Der::Scalar, double>;
}
inline void init(double& x, int, int) { x = 0; }
template <class Der>
void init(Eigen::AutoDiffScalar<Der>& x, int n_in, int n_out) {
  if constexpr (!is_nested<Der>()) {
    x.value() = 0;
    x.derivatives().setZero(n_in);
  } else {
    init(x.value(), n_in, 0);
    x.derivatives().resize(n_out);
    for (int j = 0; j < n_out; ++j) init(x.derivatives()[j], n_in, 0);
  }
}
inline void zero(double& x) { x = 0; }
template <class Der>
void zero(Eigen::AutoDiffScalar<Der>& x) {
  zero(x.value());
  if constexpr (!is_nested<Der>())
    x.derivatives().setZero();
  else
    for (Eigen::Index j = 0; j < x.derivatives().size(); ++j) zero(x.derivatives()[j]);
}
inline void set_value(double& x, double v) { x = v; }
template <class Der>
void set_value(Eigen::AutoDiffScalar<Der>& x, double v) {
  set_value(x.value(), v);
}

// A leaf of the computation: the value v of a linear function of the control-point coordinates
// of joint i, dx/dq_i^b = coef[b]. off[b] is the index of q_i^b - i among the first-level (in) or
// second-level (out) variables, -1 if q^b is not a variable at that level; the second-level
// derivatives carried are those of the variables out_begin, out_begin + 1, ...
inline void seed(double& x, double v, int, const double*, const std::vector<int>&, const std::vector<int>&, int) {
  x = v;
}
template <class Der>
void seed(Eigen::AutoDiffScalar<Der>& x, double v, int i, const double* coef, const std::vector<int>& in_off,
          const std::vector<int>& out_off, int out_begin) {
  if constexpr (!is_nested<Der>()) {
    x.value() = v;
    x.derivatives().setZero();
    for (size_t b = 0; b < in_off.size(); ++b)
      if (in_off[b] >= 0) x.derivatives()[in_off[b] + i] = coef[b];
  } else {
    seed(x.value(), v, i, coef, in_off, out_off, 0);
    auto& D = x.derivatives();  // dx/dq_out: constants, so their own derivatives stay zero (set by init)
    for (Eigen::Index j = 0; j < D.size(); ++j) D[j].value() = 0;
    for (size_t b = 0; b < out_off.size(); ++b) {
      const Eigen::Index j = out_off[b] + i - out_begin;  // this pass's chunk of second-level directions
      if (out_off[b] >= 0 && j >= 0 && j < D.size()) D[j].value() = coef[b];
    }
  }
}

// ---- The model's constant data, per body ------------------------------------------------------
struct BodyConst {
  int parent = -1;
  int nchild = 0;
  bool screw = true;  // joint twist with a rotation (revolute); false: pure translation (prismatic)
  double th = 0;      // |ω| of the joint twist S_i = (ω, v)
  // g_{par,i}(q) = g_{par,i}(0) exp(Ŝ_i q) = (R0 + sin φ C1 + (1 - cos φ) C2,
  //                                         p0 + φ d0 + (1 - cos φ) d1 + (φ - sin φ) d2), φ = th q;
  // prismatic: (R0, p0 + q d0). Matrices row-major.
  double R0[9], C1[9], C2[9], p0[3], d0[3], d1[3], d2[3];
  double sw[3], sv[3];      // S_i = (ω, v) in the body frame {i}
  double m, h[3], I[6];     // M_i: mass, first moment, rotational inertia (xx yy zz xy xz yz)
  bool has_h = false;
  double k = 0, preload = 0;  // spring: V_s = 1/2 k q^2 - preload q (preload = k qref)
  double armature = 0;        // joint armature: K_a = 1/2 a q̇^2
};

// Body state at one control point: body twist V_i = (ω_i, v_i) = Ad_{g_i}^{-1} v̄_i (0..5),
// gravity in body axes R_i^T g (6..8), g^T p_i (9).
template <class T>
using State = std::array<T, 10>;

template <class T>
struct Work {
  int n_in = 0, n_out = 0;
  std::vector<int> in_off, out_off;  // see seed()
  int out_begin = 0;                 // first second-level direction of this pass
  std::vector<State<T>> pool;        // states of the bodies whose children are still to come
  State<T> world;                    // the parent of the roots: at rest, R^T g = g, g^T p = 0
  std::vector<int> free_slots, slot, pending;
  T th, thd;                         // q_i^a and q̇_i^a
  T phi, sn, omc, pms;               // φ = th q, sin φ, 1 - cos φ, φ - sin φ
  T R[9], p[3], x[3];                // g_{par,i}(q_i^a) = (R, p); x = v_par + ω_par × p
  T L;                               // L_d

  Work(int n_in_, int n_out_, std::vector<int> in, std::vector<int> out, int pool_size, int n, const Vec3& g)
      : n_in(n_in_), n_out(n_out_), in_off(std::move(in)), out_off(std::move(out)), pool(pool_size), slot(n),
        pending(n) {
    for (auto& st : pool)
      for (auto& v : st) init(v, n_in, n_out);
    for (auto& v : world) init(v, n_in, n_out);
    for (int k = 0; k < 3; ++k) set_value(world[6 + k], g[k]);
    for (T* v : {&th, &thd, &phi, &sn, &omc, &pms, &L}) init(*v, n_in, n_out);
    for (int k = 0; k < 9; ++k) init(R[k], n_in, n_out);
    for (int k = 0; k < 3; ++k) {
      init(p[k], n_in, n_out);
      init(x[k], n_in, n_out);
    }
    free_slots.reserve(pool.size());
  }
};

// State C of body i from its parent's P and the relative pose (R, p) = g_{par,i}(q_i^a):
// V_i = Ad_{g_{par,i}^{-1}} V_par + S_i q̇_i, i.e. ω_i = R^T ω_par + S_ω q̇,
// v_i = R^T (v_par + ω_par × p) + S_v q̇; R_i^T g = R^T (R_par^T g); g^T p_i = g^T p_par + (R_par^T g)·p.
template <class T, class RT>
void propagate(const BodyConst& B, const RT* R, const State<T>& P, State<T>& C, Work<T>& w) {
  const T* p = w.p;
  w.x[0] = P[3] + P[1] * p[2] - P[2] * p[1];
  w.x[1] = P[4] + P[2] * p[0] - P[0] * p[2];
  w.x[2] = P[5] + P[0] * p[1] - P[1] * p[0];
  for (int k = 0; k < 3; ++k) {
    C[k] = mul(R[k], P[0]) + mul(R[3 + k], P[1]) + mul(R[6 + k], P[2]) + cm(w.thd, B.sw[k]);
    C[3 + k] = mul(R[k], w.x[0]) + mul(R[3 + k], w.x[1]) + mul(R[6 + k], w.x[2]) + cm(w.thd, B.sv[k]);
    C[6 + k] = mul(R[k], P[6]) + mul(R[3 + k], P[7]) + mul(R[6 + k], P[8]);
  }
  C[9] = P[9] + P[6] * p[0] + P[7] * p[1] + P[8] * p[2];
}

// One body at one control point: its state, and w^a dt (K_i - V_i) added to L_d.
template <class T>
void body_step(const BodyConst& B, double wdt, const State<T>& P, State<T>& C, Work<T>& w) {
  if (B.screw) {
    w.phi = cm(w.th, B.th);
    sin_omc(w.phi, w.sn, w.omc);
    w.pms = w.phi - w.sn;
    for (int k = 0; k < 9; ++k) w.R[k] = cm(w.sn, B.C1[k]) + cm(w.omc, B.C2[k]) + B.R0[k];
    for (int k = 0; k < 3; ++k)
      w.p[k] = cm(w.phi, B.d0[k]) + cm(w.omc, B.d1[k]) + cm(w.pms, B.d2[k]) + B.p0[k];
    propagate(B, w.R, P, C, w);
  } else {
    for (int k = 0; k < 3; ++k) w.p[k] = cm(w.th, B.d0[k]) + B.p0[k];
    propagate(B, B.R0, P, C, w);
  }
  // K_i = 1/2 ω^T I ω + 1/2 m v·v (+ ω·(h × v));  -V_i = m g^T p_i (+ (R_i^T g)·h) for gravity
  const double* I = B.I;
  w.L = w.L + cm(C[0] * C[0], 0.5 * wdt * I[0]) + cm(C[1] * C[1], 0.5 * wdt * I[1]) +
        cm(C[2] * C[2], 0.5 * wdt * I[2]) + cm(C[0] * C[1], wdt * I[3]) + cm(C[0] * C[2], wdt * I[4]) +
        cm(C[1] * C[2], wdt * I[5]) + cm(C[3] * C[3] + C[4] * C[4] + C[5] * C[5], 0.5 * wdt * B.m) +
        cm(C[9], wdt * B.m);
  if (B.has_h)
    w.L = w.L + cm(C[4] * C[2] - C[5] * C[1], wdt * B.h[0]) + cm(C[5] * C[0] - C[3] * C[2], wdt * B.h[1]) +
          cm(C[3] * C[1] - C[4] * C[0], wdt * B.h[2]) + cm(C[6], wdt * B.h[0]) + cm(C[7], wdt * B.h[1]) +
          cm(C[8], wdt * B.h[2]);
  // joint spring: -V_s = -1/2 k q^2 + preload q
  if (B.k != 0 || B.preload != 0) w.L = w.L + cm(w.th * w.th, -0.5 * wdt * B.k) + cm(w.th, wdt * B.preload);
  if (B.armature != 0) w.L = w.L + cm(w.thd * w.thd, 0.5 * wdt * B.armature);
}

// The model's constants and the evaluation of L_d, for any scalar type.
struct Lagrangian {
  int n = 0, s = 0;
  double dt = 0;
  VecX w;                         // w^a
  MatX b;                         // b^{ab}
  std::vector<double> unit, bdt;  // leaf coefficients: row a of the identity and of b / dt, (s+1)^2
  std::vector<BodyConst> body;
  int pool_size = 0;              // most body states alive at once (index order)
  Vec3 g;                         // gravity
  MatX qd;                        // q̇^a, n x (s+1)

  // L_d at qc into ws.L, with the derivatives the type T carries.
  template <class T>
  void eval(Work<T>& ws, const MatX& qc) {
    qd.noalias() = qc * b.transpose() / dt;  // q̇^a = (1/dt) sum_b b^{ab} q^b
    zero(ws.L);
    const int S1 = s + 1;
    for (int a = 0; a < S1; ++a) {
      const double wdt = w[a] * dt;
      ws.free_slots.clear();
      for (int k = pool_size - 1; k >= 0; --k) ws.free_slots.push_back(k);
      for (int i = 0; i < n; ++i) ws.pending[i] = body[i].nchild;
      for (int i = 0; i < n; ++i) {
        const BodyConst& Bi = body[i];
        seed(ws.th, qc(i, a), i, &unit[a * S1], ws.in_off, ws.out_off, ws.out_begin);  // q_i^a
        seed(ws.thd, qd(i, a), i, &bdt[a * S1], ws.in_off, ws.out_off, ws.out_begin);  // q̇_i^a
        const int sl = ws.free_slots.back();
        ws.free_slots.pop_back();
        ws.slot[i] = sl;
        const int par = Bi.parent;
        body_step(Bi, wdt, par >= 0 ? ws.pool[ws.slot[par]] : ws.world, ws.pool[sl], ws);
        if (par >= 0 && --ws.pending[par] == 0) ws.free_slots.push_back(ws.slot[par]);
        if (Bi.nchild == 0) ws.free_slots.push_back(sl);
      }
    }
  }
};

// Nested forward AD in vector mode, strip-mined: each pass carries the first-level gradient and
// a chunk of at most kChunk second-level directions (kChunk columns of the Hessian), so that the
// operands of every operation stay in cache; ceil(n_out / kChunk) passes. The first-level
// derivative vectors hold at most MaxN entries inline, so the O(n) temporaries that every nested
// operation creates per second-level direction live on the stack instead of the heap
// (MaxN = Dynamic: heap, for the largest problems).
constexpr int kChunk = 32;

template <int MaxN>
using AD1f = Eigen::AutoDiffScalar<Eigen::Matrix<double, Eigen::Dynamic, 1, 0, MaxN, 1>>;
template <int MaxN>
using AD2f = Eigen::AutoDiffScalar<Eigen::Matrix<AD1f<MaxN>, Eigen::Dynamic, 1>>;

struct NestedPass {
  virtual ~NestedPass() = default;
  // At qc: grad = dL_d/dq_in (n_in), H = d^2 L_d / dq_in dq_out (n_in x n_out).
  virtual void run(Lagrangian& lag, const MatX& qc, MatX& H, VecX& grad) = 0;
};

template <int MaxN>
struct NestedPassT final : NestedPass {
  int n_out, chunk;
  Work<AD2f<MaxN>> ws;
  NestedPassT(int n_in, int n_out_, int chunk_, std::vector<int> in, std::vector<int> out, int pool, int n,
              const Vec3& g)
      : n_out(n_out_), chunk(chunk_), ws(n_in, chunk_, std::move(in), std::move(out), pool, n, g) {}
  void run(Lagrangian& lag, const MatX& qc, MatX& H, VecX& grad) override {
    H.resize(ws.n_in, n_out);
    for (int c0 = 0; c0 < n_out; c0 += chunk) {
      ws.out_begin = c0;
      lag.eval(ws, qc);
      if (c0 == 0) grad = ws.L.value().derivatives();
      const auto& D = ws.L.derivatives();
      for (int c = 0; c < chunk && c0 + c < n_out; ++c) H.col(c0 + c) = D[c].derivatives();
    }
  }
};

std::unique_ptr<NestedPass> make_nested(int n_in, int n_out, std::vector<int> in, std::vector<int> out, int pool,
                                        int n, const Vec3& g) {
  const int passes = (n_out + kChunk - 1) / kChunk, chunk = (n_out + passes - 1) / passes;
  auto make = [&](auto tag) -> std::unique_ptr<NestedPass> {
    constexpr int M = decltype(tag)::value;
    return std::make_unique<NestedPassT<M>>(n_in, n_out, chunk, std::move(in), std::move(out), pool, n, g);
  };
  if (n_in <= 32) return make(std::integral_constant<int, 32>());
  if (n_in <= 128) return make(std::integral_constant<int, 128>());
  if (n_in <= 512) return make(std::integral_constant<int, 512>());
  return make(std::integral_constant<int, Eigen::Dynamic>());
}

}  // namespace

struct AutodiffDel::Impl : Lagrangian {
  int m = 0;
  VecX damping;          // c_i
  MatX B;                // actuation, n x m
  std::unique_ptr<Work<double>> wd;
  std::unique_ptr<Work<AD1>> w1;
  std::unique_ptr<NestedPass> nj, nh;  // second level q^{1..s} / first q^{0..s-1}; all q^{0..s} for both
  MatX R, J, H;
  VecX grad, rv;
  Eigen::PartialPivLU<MatX> lu;

  void check_q(const MatX& qc) const {
    if (qc.rows() != n || qc.cols() != s + 1)
      throw InputError("AutodiffDel: qc must be " + std::to_string(n) + " x " + std::to_string(s + 1));
  }
  void check_u(const MatX& u) const {
    if (m > 0 && (u.rows() != m || u.cols() != s + 1))
      throw InputError("AutodiffDel: u must be " + std::to_string(m) + " x " + std::to_string(s + 1));
  }

  // The discrete joint forces F^a = w^a dt (-c q̇^a + B u^a), added to column a of out (a < cols).
  void add_forces(const MatX& u, MatX& out) const {
    for (int a = 0; a < out.cols(); ++a) {
      const double wdt = w[a] * dt;
      out.col(a) -= wdt * damping.cwiseProduct(qd.col(a));
      if (m > 0) out.col(a) += wdt * (B * u.col(a));
    }
  }

  // J = d r^{0..s-1} / d q^{1..s} (and the gradient D_{1..s} L_d) from one nested pass.
  void nested_jacobian(const MatX& qc) {
    const int sn = s * n;
    if (!nj) {
      std::vector<int> in(s + 1, -1), out(s + 1, -1);
      for (int a = 0; a < s; ++a) in[a] = a * n;
      for (int a = 1; a <= s; ++a) out[a] = (a - 1) * n;
      nj = make_nested(sn, sn, in, out, pool_size, n, g);
    }
    nj->run(*this, qc, J, grad);
    // dF^a_i / dq_i^c = -w^a c_i b^{ac}
    for (int a = 0; a < s; ++a)
      for (int c = 1; c <= s; ++c)
        for (int i = 0; i < n; ++i) J(a * n + i, (c - 1) * n + i) -= w[a] * damping[i] * b(a, c);
  }
};

AutodiffDel::AutodiffDel(const Model& model, const Quadrature& quad, double dt) : impl_(std::make_unique<Impl>()) {
  if (!model.wrenches.empty())
    throw ModelError("AutodiffDel: body wrench elements are not supported by the automatic-differentiation baseline");
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError("AutodiffDel: dt must be positive and finite");
  Impl& im = *impl_;
  im.n = model.n();
  im.s = quad.s;
  im.m = model.n_controls();
  im.dt = dt;
  im.w = quad.w;
  im.b = quad.b;
  const int S1 = im.s + 1;
  im.unit.assign(S1 * S1, 0.0);
  im.bdt.resize(S1 * S1);
  for (int a = 0; a < S1; ++a) {
    im.unit[a * S1 + a] = 1;
    for (int c = 0; c < S1; ++c) im.bdt[a * S1 + c] = quad.b(a, c) / dt;
  }
  im.g = model.gravity;
  const JointForces& jf = model.joint_forces;
  im.damping = jf.damping.size() == im.n ? jf.damping : VecX::Zero(im.n);
  im.B = im.m > 0 ? jf.actuation : MatX::Zero(im.n, 0);
  im.qd.resize(im.n, S1);

  im.body.resize(im.n);
  for (int i = 0; i < im.n; ++i) {
    BodyConst& B = im.body[i];
    B.parent = model.parent[i];
    B.nchild = static_cast<int>(model.children[i].size());
    const Vec3 sw = model.S[i].head<3>(), sv = model.S[i].tail<3>();
    const Mat3 R0 = model.g_parent0[i].R;
    const Vec3 p0 = model.g_parent0[i].p;
    B.th = sw.norm();
    B.screw = B.th >= 1e-14;  // as exp_twist
    Mat3 C1 = Mat3::Zero(), C2 = Mat3::Zero();
    Vec3 d0, d1 = Vec3::Zero(), d2 = Vec3::Zero();
    if (B.screw) {
      const Mat3 A = hat(sw / B.th);
      C1 = R0 * A;
      C2 = R0 * A * A;
      d0 = R0 * sv / B.th;
      d1 = C1 * sv / B.th;
      d2 = C2 * sv / B.th;
    } else {
      d0 = R0 * sv;
    }
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        B.R0[3 * r + c] = R0(r, c);
        B.C1[3 * r + c] = C1(r, c);
        B.C2[3 * r + c] = C2(r, c);
      }
      B.p0[r] = p0[r];
      B.d0[r] = d0[r];
      B.d1[r] = d1[r];
      B.d2[r] = d2[r];
      B.sw[r] = sw[r];
      B.sv[r] = sv[r];
      B.h[r] = model.M[i].h[r];
    }
    const Mat3& I = model.M[i].I;
    B.I[0] = I(0, 0);
    B.I[1] = I(1, 1);
    B.I[2] = I(2, 2);
    B.I[3] = I(0, 1);
    B.I[4] = I(0, 2);
    B.I[5] = I(1, 2);
    B.m = model.M[i].m;
    B.has_h = model.M[i].h.squaredNorm() > 0;
    if (jf.stiffness.size() == im.n) B.k = jf.stiffness[i];
    if (jf.preload.size() == im.n) B.preload = jf.preload[i];
    B.armature = model.armature[i];
  }
  // Largest number of body states alive at once when the bodies are visited in index order.
  int live = 0;
  std::vector<int> pending(im.n);
  for (int i = 0; i < im.n; ++i) pending[i] = im.body[i].nchild;
  for (int i = 0; i < im.n; ++i) {
    im.pool_size = std::max(im.pool_size, ++live);
    if (im.body[i].parent >= 0 && --pending[im.body[i].parent] == 0) --live;
    if (im.body[i].nchild == 0) --live;
  }
}

AutodiffDel::~AutodiffDel() = default;
AutodiffDel::AutodiffDel(AutodiffDel&&) noexcept = default;
AutodiffDel& AutodiffDel::operator=(AutodiffDel&&) noexcept = default;

int AutodiffDel::n() const { return impl_->n; }
int AutodiffDel::s() const { return impl_->s; }
double AutodiffDel::dt() const { return impl_->dt; }

double AutodiffDel::lagrangian(const MatX& qc) {
  Impl& im = *impl_;
  im.check_q(qc);
  if (!im.wd) im.wd = std::make_unique<Work<double>>(0, 0, std::vector<int>(im.s + 1, -1),
                                                     std::vector<int>(im.s + 1, -1), im.pool_size, im.n, im.g);
  im.eval(*im.wd, qc);
  // the constant of the springs' 1/2 k (q - qref)^2 = 1/2 k q^2 - preload q + 1/2 preload^2 / k
  double c = 0;
  for (const BodyConst& B : im.body)
    if (B.k != 0) c -= 0.5 * B.preload * B.preload / B.k;
  return im.wd->L + c * im.w.sum() * im.dt;
}

void AutodiffDel::residual(const MatX& qc, const VecX& p, const MatX& u, MatX& r, VecX& p_next) {
  Impl& im = *impl_;
  im.check_q(qc);
  im.check_u(u);
  if (p.size() != im.n) throw InputError("AutodiffDel: p must have n entries");
  const int n = im.n, s = im.s, N = (s + 1) * n;
  if (!im.w1) {
    std::vector<int> in(s + 1);
    for (int a = 0; a <= s; ++a) in[a] = a * n;
    im.w1 = std::make_unique<Work<AD1>>(N, 0, in, std::vector<int>(s + 1, -1), im.pool_size, n, im.g);
  }
  im.eval(*im.w1, qc);
  // D_{a+1} L_d = block a of the gradient
  im.R = Eigen::Map<const MatX>(im.w1->L.derivatives().data(), n, s + 1);  // column a: D_{a+1} L_d
  im.add_forces(u, im.R);
  r = im.R.leftCols(s);
  r.col(0) += p;
  p_next = im.R.col(s);
}

void AutodiffDel::jacobian(const MatX& qc, const MatX& u, MatX& J) {
  Impl& im = *impl_;
  im.check_q(qc);
  im.check_u(u);
  im.nested_jacobian(qc);
  J = im.J;
}

void AutodiffDel::newton_direction(const MatX& qc, const VecX& p, const MatX& u, MatX& dq) {
  Impl& im = *impl_;
  im.check_q(qc);
  im.check_u(u);
  if (p.size() != im.n) throw InputError("AutodiffDel: p must have n entries");
  const int n = im.n, s = im.s;
  im.nested_jacobian(qc);
  // r^a = D_{a+1} L_d + F^a (+ p for a = 0): the first-level gradient of the same pass
  im.R = Eigen::Map<const MatX>(im.grad.data(), n, s);
  im.add_forces(u, im.R);
  im.R.col(0) += p;
  im.rv = Eigen::Map<const VecX>(im.R.data(), n * s);
  im.lu.compute(im.J);
  dq.resize(n, s);
  Eigen::Map<VecX>(dq.data(), n * s) = -im.lu.solve(im.rv);
}

void AutodiffDel::d2Ld(const MatX& qc, MatX& H) {
  Impl& im = *impl_;
  im.check_q(qc);
  const int n = im.n, s = im.s, N = (s + 1) * n;
  if (!im.nh) {
    std::vector<int> off(s + 1);
    for (int a = 0; a <= s; ++a) off[a] = a * n;
    im.nh = make_nested(N, N, off, off, im.pool_size, n, im.g);
  }
  im.nh->run(im, qc, H, im.grad);
}

}  // namespace hovi
