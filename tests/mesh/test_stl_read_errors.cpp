// STL files that read_input_mesh refuses: every message names the file and where, the line of an
// ASCII file or the counts and sizes of a binary one, as for OFF, OBJ and PLY (before, CGAL's
// reader gave "CGAL could not read it as a .stl file (truncated file or garbage)" for all of
// them). Valid files are still read by CGAL alone: the success-path checks below.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "mesh/stl_diagnosis.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

const float P[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const int F[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

/// The lines of an ASCII tetrahedron: "solid t" on line 1, facet f on lines 2 + 7f to 8 + 7f (its
/// vertices on 4 + 7f to 6 + 7f), "endsolid t" on line 30. lines[i] is line i + 1.
std::vector<std::string> ascii_lines() {
  std::vector<std::string> l{"solid t"};
  for (const auto& f : F) {
    l.push_back("  facet normal 0 0 0");
    l.push_back("    outer loop");
    for (int c = 0; c < 3; ++c)
      l.push_back("      vertex " + std::to_string(static_cast<int>(P[f[c]][0])) + " " + std::to_string(static_cast<int>(P[f[c]][1])) +
                  " " + std::to_string(static_cast<int>(P[f[c]][2])));
    l.push_back("    endloop");
    l.push_back("  endfacet");
  }
  l.push_back("endsolid t");
  return l;
}

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

/// A binary tetrahedron; `header` starts the 80-byte header.
std::string binary(const std::string& header) {
  std::string s(84 + 50 * 4, '\0');
  std::memcpy(&s[0], header.data(), header.size());
  const std::uint32_t n = 4;
  std::memcpy(&s[80], &n, 4);
  for (int f = 0; f < 4; ++f)
    for (int c = 0; c < 3; ++c) std::memcpy(&s[84 + 50 * f + 12 * (c + 1)], P[F[f][c]], 12);
  return s;
}

/// A binary tetrahedron with coordinate k of corner c of facet f set to v.
std::string binary_with(const std::string& header, int f, int c, int k, float v) {
  std::string s = binary(header);
  std::memcpy(&s[84 + 50 * f + 12 * (c + 1) + 4 * k], &v, 4);
  return s;
}

struct StlCase {
  std::string name, bytes;
  std::vector<std::string> expected;  ///< substrings of the message besides the file's name
  bool whole = false;                 ///< expected[0] is the whole message after the file's name
};

void PrintTo(const StlCase& c, std::ostream* os) { *os << c.name; }

class TempDir {
 public:
  TempDir() : dir_(fs::temp_directory_path() / ("shellcontract_stl_errors_" + std::to_string(::getpid()))) { fs::create_directories(dir_); }
  ~TempDir() { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string path = (dir_ / (name + ".stl")).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

 private:
  fs::path dir_;
};

class StlReadErrors : public ::testing::TestWithParam<StlCase> {};

TEST_P(StlReadErrors, NameTheFileAndWhere) {
  const StlCase& c = GetParam();
  const TempDir dir;
  const std::string path = dir.write(c.name, c.bytes);
  try {
    read_input_mesh(path);
    ADD_FAILURE() << c.name << ": accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
    EXPECT_EQ(msg.find("CGAL could not read it"), std::string::npos) << msg;
    for (const std::string& s : c.expected) EXPECT_NE(msg.find(s), std::string::npos) << c.name << ": '" << s << "' not in: " << msg;
    if (c.whole) {
      EXPECT_EQ(msg, path + c.expected.at(0));
    }
  }
}

std::string ascii_with(int line, const std::string& text) {
  auto l = ascii_lines();
  l[line - 1] = text;
  return join(l);
}
std::string ascii_without(int line) {
  auto l = ascii_lines();
  l.erase(l.begin() + (line - 1));
  return join(l);
}
std::string ascii_inserted(int before, const std::string& text) {
  auto l = ascii_lines();
  l.insert(l.begin() + (before - 1), text);
  return join(l);
}
std::string ascii_first(int n) {
  auto l = ascii_lines();
  l.resize(n);
  return join(l);
}

/// `text` with its keywords solid, facet, vertex, endfacet and endsolid in upper case.
std::string upper_keywords(std::string text) {
  for (const std::string w : {"endsolid", "endfacet", "solid", "facet", "vertex"}) {
    std::string up = w;
    for (char& c : up) c = static_cast<char>(c - 'a' + 'A');
    for (std::size_t at = text.find(w); at != std::string::npos; at = text.find(w, at + w.size()))
      text.replace(at, w.size(), up);
  }
  return text;
}

INSTANTIATE_TEST_SUITE_P(
    Files, StlReadErrors,
    ::testing::Values(
        // The review's case: a word where the first coordinate of facet 1's first vertex is.
        StlCase{"bad_number",
                ascii_with(11, "      vertex abc 0 1"),
                {": parse error: line 11: expected 'vertex X Y Z' with three numbers, got 'vertex "
                 "abc 0 1'"}},
        StlCase{"two_numbers",
                ascii_with(12, "      vertex 1 0"),
                {": parse error: line 12: expected 'vertex X Y Z' with three numbers, got 'vertex "
                 "1 0' (then line 13: 'vertex')"}},
        StlCase{"four_vertices",
                ascii_inserted(14, "      vertex 1 1 1"),
                {": parse error: line 14: a 4th vertex in the facet begun on line 9, got 'vertex 1 "
                 "1 1'; STL facets are triangles (3 vertices)"},
                true},
        StlCase{"two_vertices",
                ascii_without(13),
                {": parse error: line 14: the facet begun on line 9 ends with 2 vertices",
                 "triangles"}},
        StlCase{"no_endsolid",
                ascii_first(29),
                {": truncated file: the solid begun on line 1 has no 'endsolid': the file ends at "
                 "line 29 ('endfacet')"}},
        StlCase{"cut_in_a_facet",
                ascii_first(12),
                {": truncated file: the file ends at line 12 ('vertex 1 0 0') inside the facet "
                 "begun on line 9 (expected vertex 3 of 3)"},
                true},
        // A facet's closing line missing: CGAL reads on into the next facet and stops at its first
        // vertex, as a 4th; the message names the line where the closing word was expected (it
        // said "a 4th vertex in the facet begun on line 9").
        StlCase{"no_endfacet",
                ascii_without(15),
                {": parse error: line 15: expected 'endfacet' after the 3 vertices of the facet "
                 "begun on line 9, got 'facet normal 0 0 0'"},
                true},
        StlCase{"no_endloop_nor_endfacet",
                [] {
                  auto l = ascii_lines();
                  l.erase(l.begin() + 13, l.begin() + 15);  // lines 14 and 15
                  return join(l);
                }(),
                {": parse error: line 14: expected 'endloop' after the 3 vertices of the facet "
                 "begun on line 9, got 'facet normal 0 0 0'"},
                true},
        // The last facet's: CGAL reads 'endsolid' as a word inside the facet and reaches the end.
        StlCase{"last_facet_no_endfacet",
                ascii_without(29),
                {": parse error: line 29: expected 'endfacet' after the 3 vertices of the facet "
                 "begun on line 23, got 'endsolid t'"},
                true},
        StlCase{"cut_after_the_vertices",
                ascii_first(13),
                {": truncated file: the file ends at line 13 ('vertex 0 0 1') inside the facet "
                 "begun on line 9 (expected 'endloop' after its 3 vertices)"},
                true},
        StlCase{"cut_after_endloop",
                ascii_first(14),
                {": truncated file: the file ends at line 14 ('endloop') inside the facet begun on "
                 "line 9 (expected 'endfacet' after its 3 vertices)"},
                true},
        StlCase{"cut_in_a_vertex",
                join(ascii_lines()).substr(0, ascii_first(11).size() + 14),
                {": truncated file: the file ends at line 12", "in the vertex of line 12"}},
        StlCase{"nan",
                ascii_with(11, "      vertex 0 nan 0"),
                {": non-finite coordinate: line 11:", "coordinate y = nan"}},
        StlCase{"overflow",
                ascii_with(25, "      vertex 0 0 1e999"),
                {": non-finite coordinate: line 25:", "begun on line 23", "z = 1e999"}},
        StlCase{"crlf_bad_number",
                [] {
                  std::string s;
                  auto l = ascii_lines();
                  l[10] = "vertex 0 0 x";
                  for (const auto& t : l) s += t + "\r\n";
                  return s;
                }(),
                {": parse error: line 11: expected 'vertex X Y Z' with three numbers, got 'vertex "
                 "0 0 x'"}},
        StlCase{"no_solid",
                [] {
                  std::string s;
                  for (int i = 0; i < 10; ++i)
                    s += "hello world\n";  // past 84 bytes: not read as an empty binary file
                  return s;
                }(),
                {": parse error: no 'solid NAME'"}},
        StlCase{"binary_cut",
                binary("exported").substr(0, 200),
                {": truncated file: the header says 4 facets (284 bytes), the file has 200 bytes; "
                 "facet 2 is cut after 16 of its 50 bytes"}},
        StlCase{"binary_cut_between_facets",
                binary("exported").substr(0, 184),
                {": truncated file: the header says 4 facets (284 bytes), the file has 184 bytes; "
                 "it ends after 2 whole facets"}},
        // Binary files may begin with "solid": diagnosed as binary all the same.
        StlCase{"binary_solid_cut",
                binary("solid exported by a CAD tool").substr(0, 200),
                {": truncated file: the header says 4 facets (284 bytes), the file has 200 bytes"}},
        // CGAL reads these without an error, and puts another point in place of a NaN one: the
        // file was a usable tetrahedron.
        StlCase{"binary_nan",
                binary_with("exported", 3, 1, 1, std::numeric_limits<float>::quiet_NaN()),
                {": non-finite coordinate: facet 3 (bytes 234 to 283) has corner 1 with coordinate "
                 "y = "}},
        StlCase{"binary_solid_nan",
                binary_with("solid exported by a CAD tool", 0, 2, 0,
                            std::numeric_limits<float>::quiet_NaN()),
                {": non-finite coordinate: facet 0 (bytes 84 to 133) has corner 2 with coordinate "
                 "x = "}},
        StlCase{"binary_inf",
                binary_with("exported", 1, 0, 2, -std::numeric_limits<float>::infinity()),
                {": non-finite coordinate: facet 1 (bytes 134 to 183) has corner 0 with coordinate "
                 "z = -inf"}},
        StlCase{"binary_short",
                binary("exported").substr(0, 82),
                {": truncated file: the file has 82 bytes", "at least 84"}},
        // Text that CGAL read as binary facets of its bytes (its first word not 'solid'): before,
        // "open boundary: the edge from (1.17e-19, 2.7e+23, 7.3e+31) ..." or a duplicate of a
        // facet the file does not have.
        StlCase{"upper_solid",
                ascii_with(1, "Solid t"),
                {": parse error: line 1: the keyword 'Solid' is not in lower case"}},
        // CGAL reads the upper-case keyword in a solid as ASCII (a word it skips): its facet is
        // missing, as the message says.
        StlCase{"upper_facet", ascii_with(9, "  FACET normal 0 0 0"), {": open boundary: "}},
        // Before: "an ASCII STL begins with 'solid' and a space", which the file visibly does.
        StlCase{"byte_order_mark",
                "\xEF\xBB\xBF" + join(ascii_lines()),
                {": parse error: line 1: the text begins with a UTF-8 byte-order mark"}},
        // Every keyword in upper case (CGAL refuses it as ASCII and as binary): before, "no
        // 'solid NAME' ... 'endsolid' in the file".
        StlCase{"all_upper_case",
                upper_keywords(join(ascii_lines())),
                {": parse error: line 1: the keyword 'SOLID' is not in lower case"}},
        StlCase{
            "solid_and_a_tab",
            "solid\t" + join(ascii_lines()).substr(6),
            {": parse error: line 1: an ASCII STL begins with 'solid' and a space or a line end"}},
        StlCase{"text_of_no_solid",
                std::string(4, '\n') + std::string(100, 'w') + "\n",
                {": parse error: no 'solid NAME'", "not a binary STL either"}}),
    [](const ::testing::TestParamInfo<StlCase>& i) { return i.param.name; });

// Success path: what CGAL reads is read as before, and the diagnosis finds nothing in it.
TEST(StlReadSuccess, AsciiAndBinaryTetrahedraAreRead) {
  const TempDir dir;
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"ascii", join(ascii_lines())}, {"binary", binary("exported")}, {"binary_solid", binary("solid exported by a CAD tool")},
           {"binary_solid_newline", binary("solid \n")}}) {
    const Mesh m = read_input_mesh(dir.write(name, bytes));
    EXPECT_EQ(m.number_of_vertices(), 4u) << name;
    EXPECT_EQ(m.number_of_faces(), 4u) << name;
    EXPECT_TRUE(diagnose_stl(bytes).problem.empty()) << name << ": " << diagnose_stl(bytes).details;
  }
}

// Upper-case 'NORMAL' (CGAL skips the words of a facet line after 'facet'): read as ASCII, as
// before; text_read_as_binary keeps it.
TEST(StlReadSuccess, AnUpperCaseNormalIsRead) {
  const TempDir dir;
  const std::string bytes = ascii_with(2, "  facet NORMAL 0 0 0");
  EXPECT_TRUE(text_read_as_binary(bytes).problem.empty()) << text_read_as_binary(bytes).details;
  const Mesh m = read_input_mesh(dir.write("normal", bytes));
  EXPECT_EQ(m.number_of_faces(), 4u);
}

// CGAL skips the words 'outer loop' and 'endloop' inside a facet: a facet without its 'endloop'
// line is read (only 'endfacet' closes a facet), and the diagnosis finds nothing to report.
TEST(StlReadSuccess, AFacetWithoutEndloopIsRead) {
  const TempDir dir;
  const std::string bytes = ascii_without(14);
  const Mesh m = read_input_mesh(dir.write("no_endloop", bytes));
  EXPECT_EQ(m.number_of_faces(), 4u);
  EXPECT_TRUE(diagnose_stl(bytes).problem.empty()) << diagnose_stl(bytes).details;
}

// CGAL accepts a binary file longer than its facets need (the rest is ignored): still read.
TEST(StlReadSuccess, BinaryWithTrailingBytesIsRead) {
  const TempDir dir;
  const Mesh m = read_input_mesh(dir.write("trailing", binary("exported") + std::string(7, 'x')));
  EXPECT_EQ(m.number_of_faces(), 4u);
}

TEST(StlDiagnosis, BinaryNonFiniteCoordinateNamesTheFacet) {
  std::string b = binary("exported");
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&b[84 + 50 * 3 + 12 * 2 + 4], &inf, 4);  // facet 3, corner 1, y
  const StlDiagnosis d = diagnose_stl(b);
  EXPECT_EQ(d.problem, "non-finite coordinate");
  EXPECT_NE(d.details.find("facet 3 (bytes 234 to 283) has corner 1 with coordinate y = inf"), std::string::npos) << d.details;
}

}  // namespace
}  // namespace shellcontract
