// The lower triangle of the Hessian of the Lagrangian sigma f + lambda^T g of an NlpProgram:
//   the quadratic costs' part exact (sigma H);
//   the transcription's part its own Hessian where it has one (the VI: del_hessian.hpp, two
//     D^2 L_d per stage), the built-in rows' (RowBlocks) theirs, unless told to difference them;
//   the rest, like the caller's terms (Python), forward differences of the gradient along coloured
//     directions (one difference per colour of a star colouring of the Hessian's pattern;
//     python/hovi/trajopt/hessian.py chooses the pattern and the colours and documents the method).
#pragma once
#include <utility>

#include "hovi/trajopt/colouring.hpp"
#include "hovi/trajopt/nlp_program.hpp"

namespace hovi {

struct HessianColouring {
  Eigen::VectorXi colour;              // (n,) colour of each variable, 0 .. n_colours - 1
  Eigen::VectorXi rows, cols;          // the lower triangle's entries (rows >= cols)
  Eigen::VectorXi read_row, read_col;  // entry e = difference of read_col's colour, component read_row, / h[read_col]
};

// The entries of the coupling pattern P (symmetric, with the diagonal) where the Lagrangian's
// Hessian is not identically zero, as a symmetric pattern (indptr, indices, sorted): found at a
// random point near x (each variable moved by 10% of max(1, |x_j|), random multipliers) by one
// gradient change per distance-2 colour of P (python/hovi/trajopt/hessian.py documents it), plus
// the quadratic costs' entries and the diagonal. own_structures: the parts with Hessians of their
// own (the transcription's, if it has one; the built-in rows') add the entries of those Hessians
// above 1e-14 of their largest at that point instead of being probed, and only the rest is probed
// (nothing, if nothing is left).
std::pair<Eigen::VectorXi, Eigen::VectorXi> probed_pattern(const NlpProgram& program, const Pattern& P,
                                                           const VecX& x, unsigned seed, bool own_structures = false);

class LagrangianHessian {
 public:
  // Throws InputError for colours or entries out of range or of different lengths. The colours'
  // differences of the C++ parts and the transcription's own Hessian run on `threads` threads
  // (parallel_for.hpp's thread_count), the caller's extra terms (Python, the GIL) on the calling
  // thread; the values do not depend on the number of threads.
  // by_differences: difference the transcription's and the built-in rows' parts even where they
  // have Hessians of their own.
  LagrangianHessian(const NlpProgram& program, HessianColouring colouring, int threads = 1,
                    bool by_differences = false);
  int nnz() const { return static_cast<int>(c_.rows.size()); }
  int n_colours() const { return n_colours_; }
  int threads() const { return threads_; }
  // Whether the transcription's part comes from its own Hessian (not differenced).
  bool transcription_hessian() const { return own_; }
  const HessianColouring& colouring() const { return c_; }
  // values (nnz,) at (x, lambda, sigma).
  void values(const VecX& x, const VecX& lambda, double sigma, Eigen::Ref<VecX> values) const;

 private:
  const NlpProgram& p_;
  HessianColouring c_;
  int n_colours_, threads_;
  bool by_differences_, own_;
  int differenced_;                     // the C++ parts differenced (NlpProgram::Part flags)
  std::vector<int> own_entry_;          // the transcription's Hessian entry i -> entry, -1 outside the pattern
  std::vector<std::vector<int>> block_entry_;   // the same for each row block's Hessian
  VecX cost_values_;                    // H at (rows, cols)
  std::vector<std::vector<int>> by_colour_;   // variables of each colour
  std::vector<std::vector<int>> entries_;     // entries read from each colour's difference
};

}  // namespace hovi
