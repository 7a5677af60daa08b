// The OFF scan's face indices and blanks (src/mesh/off_scan.cpp reads them by hand, not with
// strtoll and isspace): a token is an index when strtoll (C11 7.22.1.4) would read all of it,
// an optional sign and decimal digits within long long; the blanks are the "C" locale's
// isspace set (C11 7.4.1.10). Checked to fail when the '+' sign, the overflow test or the
// vertical tab as a blank is left out.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mesh/off_scan.hpp"
#include "shellcontract/error.hpp"

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

}  // namespace
}  // namespace shellcontract
