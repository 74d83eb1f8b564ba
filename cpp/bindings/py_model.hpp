// The Python-side model shared by the bindings: the core Model plus a lazily sized workspace.
#pragma once
#include <memory>

#include "common.hpp"
#include "hovi/model/data.hpp"

namespace hovi::py_bind {

// The Python-side model: the immutable core Model plus a lazily (re)sized workspace.
struct PyModel {
  Model model;
  std::unique_ptr<Data> data;
  Data& ws() {
    if (!data || static_cast<int>(data->g.size()) != model.n()) data = std::make_unique<Data>(model);
    return *data;
  }
  VecX vec(const py::handle& x, const char* name) { return as_vector(x, name, model.n()); }
};

// Index of a joint given as int or name; ModelError otherwise.
int joint_arg(const Model& model, const py::handle& joint);
// Index of a body given as int or link name; ModelError otherwise.
int body_arg(const Model& model, const py::handle& body);

}  // namespace hovi::py_bind
