// Shared helpers of the pybind11 bindings: array conversion with clear errors.
#pragma once
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "hovi/spatial/types.hpp"

namespace hovi::py_bind {
namespace py = pybind11;

// A 1-D float array of length n (n < 0: any length) converted to VecX; ValueError otherwise.
VecX as_vector(const py::handle& obj, const char* name, long n);
// A 2-D float array of shape (rows, cols) (negative: any) converted to MatX; ValueError otherwise.
MatX as_matrix(const py::handle& obj, const char* name, long rows, long cols);
// A stack of SE(3)/4x4 or 6-vectors as numpy arrays of shape (n, 4, 4) / (n, 6).
py::array_t<double> stack(const std::vector<Mat4>& mats);
py::array_t<double> stack(const std::vector<Vec6>& vecs);

void bind_model(py::module_& m);
void bind_integrator(py::module_& m);
void bind_linearizer(py::module_& m);
void bind_baselines(py::module_& m);
void bind_trajopt(py::module_& m);

}  // namespace hovi::py_bind
