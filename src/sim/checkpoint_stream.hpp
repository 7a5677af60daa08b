// The checkpoint file's byte stream (sim/checkpoint.cpp): fields written and read back in one
// order as the machine's own bytes, a short or damaged file refused naming it.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/types.hpp"

namespace shellcontract::detail {

class Writer {
 public:
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void size(std::size_t n) { pod(static_cast<std::uint64_t>(n)); }
  void text(const std::string& s) {
    size(s.size());
    out_ += s;
  }
  void matrix(const Positions& m) {
    size(static_cast<std::size_t>(m.rows()));
    size(static_cast<std::size_t>(m.cols()));
    out_.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * m.size());
  }
  void vector(const Eigen::VectorXd& v) {
    size(static_cast<std::size_t>(v.size()));
    out_.append(reinterpret_cast<const char*>(v.data()), sizeof(double) * v.size());
  }
  template <class T>
  void list(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    size(v.size());
    out_.append(reinterpret_cast<const char*>(v.data()), sizeof(T) * v.size());
  }
  void options(const OptionValues& o) {
    size(o.size());
    for (const auto& [name, value] : o) {
      text(name);
      text(value);
    }
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(const std::string& bytes, std::string path) : in_(bytes), path_(std::move(path)) {}
  template <class T>
  T pod() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  std::size_t size() {
    const auto n = pod<std::uint64_t>();
    if (n > remaining()) fail("a length past the end of the file");
    return static_cast<std::size_t>(n);
  }
  /// A count of entries that take at least `min_bytes` each in the file: a count the bytes left
  /// cannot hold is refused before anything is allocated for it. (Checked against the file's
  /// size alone, a forged count made the reader allocate an entry's memory, tens of bytes, for
  /// each byte of the file before the entries ran past its end.)
  std::size_t count(std::size_t min_bytes, const char* what) {
    const auto n = pod<std::uint64_t>();
    if (n > remaining() / min_bytes)
      fail(std::to_string(n) + " " + what + " of at least " + std::to_string(min_bytes) +
           " bytes each in the " + std::to_string(remaining()) + " bytes left");
    return static_cast<std::size_t>(n);
  }
  std::size_t remaining() const { return in_.size() - pos_; }
  std::string text() {
    const std::size_t n = size();
    std::string s(n, '\0');
    take(s.data(), n);
    return s;
  }
  Positions matrix() {
    const std::size_t rows = size(), cols = size();
    // Positions have 3 columns by their type: another count would be read as 3 (Eigen checks
    // the count only in debug builds), and the fields after it from the wrong bytes.
    if (cols != 3) fail("a matrix of " + std::to_string(cols) + " columns");
    if (rows > remaining() / (cols * sizeof(double))) fail("a matrix past the end");
    Positions m(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    take(m.data(), sizeof(double) * m.size());
    return m;
  }
  Eigen::VectorXd vector() {
    const std::size_t n = size();
    if (n > remaining() / sizeof(double)) fail("a vector past the end");
    Eigen::VectorXd v(static_cast<Eigen::Index>(n));
    take(v.data(), sizeof(double) * n);
    return v;
  }
  template <class T>
  std::vector<T> list() {
    const std::size_t n = size();
    if (n > remaining() / sizeof(T)) fail("a list past the end");
    std::vector<T> v(n);
    take(v.data(), sizeof(T) * n);
    return v;
  }
  OptionValues options() {
    OptionValues o(count(2 * sizeof(std::uint64_t), "options"));  // two texts' lengths each
    for (auto& [name, value] : o) {
      name = text();
      value = text();
    }
    return o;
  }
  void take(void* p, std::size_t n) {
    if (in_.size() - pos_ < n) fail("truncated");
    std::memcpy(p, in_.data() + pos_, n);
    pos_ += n;
  }
  /// An int saved as 64 bits: one outside int's range would wrap to another value when cast.
  int int_value(const char* what) {
    const auto v = pod<std::int64_t>();
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      fail(std::string(what) + " " + std::to_string(v) + " out of range");
    return static_cast<int>(v);
  }
  std::size_t position() const { return pos_; }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("checkpoint " + printable(path_) + ": " + what + " (not a whole checkpoint)");
  }

 private:
  const std::string& in_;
  std::string path_;
  std::size_t pos_ = 0;
};

}  // namespace shellcontract::detail
