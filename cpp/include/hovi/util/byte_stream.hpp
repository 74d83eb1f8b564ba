// A flat binary record of numbers, strings and Eigen matrices (the bytes of a pickled Model):
// values are written in this machine's byte order, bit for bit, and read back in the order they
// were written. Reading past the end, or a length that the remaining bytes cannot hold, throws
// ModelError: a truncated or corrupt record never reads out of bounds.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>

#include <Eigen/Core>

#include "hovi/errors.hpp"

namespace hovi {

class ByteWriter {
 public:
  template <class T, class = std::enable_if_t<std::is_arithmetic_v<T>>>
  void put(T x) {
    bytes_.append(reinterpret_cast<const char*>(&x), sizeof x);
  }
  void put(const std::string& s) {
    put(static_cast<std::uint64_t>(s.size()));
    bytes_ += s;
  }
  template <class D>
  void put(const Eigen::DenseBase<D>& m) {  // dimensions, then the entries column by column
    put(static_cast<std::int64_t>(m.rows()));
    put(static_cast<std::int64_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j)
      for (Eigen::Index i = 0; i < m.rows(); ++i) put(static_cast<double>(m(i, j)));
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
  template <class T, class = std::enable_if_t<std::is_arithmetic_v<T>>>
  T get() {
    T x;
    std::memcpy(&x, take(sizeof x), sizeof x);
    return x;
  }
  std::string get_string() {
    const auto size = get<std::uint64_t>();
    if (size > left()) corrupt();
    return std::string(take(size), size);
  }
  // A matrix of the written dimensions; with fixed-size M they must match its size.
  template <class M>
  M get_matrix() {
    const auto rows = get<std::int64_t>(), cols = get<std::int64_t>();
    if (rows < 0 || cols < 0 || (rows && static_cast<std::uint64_t>(cols) > left() / 8 / rows)) corrupt();
    if ((M::RowsAtCompileTime != Eigen::Dynamic && rows != M::RowsAtCompileTime) ||
        (M::ColsAtCompileTime != Eigen::Dynamic && cols != M::ColsAtCompileTime))
      corrupt();
    M m;
    m.resize(rows, cols);
    for (Eigen::Index j = 0; j < cols; ++j)
      for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = get<double>();
    return m;
  }
  bool at_end() const { return pos_ == bytes_.size(); }
  std::size_t position() const { return pos_; }  // bytes read so far
  [[noreturn]] static void corrupt() { throw ModelError("the serialised model is truncated or corrupt"); }

 private:
  std::size_t left() const { return bytes_.size() - pos_; }
  const char* take(std::size_t n) {
    if (n > left()) corrupt();
    const char* at = bytes_.data() + pos_;
    pos_ += n;
    return at;
  }
  const std::string& bytes_;
  std::size_t pos_ = 0;
};

}  // namespace hovi
