// Small valid meshes in every format the reader supports, and a seeded, deterministic mutator
// over them. Each seed file is an octahedron with vertices on {0, 1, 2}^3, so that
// every PLY coordinate type (uchar to double) holds it exactly.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "support/gltf_files.hpp"

namespace shellcontract::test {

/// One valid input file: its extension (which picks the reader) and its bytes.
struct SeedFile {
  std::string name;  ///< unique, for messages
  std::string ext;   ///< a row of MESH_FORMATS (src/mesh/formats.hpp): every row has seeds
  std::string bytes;
};

inline constexpr std::array<std::array<int, 3>, 6> OCTA_POINTS{{{2, 1, 1}, {0, 1, 1}, {1, 2, 1}, {1, 0, 1}, {1, 1, 2}, {1, 1, 0}}};
inline constexpr std::array<std::array<int, 3>, 8> OCTA_FACES{
    {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}}};

/// Appends the `size` low bytes of `v` in little- or big-endian order.
inline void put_bytes(std::string& out, std::uint64_t v, int size, bool big_endian) {
  for (int i = 0; i < size; ++i) {
    const int shift = 8 * (big_endian ? size - 1 - i : i);
    out += static_cast<char>((v >> shift) & 0xFF);
  }
}

inline void put_float(std::string& out, float f, bool big_endian) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, 4);
  put_bytes(out, u, 4, big_endian);
}

inline void put_double(std::string& out, double d, bool big_endian) {
  std::uint64_t u = 0;
  std::memcpy(&u, &d, 8);
  put_bytes(out, u, 8, big_endian);
}

inline std::string octa_off() {
  std::string s = "OFF\n6 8 0\n";
  for (const auto& p : OCTA_POINTS) s += std::to_string(p[0]) + ".0 " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  for (const auto& f : OCTA_FACES) s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  return s;
}

/// "OFF BINARY" as CGAL writes it: big-endian int32 counts, float32 coordinates, and per face
/// its corner count, the indices and a colour count (0).
inline std::string octa_off_binary() {
  std::string s = "OFF BINARY\n";
  for (std::uint64_t n : {6u, 8u, 0u}) put_bytes(s, n, 4, true);
  for (const auto& p : OCTA_POINTS)
    for (int c : p) put_float(s, static_cast<float>(c), true);
  for (const auto& f : OCTA_FACES) {
    put_bytes(s, 3, 4, true);
    for (int v : f) put_bytes(s, static_cast<std::uint64_t>(v), 4, true);
    put_bytes(s, 0, 4, true);
  }
  return s;
}

inline std::string octa_obj() {
  std::string s = "# octahedron\n";
  for (const auto& p : OCTA_POINTS) s += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + ".5e0 " + std::to_string(p[2]) + "\n";
  for (const auto& f : OCTA_FACES) s += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
  return s;
}

/// PLY header for the octahedron with coordinate type `coord`, list types `count` / `index`.
inline std::string ply_header(const std::string& format, const std::string& coord, const std::string& count,
                              const std::string& index, const std::string& index_name = "vertex_indices") {
  return "ply\nformat " + format + " 1.0\ncomment seed\nelement vertex 6\nproperty " + coord + " x\nproperty " +
         coord + " y\nproperty " + coord + " z\nelement face 8\nproperty list " + count + " " + index + " " +
         index_name + "\nend_header\n";
}

inline std::string octa_ply_ascii(const std::string& coord) {
  std::string s = ply_header("ascii", coord, "uchar", "int");
  for (const auto& p : OCTA_POINTS) s += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  for (const auto& f : OCTA_FACES) s += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  return s;
}

/// Binary PLY; coord is "float", "double" or an integer type of `coord_size` bytes.
inline std::string octa_ply_binary(bool big_endian, const std::string& coord, int coord_size, const std::string& count,
                                   int count_size, const std::string& index, int index_size) {
  std::string s = ply_header(big_endian ? "binary_big_endian" : "binary_little_endian", coord, count, index, "vertex_index");
  for (const auto& p : OCTA_POINTS)
    for (int c : p) {
      if (coord == "float") put_float(s, static_cast<float>(c), big_endian);
      else if (coord == "double") put_double(s, static_cast<double>(c), big_endian);
      else put_bytes(s, static_cast<std::uint64_t>(c), coord_size, big_endian);
    }
  for (const auto& f : OCTA_FACES) {
    put_bytes(s, 3, count_size, big_endian);
    for (int v : f) put_bytes(s, static_cast<std::uint64_t>(v), index_size, big_endian);
  }
  return s;
}

inline std::string octa_stl_ascii() {
  std::string s = "solid octa\n";
  for (const auto& f : OCTA_FACES) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (int v : f) s += "vertex " + std::to_string(OCTA_POINTS[v][0]) + " " + std::to_string(OCTA_POINTS[v][1]) + " " + std::to_string(OCTA_POINTS[v][2]) + "\n";
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid octa\n";
}

inline std::string octa_stl_binary() {
  std::string s(80, ' ');
  s.replace(0, 9, "binarystl");  // a binary STL must not start with "solid"
  put_bytes(s, OCTA_FACES.size(), 4, false);
  for (const auto& f : OCTA_FACES) {
    for (int k = 0; k < 3; ++k) put_float(s, 0.0f, false);
    for (int v : f)
      for (int c : OCTA_POINTS[v]) put_float(s, static_cast<float>(c), false);
    put_bytes(s, 0, 2, false);
  }
  return s;
}

/// The octahedron as one indexed glTF primitive (unsigned short indices).
inline GltfParts octa_gltf_parts() {
  GltfScene s;
  GltfPrimitive p;
  for (const auto& x : OCTA_POINTS)
    p.positions.push_back(
        {static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2])});
  for (const auto& f : OCTA_FACES)
    for (int v : f) p.indices.push_back(static_cast<std::uint32_t>(v));
  p.index_type = 5123;
  s.primitives.push_back(p);
  return gltf_parts(s);
}

/// Every seed file: OFF (ascii and binary), OBJ, PLY (ascii and both binary byte orders, float,
/// double and integer coordinates), STL ascii and binary, glTF binary (.glb) and JSON with a data
/// URI (.gltf).
inline std::vector<SeedFile> seed_files() {
  return {
      {"off", "off", octa_off()},
      {"off_binary", "off", octa_off_binary()},
      {"obj", "obj", octa_obj()},
      {"ply_ascii_float", "ply", octa_ply_ascii("float")},
      {"ply_ascii_int", "ply", octa_ply_ascii("int")},
      {"ply_binary_le_float", "ply", octa_ply_binary(false, "float", 4, "uchar", 1, "int", 4)},
      {"ply_binary_be_double", "ply", octa_ply_binary(true, "double", 8, "uchar", 1, "uint", 4)},
      {"ply_binary_le_uchar", "ply", octa_ply_binary(false, "uchar", 1, "int", 4, "ushort", 2)},
      {"ply_binary_be_short", "ply", octa_ply_binary(true, "short", 2, "uint8", 1, "int32", 4)},
      {"stl_ascii", "stl", octa_stl_ascii()},
      {"stl_binary", "stl", octa_stl_binary()},
      {"glb", "glb", glb_bytes(octa_gltf_parts())},
      {"gltf", "gltf", gltf_text(octa_gltf_parts())},
  };
}

/// Seeded mutator: the same (seed, index) always gives the same mutant, so a failure is
/// reproduced by its two numbers.
class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  /// Applies 1 to 3 random mutations to `s`; `what` gets a short description of each.
  std::string mutate(std::string s, std::string& what) {
    const int n = 1 + static_cast<int>(below(3));
    for (int i = 0; i < n; ++i) {
      const int kind = static_cast<int>(below(9));
      what += (what.empty() ? "" : ", ");
      switch (kind) {
        case 0: what += "bit flip"; bit_flip(s); break;
        case 1: what += "insert bytes"; insert_bytes(s); break;
        case 2: what += "delete bytes"; delete_bytes(s); break;
        case 3: what += "swap lines"; swap_lines(s); break;
        case 4: what += "duplicate line"; duplicate_line(s); break;
        case 5: what += "replace number"; replace_number(s, false); break;
        case 6: what += "truncate"; truncate(s); break;
        case 7: what += "huge count"; replace_number(s, true); break;
        default: what += "move line to front"; move_line_to_front(s); break;
      }
    }
    return s;
  }

 private:
  std::uint64_t below(std::uint64_t n) { return n == 0 ? 0 : rng_() % n; }

  void bit_flip(std::string& s) {
    if (s.empty()) return;
    s[below(s.size())] ^= static_cast<char>(1u << below(8));
  }
  void insert_bytes(std::string& s) {
    static const char special[] = {'\0', '\r', '\n', ' ', '-', '#', '9', 'e', '.', '\xff', '\xef', '\t'};
    const std::size_t at = below(s.size() + 1);
    const std::size_t n = 1 + below(8);
    std::string ins;
    for (std::size_t i = 0; i < n; ++i)
      ins += below(2) ? special[below(sizeof special)] : static_cast<char>(below(256));
    s.insert(at, ins);
  }
  void delete_bytes(std::string& s) {
    if (s.empty()) return;
    const std::size_t at = below(s.size());
    s.erase(at, 1 + below(16));
  }
  std::vector<std::pair<std::size_t, std::size_t>> lines(const std::string& s) {
    std::vector<std::pair<std::size_t, std::size_t>> l;  // [begin, end) including the '\n'
    std::size_t b = 0;
    for (std::size_t i = 0; i < s.size(); ++i)
      if (s[i] == '\n') {
        l.emplace_back(b, i + 1);
        b = i + 1;
      }
    if (b < s.size()) l.emplace_back(b, s.size());
    return l;
  }
  void swap_lines(std::string& s) {
    auto l = lines(s);
    if (l.size() < 2) return;
    std::size_t a = below(l.size()), b = below(l.size());
    if (a == b) return;
    if (a > b) std::swap(a, b);
    const std::string la = s.substr(l[a].first, l[a].second - l[a].first);
    const std::string lb = s.substr(l[b].first, l[b].second - l[b].first);
    s = s.substr(0, l[a].first) + lb + s.substr(l[a].second, l[b].first - l[a].second) + la + s.substr(l[b].second);
  }
  void duplicate_line(std::string& s) {
    auto l = lines(s);
    if (l.empty()) return;
    const auto& x = l[below(l.size())];
    s.insert(x.second, s.substr(x.first, x.second - x.first));
  }
  void move_line_to_front(std::string& s) {
    auto l = lines(s);
    if (l.size() < 2) return;
    // Mostly a header line, after the first: e.g. a PLY 'property' before any 'element'.
    const std::size_t i = 1 + below(std::min<std::size_t>(l.size() - 1, 10));
    const std::string li = s.substr(l[i].first, l[i].second - l[i].first);
    s.erase(l[i].first, l[i].second - l[i].first);
    s.insert(l[1].first, li);
  }
  void truncate(std::string& s) { s.resize(below(s.size() + 1)); }

  /// Replaces a decimal number (anywhere, or with `header` one of the first 12 lines' numbers)
  /// by an extreme value.
  void replace_number(std::string& s, bool header) {
    static const char* const extreme[] = {"1e308", "-1e308", "nan", "inf", "-inf", "-1", "0", "1e-320", "4294967295",
                                          "4294967296", "18446744073709551616", "1e12", "-2147483648", "255", "256"};
    static const char* const huge[] = {"1000000000", "1000000000000", "1000000000000000000", "4294967295", "2147483647",
                                       "-1", "99999999999999999999"};
    std::vector<std::pair<std::size_t, std::size_t>> nums;
    std::size_t limit = s.size();
    if (header) {
      auto l = lines(s);
      if (l.size() > 12) limit = l[12].first;
    }
    for (std::size_t i = 0; i < limit;) {
      const bool digit = s[i] >= '0' && s[i] <= '9';
      if (!digit) { ++i; continue; }
      std::size_t j = i;
      while (j < s.size() && ((s[j] >= '0' && s[j] <= '9') || s[j] == '.' || s[j] == 'e' || s[j] == '-')) ++j;
      nums.emplace_back(i, j);
      i = j;
    }
    if (nums.empty()) return;
    const auto& n = nums[below(nums.size())];
    const std::string rep = header ? huge[below(std::size(huge))] : extreme[below(std::size(extreme))];
    s.replace(n.first, n.second - n.first, rep);
  }

  std::mt19937_64 rng_;
};

}  // namespace shellcontract::test
