#include "ipopt_adapter.hpp"

#include <IpIpoptApplication.hpp>
#include <chrono>

#include "hovi/errors.hpp"

namespace hovi {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

bool set_option(Ipopt::OptionsList& list, const IpoptOption& o) {
  switch (o.kind) {
    case IpoptOption::Text: return list.SetStringValue(o.name, o.text);
    case IpoptOption::Integer: return list.SetIntegerValue(o.name, o.integer);
    default: return list.SetNumericValue(o.name, o.number);
  }
}
}  // namespace

IpoptAdapter::IpoptAdapter(const NlpProgram& program, const LagrangianHessian* hessian, const IpoptProblemData& data,
                           IterationCallback callback, IpoptOutcome& out)
    : p_(program), H_(hessian), d_(data), callback_(std::move(callback)), out_(out) {}

template <class F>
bool IpoptAdapter::guarded(F&& f, double* hessian_clock) {
  if (error) return false;
  const auto t0 = Clock::now();
  try {
    f();
  } catch (...) {
    error = std::current_exception();
  }
  const double dt = since(t0);
  out_.callback_seconds += dt;
  if (hessian_clock) *hessian_clock += dt;
  return !error;
}

bool IpoptAdapter::get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                                IndexStyleEnum& style) {
  n = p_.n_variables();
  m = p_.n_constraints();
  nnz_jac = p_.nnz();
  nnz_h = H_ ? H_->nnz() : 0;
  style = C_STYLE;
  return true;
}

bool IpoptAdapter::get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                                   Ipopt::Number* g_l, Ipopt::Number* g_u) {
  Eigen::Map<VecX>(x_l, n) = d_.lower;
  Eigen::Map<VecX>(x_u, n) = d_.upper;
  Eigen::Map<VecX>(g_l, m) = d_.cl;
  Eigen::Map<VecX>(g_u, m) = d_.cu;
  return true;
}

bool IpoptAdapter::get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                                      Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda, Ipopt::Number* lambda) {
  if (init_x) Eigen::Map<VecX>(x, n) = d_.x0;
  // IPOPT asks for multipliers only with the option warm_start_init_point 'yes': zeros
  if (init_z) {
    Eigen::Map<VecX>(z_L, n).setZero();
    Eigen::Map<VecX>(z_U, n).setZero();
  }
  if (init_lambda) Eigen::Map<VecX>(lambda, m).setZero();
  return true;
}

bool IpoptAdapter::eval_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number& f) {
  return guarded([&] { f = p_.objective(Eigen::Map<const VecX>(x, n)); });
}

bool IpoptAdapter::eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number* grad) {
  return guarded([&] { p_.gradient(Eigen::Map<const VecX>(x, n), Eigen::Map<VecX>(grad, n)); });
}

bool IpoptAdapter::eval_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index m, Ipopt::Number* g) {
  return guarded([&] { p_.constraints(Eigen::Map<const VecX>(x, n), Eigen::Map<VecX>(g, m)); });
}

bool IpoptAdapter::eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Index nnz,
                              Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) {
  if (values == nullptr) {
    Eigen::Map<Eigen::VectorXi>(rows, nnz) = p_.jac_rows();
    Eigen::Map<Eigen::VectorXi>(cols, nnz) = p_.jac_cols();
    return true;
  }
  return guarded([&] { p_.jacobian(Eigen::Map<const VecX>(x, n), Eigen::Map<VecX>(values, nnz)); });
}

bool IpoptAdapter::eval_h(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number sigma, Ipopt::Index m,
                          const Ipopt::Number* lambda, bool, Ipopt::Index nnz, Ipopt::Index* rows, Ipopt::Index* cols,
                          Ipopt::Number* values) {
  if (H_ == nullptr) return false;
  if (values == nullptr) {
    Eigen::Map<Eigen::VectorXi>(rows, nnz) = H_->colouring().rows;
    Eigen::Map<Eigen::VectorXi>(cols, nnz) = H_->colouring().cols;
    return true;
  }
  return guarded([&] {
    H_->values(Eigen::Map<const VecX>(x, n), Eigen::Map<const VecX>(lambda, m), sigma, Eigen::Map<VecX>(values, nnz));
  }, &out_.hessian_seconds);
}

void IpoptAdapter::finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x,
                                     const Ipopt::Number* z_L, const Ipopt::Number* z_U, Ipopt::Index m,
                                     const Ipopt::Number*, const Ipopt::Number* lambda, Ipopt::Number obj_value,
                                     const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) {
  out_.x = Eigen::Map<const VecX>(x, n);
  out_.z_lower = Eigen::Map<const VecX>(z_L, n);
  out_.z_upper = Eigen::Map<const VecX>(z_U, n);
  out_.lambda = Eigen::Map<const VecX>(lambda, m);
  out_.cost = obj_value;
}

bool IpoptAdapter::intermediate_callback(Ipopt::AlgorithmMode, Ipopt::Index iter, Ipopt::Number obj_value,
                                         Ipopt::Number inf_pr, Ipopt::Number inf_du, Ipopt::Number mu, Ipopt::Number,
                                         Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Index,
                                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) {
  out_.iterations = iter;
  if (error) return false;
  if (!callback_) return true;
  bool go = true;
  guarded([&] { go = callback_(iter, obj_value, inf_pr, inf_du, mu); });
  return go && !error;
}

IpoptOutcome solve_with_ipopt(const NlpProgram& program, const LagrangianHessian* hessian,
                              const IpoptProblemData& data, const std::vector<IpoptOption>& options,
                              IterationCallback callback) {
  const int n = program.n_variables(), m = program.n_constraints();
  if (data.x0.size() != n || data.lower.size() != n || data.upper.size() != n)
    throw InputError("x0, lower and upper must have one entry per variable (" + std::to_string(n) + ")");
  if (data.cl.size() != m || data.cu.size() != m)
    throw InputError("cl and cu must have one entry per constraint (" + std::to_string(m) + ")");
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->RethrowNonIpoptException(false);
  for (const IpoptOption& o : options)
    if (!set_option(*app->Options(), o)) throw InputError("IPOPT refused the option '" + o.name + "'");
  if (!hessian && !app->Options()->SetStringValueIfUnset("hessian_approximation", "limited-memory"))
    throw InputError("could not set hessian_approximation");
  IpoptOutcome out;
  Ipopt::ApplicationReturnStatus status = app->Initialize();
  if (status != Ipopt::Solve_Succeeded) {
    out.status = status;
    return out;
  }
  program.reset_timers();
  Ipopt::SmartPtr<IpoptAdapter> adapter = new IpoptAdapter(program, hessian, data, std::move(callback), out);
  const auto t0 = Clock::now();
  status = app->OptimizeTNLP(Ipopt::SmartPtr<Ipopt::TNLP>(GetRawPtr(adapter)));
  out.seconds = since(t0);
  out.status = status;
  if (adapter->error) std::rethrow_exception(adapter->error);
  if (out.x.size() != n) out.x = data.x0;   // IPOPT stopped before finalize_solution
  return out;
}

bool ipopt_accepts(const IpoptOption& option) {
  // one application per thread, quiet: building one registers all of IPOPT's options (milliseconds)
  thread_local Ipopt::SmartPtr<Ipopt::IpoptApplication> app;
  if (!Ipopt::IsValid(app)) {
    app = IpoptApplicationFactory();
    app->Jnlst()->DeleteAllJournals();
  }
  return set_option(*app->Options(), option);
}

}  // namespace hovi
