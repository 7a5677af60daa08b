// OBJ line continuation (a backslash at a line's end, line_tokens.hpp): scan_obj, the OBJ
// document and read_input_mesh read a continued statement as the same statement on one line,
// name the line it starts on, write new positions into a continued `v` and keep a continued `f`,
// and refuse a file whose last line is continued with a message, not a crash.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mesh/obj_material_paths.hpp"
#include "mesh/obj_scan.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// A tetrahedron on one line per statement.
const std::string JOINED =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// The same with a continued `v` (line 2: three lines), a continued `f` (line 7: two lines,
/// "\r\n" ends and blanks after the backslash) and a comment with backslashes inside it.
const std::string CONTINUED =
    "v 0 0 0\nv 1 \\\n 0 \\\n 0\nv 0 1 0\n# C:\\models\\tet\nv 0 0 1\nf 1 3 2\nf 1 2 \\ \t\r\n 4\n"
    "f 1 4 3\nf 2 3 4\n";

TEST(ObjContinuation, ScanReadsContinuedLinesAsJoinedAndNamesTheLinesTheyStartOn) {
  const ObjScan a = scan_obj("joined.obj", JOINED), b = scan_obj("continued.obj", CONTINUED);
  EXPECT_EQ(b.points, a.points);
  EXPECT_EQ(b.faces, a.faces);
  EXPECT_EQ(b.lines.vertex_line, (std::vector<std::size_t>{1, 2, 5, 7}));
  EXPECT_EQ(b.lines.face_line, (std::vector<std::size_t>{8, 9, 11, 12}));
}

TEST(ObjContinuation, AnErrorNamesTheLineTheStatementStartsOn) {
  const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 \\\nx\nf 1 2 3\n";
  try {
    scan_obj("bad.obj", text);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("face 0 (line 4)"), std::string::npos) << e.what();
  }
  try {
    parse_obj_document("bad.obj", text);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
  }
}

TEST(ObjContinuation, ReadInputMeshReadsTheContinuedTetrahedron) {
  const fs::path dir =
      fs::temp_directory_path() / ("shellcontract_obj_continuation_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "cont.obj").string();
  std::ofstream(path, std::ios::binary) << CONTINUED;
  const Mesh m = read_input_mesh(path);
  EXPECT_EQ(m.number_of_vertices(), 4u);
  EXPECT_EQ(m.number_of_faces(), 4u);
  fs::remove_all(dir);
}

TEST(ObjContinuation, DocumentWritesNewPositionsIntoAContinuedVertexAndKeepsTheRest) {
  const auto doc = parse_obj_document("continued.obj", CONTINUED);
  ASSERT_EQ(doc->vertex_count(), 4u);
  ASSERT_EQ(doc->polygon_count(), 4u);
  Positions y(4, 3);
  y << 0.5, -1.25, 2, 3.5, 4.75, -6, 7, 8.5, 9, 10, 11, 12.125;
  const std::string out = doc->text(y);
  // Vertex 1's numbers replaced where they were, its continuations kept; every other byte but
  // the other vertices' numbers as read.
  EXPECT_EQ(out,
            "v 0.5 -1.25 2\nv 3.5 \\\n 4.75 \\\n -6\nv 7 8.5 9\n# C:\\models\\tet\nv 10 11 12.125\n"
            "f 1 3 2\nf 1 2 \\ \t\r\n 4\nf 1 4 3\nf 2 3 4\n");
  // Read back: the new positions, the same faces.
  const ObjScan back = scan_obj("out.obj", out);
  ASSERT_EQ(back.points.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_EQ(back.points[i][k], y(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)));
  EXPECT_EQ(back.faces, scan_obj("joined.obj", JOINED).faces);
}

TEST(ObjContinuation, AContinuedMtllibIsRewrittenForAnotherFolderInPlace) {
  const fs::path dir = fs::temp_directory_path() /
                       ("shellcontract_obj_continued_mtllib_" + std::to_string(::getpid()));
  fs::create_directories(dir / "in");
  fs::create_directories(dir / "out");
  std::ofstream(dir / "in" / "a.mtl") << "newmtl red\nKd 1 0 0\n";
  const std::string in = (dir / "in" / "t.obj").string(), out = (dir / "out" / "t.obj").string();
  // Two libraries on a statement of lines 2-4, the missing one on line 4.
  const std::string bytes = "# t\nmtllib \\\n a.mtl \\\n gone.mtl\n" + JOINED;
  const std::string want = "# t\nmtllib \\\n ../in/a.mtl \\\n gone.mtl\n" + JOINED;
  std::vector<std::string> w;
  EXPECT_EQ(relocate_material_libraries(bytes, in, out, &w), want);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find(in + ": line 2: material library 'gone.mtl' not found"), std::string::npos)
      << w[0];
  // The document: the same edit, with the positions.
  std::ofstream(in, std::ios::binary) << bytes;
  const auto doc = read_mesh_document(in);
  Positions y(4, 3);
  y << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  w.clear();
  EXPECT_EQ(doc->text_for(out, y, &w), want);
  EXPECT_EQ(w.size(), 1u);
  fs::remove_all(dir);
}

TEST(ObjContinuation, AContinuedLastLineIsRefusedWithItsLine) {
  // The backslash as the very last byte, before a last line end, and with blanks after it.
  for (const std::string tail : {"f 2 3 4 \\", "f 2 3 4 \\\n", "f 2 3 4\\  "}) {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n" + tail;
    for (const bool document : {false, true}) {
      try {
        if (document)
          parse_obj_document("last.obj", text);
        else
          scan_obj("last.obj", text);
        ADD_FAILURE() << "accepted: " << tail;
      } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("last.obj: parse error"), std::string::npos) << msg;
        EXPECT_NE(msg.find("line 8"), std::string::npos) << msg;
        EXPECT_NE(msg.find("line continuation"), std::string::npos) << msg;
      }
    }
  }
}

}  // namespace
}  // namespace shellcontract
