#include "hovi/trajopt/colouring.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace hovi {

namespace {
// The smallest colour not marked taken[c] == stamp.
int smallest_free(const std::vector<int>& taken, int stamp) {
  int c = 0;
  while (c < static_cast<int>(taken.size()) && taken[c] == stamp) ++c;
  return c;
}
}  // namespace

std::pair<Eigen::VectorXi, Eigen::VectorXi> gram_pattern(const Pattern& A, int nv) {
  // columns of each row of A, and rows of each column: j's neighbours are the columns of j's rows
  std::vector<std::vector<int>> rows_of(nv);
  for (int r = 0; r < A.size(); ++r)
    for (int a = A.indptr[r]; a < A.indptr[r + 1]; ++a) rows_of[A.indices[a]].push_back(r);
  Eigen::VectorXi indptr(nv + 1);
  std::vector<int> indices, seen(nv, -1);
  indptr[0] = 0;
  for (int j = 0; j < nv; ++j) {
    const size_t start = indices.size();
    seen[j] = j;
    indices.push_back(j);
    for (int r : rows_of[j])
      for (int a = A.indptr[r]; a < A.indptr[r + 1]; ++a)
        if (seen[A.indices[a]] != j) {
          seen[A.indices[a]] = j;
          indices.push_back(A.indices[a]);
        }
    std::sort(indices.begin() + start, indices.end());
    indptr[j + 1] = static_cast<int>(indices.size());
  }
  return {indptr, Eigen::Map<Eigen::VectorXi>(indices.data(), static_cast<long>(indices.size()))};
}

Eigen::VectorXi distance2_colouring(const Pattern& P) {
  const int nv = P.size();
  Eigen::VectorXi colour = Eigen::VectorXi::Constant(nv, -1);
  std::vector<int> taken(nv + 1, -1);
  for (int j = 0; j < nv; ++j) {
    for (int a = P.indptr[j]; a < P.indptr[j + 1]; ++a) {
      const int k = P.indices[a];
      if (colour[k] >= 0) taken[colour[k]] = j;
      for (int b = P.indptr[k]; b < P.indptr[k + 1]; ++b)
        if (colour[P.indices[b]] >= 0) taken[colour[P.indices[b]]] = j;
    }
    colour[j] = smallest_free(taken, j);
  }
  return colour;
}

Eigen::VectorXi star_colouring(const Pattern& P) {
  const int nv = P.size();
  Eigen::VectorXi colour = Eigen::VectorXi::Constant(nv, -1);
  std::vector<int> order(nv);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return P.indptr[a + 1] - P.indptr[a] > P.indptr[b + 1] - P.indptr[b];
  });
  int width = 16;                                  // count[x * width + c]: neighbours of x with colour c
  std::vector<int> count(static_cast<size_t>(nv) * width, 0);
  std::vector<int> taken(nv + 1, -1);
  for (int v : order) {
    for (int a = P.indptr[v]; a < P.indptr[v + 1]; ++a) {
      const int w = P.indices[a];
      if (w == v) continue;
      if (colour[w] >= 0) taken[colour[w]] = v;
      for (int b = P.indptr[w]; b < P.indptr[w + 1]; ++b) {
        const int x = P.indices[b];
        if (x == v || x == w || colour[x] < 0) continue;
        // w uncoloured: v may not repeat x's colour; else a path v-w-x-y with colour(y) = colour(w)
        if (colour[w] < 0 || count[static_cast<size_t>(x) * width + colour[w]] > 1) taken[colour[x]] = v;
      }
    }
    const int c = smallest_free(taken, v);
    colour[v] = c;
    if (c >= width) {                              // widen the counts
      const int wider = 2 * width;
      std::vector<int> grown(static_cast<size_t>(nv) * wider, 0);
      for (int x = 0; x < nv; ++x)
        std::copy_n(&count[static_cast<size_t>(x) * width], width, &grown[static_cast<size_t>(x) * wider]);
      count.swap(grown);
      width = wider;
    }
    for (int a = P.indptr[v]; a < P.indptr[v + 1]; ++a)
      if (P.indices[a] != v) ++count[static_cast<size_t>(P.indices[a]) * width + c];
  }
  return colour;
}

}  // namespace hovi
