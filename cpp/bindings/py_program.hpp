// The NLP program as Python holds it (hovi._core.trajopt.Program, bind_nlp_program.cpp): the C++
// program, the transcription and the Python functions of its extra terms kept alive beside it, and
// its Lagrangian Hessian once a colouring is given. hovi._ipopt solves it.
#pragma once
#include <memory>

#include "common.hpp"
#include "hovi/trajopt/lagrangian_hessian.hpp"

namespace hovi::py_bind {

struct PyProgram {
  py::object transcription;   // the Python transcription object the program reads
  py::object extra_cost, extra_constraints, extra_jacobian;   // None, or Python functions of x
  std::unique_ptr<NlpProgram> program;
  std::unique_ptr<LagrangianHessian> hessian;
};

}  // namespace hovi::py_bind
