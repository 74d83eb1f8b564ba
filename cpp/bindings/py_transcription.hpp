// A C++ transcription held by Python, with a watch on the model it copied (bind_trajopt.cpp binds
// them; bind_nlp_program.cpp reads them for the NLP program).
#pragma once
#include "py_model.hpp"

namespace hovi::py_bind {

// A transcription with a watch on the model it copied.
template <class T>
struct PyTranscription {
  template <class... Args>
  PyTranscription(std::shared_ptr<const PyModel> m, Args&&... args)
      : t(m->model, std::forward<Args>(args)...), watch(std::move(m), "trajopt transcription") {}
  const T& get() const {
    watch.check();
    return t;
  }
  T t;
  ModelWatch watch;
};

}  // namespace hovi::py_bind
