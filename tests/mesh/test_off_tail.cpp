// Lines after an OFF's declared faces are not read (the header's counts decide), and are said:
// a warning when the mesh is usable, a note on the refusal when the faces left unread open it.
// Before, both were silent: a header that counted one face too few gave only "open boundary".
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "mesh/off_scan.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

const char* const FACES = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

std::string tetrahedron(int declared_faces, const std::string& tail) {
  return "OFF\n4 " + std::to_string(declared_faces) + " 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + FACES + tail;
}

TEST(OffTail, BlankAndCommentLinesAfterTheFacesAreNothing) {
  EXPECT_EQ(scan_off("t.off", tetrahedron(4, "\n  \n# the end\n")).ignored_tail, "");
}

TEST(OffTail, LinesAfterTheDeclaredFacesAreNamedWithTheFirstOnesLine) {
  const OffScan s = scan_off("t.off", tetrahedron(4, "# more\n3 0 1 2\n\nsomething else\n"));
  EXPECT_EQ(s.faces.size(), 4u);
  // Lines 1-2 header, 3-6 vertices, 7-10 faces, 11 a comment, 12 the first line not read.
  EXPECT_EQ(s.ignored_tail, "t.off: line 12: 2 lines after the 4 declared faces not read (the header's counts "
                            "decide what is read)");
}

TEST(OffTail, AUsableMeshWarnsAndARefusedOneSaysWhy) {
  const fs::path dir = fs::temp_directory_path() / ("shellcontract_off_tail_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path extra = dir / "extra.off", short_count = dir / "short.off";
  std::ofstream(extra) << tetrahedron(4, "3 0 1 2\n");
  std::ofstream(short_count) << tetrahedron(3, "");  // the fourth face is not read: the mesh is open
  InputReport report;
  read_input_mesh(extra.string(), &report);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("line 11: 1 line after the 4 declared faces not read"), std::string::npos)
      << report.warnings[0];
  try {
    read_input_mesh(short_count.string());
    ADD_FAILURE() << "an open tetrahedron was accepted";
  } catch (const FaceListError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("open boundary"), std::string::npos) << what;
    EXPECT_NE(what.find("line 10: 1 line after the 3 declared faces not read"), std::string::npos) << what;
    EXPECT_EQ(e.faces().size(), 3u) << "the three faces around the unread one";
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
