// The Python-side model shared by the bindings: the core Model plus a lazily sized workspace.
#pragma once
#include <memory>
#include <string>

#include "common.hpp"
#include "hovi/errors.hpp"
#include "hovi/model/data.hpp"

namespace hovi::py_bind {

// The Python-side model: the core Model plus a lazily (re)sized workspace, and a count of the
// changes made to it so that objects built from a copy of it (integrators) can tell they are stale.
struct PyModel {
  Model model;
  std::unique_ptr<Data> data;
  long revision = 0;
  std::string last_change;
  void changed(const char* what) {
    ++revision;
    last_change = what;
  }
  Data& ws() {
    if (!data || static_cast<int>(data->g.size()) != model.n()) data = std::make_unique<Data>(model);
    return *data;
  }
  VecX vec(const py::handle& x, const char* name) { return as_vector(x, name, model.n()); }
  // The model's algorithms' q: a free base's public q (nq,) in the chart about its attitude (θ = 0),
  // the workspace's kinematics about it; else q (n,).
  VecX config(const py::handle& q);
  // A velocity (n,) at config(q)'s q: a free base's v -> q̇ = T v; else as given.
  VecX velocity(const VecX& q, const py::handle& v, const char* name);
  Mat3 attitude = Mat3::Identity();  // a free base: config's attitude
  MatX velocity_map(const VecX& q);  // T (n x n) at config(q)'s q: q̇ = T v
  // ModelError for a free base: `what` is in joint coordinates, which the free base does not have.
  void chart_coordinates_only(const char* what) const;
};

// What an object built from a PyModel (it copies the model) remembers of it: a later change to
// the model makes every call of that object raise ModelError instead of silently using the copy.
class ModelWatch {
 public:
  ModelWatch(std::shared_ptr<const PyModel> source, const char* owner)
      : source_(std::move(source)), revision_(source_->revision), owner_(owner) {}
  void check() const {
    if (source_->revision != revision_)
      throw ModelError(std::string("the model was changed (") + source_->last_change + ") after this " + owner_ +
                       " was made from it; the " + owner_ + " works on a copy of the model and would ignore the "
                       "change: make a new hovi." + owner_ + " from the changed model (copy the model with "
                       "Model.copy() first to keep both versions)");
  }

 private:
  std::shared_ptr<const PyModel> source_;
  long revision_;
  const char* owner_;
};

// Index of a joint given as int or name; ModelError otherwise.
int joint_arg(const Model& model, const py::handle& joint);
// Index of a body given as int or link name; ModelError otherwise.
int body_arg(const Model& model, const py::handle& body);

}  // namespace hovi::py_bind
