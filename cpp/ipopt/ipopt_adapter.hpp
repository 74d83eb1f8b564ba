// IPOPT (its C++ interface, the TNLP) on an NlpProgram: every callback is C++; the Hessian is the
// program's LagrangianHessian or, without one, IPOPT's limited-memory approximation. An exception
// thrown by an evaluation (a Python hook's included) is kept, IPOPT is told the evaluation failed
// and is stopped at its next iteration, and `solve` rethrows it.
#pragma once
#include <IpTNLP.hpp>
#include <exception>
#include <functional>
#include <limits>
#include <string>

#include "hovi/trajopt/lagrangian_hessian.hpp"

namespace hovi {

// After each iteration: (iteration, cost, primal and dual infeasibility, mu); false stops IPOPT.
using IterationCallback = std::function<bool(int, double, double, double, double)>;

struct IpoptProblemData {
  VecX lower, upper, cl, cu, x0;
};

struct IpoptOutcome {
  int status = 0;                     // IPOPT's ApplicationReturnStatus
  int iterations = 0;
  double cost = std::numeric_limits<double>::quiet_NaN();   // NaN if IPOPT stopped before a solution
  VecX x, lambda, z_lower, z_upper;
  double seconds = 0.0;               // wall time of OptimizeTNLP
  double callback_seconds = 0.0;      // time in the callbacks (evaluations and the hook)
  double hessian_seconds = 0.0;       // of which in the Hessian
};

class IpoptAdapter : public Ipopt::TNLP {
 public:
  IpoptAdapter(const NlpProgram& program, const LagrangianHessian* hessian, const IpoptProblemData& data,
               IterationCallback callback, IpoptOutcome& out);
  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                    IndexStyleEnum& style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m, Ipopt::Number* g_l,
                       Ipopt::Number* g_u) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                          Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda, Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number& f) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number* grad) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Index nnz,
                  Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) override;
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number sigma, Ipopt::Index m,
              const Ipopt::Number* lambda, bool new_lambda, Ipopt::Index nnz, Ipopt::Index* rows, Ipopt::Index* cols,
              Ipopt::Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x, const Ipopt::Number* z_L,
                         const Ipopt::Number* z_U, Ipopt::Index m, const Ipopt::Number* g, const Ipopt::Number* lambda,
                         Ipopt::Number obj_value, const Ipopt::IpoptData* ip_data,
                         Ipopt::IpoptCalculatedQuantities* ip_cq) override;
  bool intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter, Ipopt::Number obj_value,
                             Ipopt::Number inf_pr, Ipopt::Number inf_du, Ipopt::Number mu, Ipopt::Number d_norm,
                             Ipopt::Number regularization_size, Ipopt::Number alpha_du, Ipopt::Number alpha_pr,
                             Ipopt::Index ls_trials, const Ipopt::IpoptData* ip_data,
                             Ipopt::IpoptCalculatedQuantities* ip_cq) override;

  std::exception_ptr error;           // the first exception of an evaluation or of the callback

 private:
  template <class F>
  bool guarded(F&& f, double* hessian_clock = nullptr);
  const NlpProgram& p_;
  const LagrangianHessian* H_;
  const IpoptProblemData& d_;
  IterationCallback callback_;
  IpoptOutcome& out_;
};

// Options by type, as IPOPT's OptionsList takes them; false when IPOPT refuses the name or value.
struct IpoptOption {
  std::string name;
  enum Kind { Text, Integer, Number } kind;
  std::string text;
  int integer = 0;
  double number = 0.0;
};

// Runs IPOPT with `options` (applied before Initialize) and returns the outcome; rethrows an
// evaluation's exception. Throws InputError naming an option IPOPT refused.
IpoptOutcome solve_with_ipopt(const NlpProgram& program, const LagrangianHessian* hessian,
                              const IpoptProblemData& data, const std::vector<IpoptOption>& options,
                              IterationCallback callback);
// Whether IPOPT takes the option (checked on a fresh application).
bool ipopt_accepts(const IpoptOption& option);

}  // namespace hovi
