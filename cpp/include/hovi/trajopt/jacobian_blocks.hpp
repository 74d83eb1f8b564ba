// Building a fixed sparsity structure from dense and diagonal blocks, and writing the values of
// those blocks in the same order (row by row within a block), for the transcriptions.
#pragma once
#include <vector>

#include "hovi/trajopt/transcription.hpp"

namespace hovi {

class BlockStructure {
 public:
  void dense(int r0, int c0, int rows, int cols) {
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) add(r0 + i, c0 + j);
  }
  void diagonal(int r0, int c0, int size) {
    for (int i = 0; i < size; ++i) add(r0 + i, c0 + i);
  }
  SparsityStructure finish() const {
    SparsityStructure s;
    s.rows = Eigen::Map<const Eigen::VectorXi>(rows_.data(), rows_.size());
    s.cols = Eigen::Map<const Eigen::VectorXi>(cols_.data(), cols_.size());
    return s;
  }

 private:
  void add(int r, int c) {
    rows_.push_back(r);
    cols_.push_back(c);
  }
  std::vector<int> rows_, cols_;
};

// Writes the values of a dense block (row by row) or of a constant diagonal at values[at..];
// returns the next position.
inline int put_dense(Eigen::Ref<VecX> values, int at, const Eigen::Ref<const MatX>& B) {
  for (int i = 0; i < B.rows(); ++i)
    for (int j = 0; j < B.cols(); ++j) values[at++] = B(i, j);
  return at;
}
inline int put_diagonal(Eigen::Ref<VecX> values, int at, int size, double value) {
  values.segment(at, size).setConstant(value);
  return at + size;
}

}  // namespace hovi
