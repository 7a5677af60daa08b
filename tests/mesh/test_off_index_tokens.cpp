// The OFF scan's face indices and blanks (src/mesh/off_scan.cpp reads them by hand, not with
// strtoll and isspace): a token is an index when strtoll (C11 7.22.1.4) would read all of it,
// an optional sign and decimal digits within long long; the blanks are the "C" locale's
// isspace set (C11 7.4.1.10). Checked to fail when the '+' sign, the overflow test or the
// vertical tab as a blank is left out.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "mesh/off_scan.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"

namespace shellcontract {
namespace {

/// A tetrahedron whose last face is `face` (a whole line).
std::string tetrahedron(const std::string& face) {
  return "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n" + face + "\n";
}

std::vector<std::size_t> last_face(const std::string& face) { return scan_off("t.off", tetrahedron(face)).faces.back(); }

/// The message of the InputError the scan throws, or "" when it accepts the file.
std::string refusal(const std::string& face) {
  try {
    scan_off("t.off", tetrahedron(face));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(OffIndexTokens, SignsAsStrtollReadsThem) {
  EXPECT_EQ(last_face("3 +1 2 3"), (std::vector<std::size_t>{1, 2, 3}));
  EXPECT_EQ(last_face("+3 1 2 -0"), (std::vector<std::size_t>{1, 2, 0}));
  EXPECT_EQ(last_face("3 1 2 0003"), (std::vector<std::size_t>{1, 2, 3}));
  EXPECT_NE(refusal("3 1 2 -3").find("vertex index out of range: face 3 (line 10) has the negative index -3"), std::string::npos)
      << refusal("3 1 2 -3");
  for (const char* bad : {"3 1 2 +-3", "3 1 2 --3", "3 1 2 +", "3 1 2 3x", "3 1 2 0x3", "3 1 2 1.0", "3 1 2 1e2"})
    EXPECT_NE(refusal(bad).find("parse error: face 3 (line 10): '"), std::string::npos) << bad << ": " << refusal(bad);
}

TEST(OffIndexTokens, RangeOfLongLong) {
  // LLONG_MAX is read (then refused as an index past the vertices), one more overflows.
  EXPECT_NE(refusal("3 1 2 9223372036854775807").find("vertex index out of range: face 3 (line 10) refers to vertex 9223372036854775807"),
            std::string::npos);
  EXPECT_NE(refusal("3 1 2 9223372036854775808").find("'9223372036854775808' is not an integer"), std::string::npos);
  EXPECT_NE(refusal("3 1 2 99999999999999999999").find("is not an integer"), std::string::npos);
  // LLONG_MIN is read (a negative index), one less overflows.
  EXPECT_NE(refusal("3 1 2 -9223372036854775808").find("has the negative index -9223372036854775808"), std::string::npos);
  EXPECT_NE(refusal("3 1 2 -9223372036854775809").find("is not an integer"), std::string::npos);
}

TEST(OffIndexTokens, BlanksAreTheCLocaleSpaces) {
  EXPECT_EQ(last_face("3\t1\v2\f3\r"), (std::vector<std::size_t>{1, 2, 3}));
  EXPECT_EQ(last_face("  3 1   2 3  # a comment"), (std::vector<std::size_t>{1, 2, 3}));
  // A byte outside ASCII is not a blank: "2\xa03" is one token (a comment line follows, so
  // the file does not end inside the face).
  const std::string nbsp = refusal("3 1 2\xa0" "3\n# end");
  EXPECT_NE(nbsp.find("parse error: face 3 (line 10) announces 3 vertices but lists 2"), std::string::npos) << nbsp;
}

/// The faces of the FaceListError the scan throws for `text`; {} (and a failure) for anything else.
std::vector<std::size_t> refused_faces(const std::string& text) {
  try {
    scan_off("t.off", text);
    ADD_FAILURE() << "accepted";
  } catch (const FaceListError& e) {
    return e.faces();
  } catch (const InputError& e) {
    ADD_FAILURE() << "refused without its faces: " << e.what();
  }
  return {};
}

/// A binary OFF tetrahedron (big-endian int32 and float32, as CGAL writes it) whose last face
/// names `last`.
std::string binary_tetrahedron(std::int32_t last) {
  std::string s = "OFF BINARY\n";
  auto put = [&s](std::uint32_t u) {
    for (int shift = 24; shift >= 0; shift -= 8) s += static_cast<char>((u >> shift) & 0xffu);
  };
  auto put_int = [&put](std::int32_t i) { put(static_cast<std::uint32_t>(i)); };
  for (std::int32_t n : {4, 4, 0}) put_int(n);
  for (float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f}) {
    std::uint32_t u = 0;
    std::memcpy(&u, &c, 4);
    put(u);
  }
  for (const auto& f :
       std::vector<std::vector<std::int32_t>>{{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, last}}) {
    put_int(3);
    for (std::int32_t v : f) put_int(v);
    put_int(0);
  }
  return s;
}

// Before, an index past the vertices was a plain InputError from a file, where the same mesh as
// arrays named its face as data (Python's MeshError.faces, the Blender add-on's selection).
TEST(OffIndexTokens, AnIndexOutOfRangeNamesItsFaceAsData) {
  EXPECT_EQ(refused_faces(tetrahedron("3 1 2 4")), (std::vector<std::size_t>{3}));
  EXPECT_EQ(refused_faces(tetrahedron("3 1 2 -3")), (std::vector<std::size_t>{3}));
  EXPECT_EQ(refused_faces(binary_tetrahedron(4)), (std::vector<std::size_t>{3}));
  EXPECT_EQ(refused_faces(binary_tetrahedron(-1)), (std::vector<std::size_t>{3}));
  // The binary tetrahedron itself is read: the refusals above are of the index alone.
  EXPECT_EQ(scan_off("t.off", binary_tetrahedron(3)).faces.back(),
            (std::vector<std::size_t>{1, 2, 3}));
}

}  // namespace
}  // namespace shellcontract
