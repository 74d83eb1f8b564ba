// Constraint rows of a program beside its transcription that C++ evaluates with their own exact
// Hessian (the body-point path constraints, body_point_rows.hpp; the contact complementarity rows,
// complementarity_rows.hpp), so that a solve through them never returns to Python.
#pragma once
#include <memory>

#include "hovi/trajopt/transcription.hpp"

namespace hovi {

class RowBlock {
 public:
  virtual ~RowBlock() = default;
  virtual int n_variables() const = 0;
  virtual int rows() const = 0;
  // Number of Jacobian values jacobian() writes (its structure is the caller's; python/hovi/trajopt/nlp.py).
  virtual int nnz() const = 0;
  virtual void values(const VecX& x, Eigen::Ref<VecX> g) const = 0;
  virtual void jacobian(const VecX& x, Eigen::Ref<VecX> values) const = 0;
  // The lower triangle of the Hessian of lambda^T rows (lambda: rows()) at x, in hessian_structure()
  // order (rows >= cols; an entry may repeat, the values add).
  virtual const SparsityStructure& hessian_structure() const = 0;
  virtual void hessian(const VecX& x, const VecX& lambda, Eigen::Ref<VecX> values) const = 0;
};

// A block placed in a program: its rows at `rows` of g, its Jacobian values at `entries` of the
// Jacobian's values.
struct PlacedRows {
  std::shared_ptr<const RowBlock> block;
  Eigen::VectorXi rows, entries;
};

}  // namespace hovi
