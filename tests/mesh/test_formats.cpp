// The format table (src/mesh/formats.hpp) against the code that reads and writes each format and
// the messages that list formats: a row the readers or writers do not handle, or a message whose
// list is not the table's, fails here. The CLI's messages and help texts are compared with the
// table in tests/cli/test_cli_formats.cpp, the fuzz seeds in tests/fuzz/test_reader_fuzz.cpp.
#include <gtest/gtest.h>

#include <cctype>
#include <set>
#include <string>
#include <vector>

#include "export/frame_sequence_writer.hpp"
#include "mesh/formats.hpp"
#include "mesh/read_polygon_soup.hpp"
#include "mesh/repair_output.hpp"
#include "mesh/soup_writer.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/repair.hpp"
#include "support/format_lists.hpp"
#include "support/scratch_dir.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

using test::Extensions;
using test::listed;
using test::rows;

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "<nothing thrown>";
}

std::string mesh_path(const std::string& name) { return std::string(test::MESH_DIR) + "/" + name; }

class Formats : public test::ScratchDirTest {
 protected:
  Formats() : ScratchDirTest("shellcontract_test_formats_") {}
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
};

TEST(FormatTable, RowsAreDistinctLowerCaseExtensions) {
  std::set<std::string> exts;
  std::set<FormatId> ids;
  for (const MeshFormat& f : MESH_FORMATS) {
    const std::string ext = f.ext;
    EXPECT_TRUE(exts.insert(ext).second) << ext << " twice";
    EXPECT_TRUE(ids.insert(f.id).second) << ext << ": its id is another row's";
    EXPECT_EQ(lower_extension("m." + ext), ext);
    EXPECT_EQ(find_mesh_format(ext), &f);
    for (const char c : ext)
      EXPECT_TRUE(std::islower(static_cast<unsigned char>(c)) ||
                  std::isdigit(static_cast<unsigned char>(c)))
          << ext;
    // A glTF is written only from a document or by the glTF mesh writer, never plainly.
    EXPECT_TRUE(!f.gltf || (f.document && !f.plain_writer)) << ext;
  }
  EXPECT_EQ(find_mesh_format(""), nullptr);
  EXPECT_EQ(find_mesh_format("OFF"), nullptr) << "the table's keys are lower_extension's";
  EXPECT_EQ(lower_extension("dir.v2/Mesh.PlY"), "ply");
  EXPECT_EQ(lower_extension("dir.v2/mesh"), "");
}

TEST(FormatTable, ExtensionListJoinsTheRowsInTableOrder) {
  EXPECT_EQ(extension_list(any_format), ".off, .obj, .ply, .stl, .glb or .gltf");
  EXPECT_EQ(extension_list(&MeshFormat::plain_writer, "", ", "), "off, obj, ply, stl");
  EXPECT_EQ(extension_list(&MeshFormat::exact_positions), ".off, .obj or .ply");
  EXPECT_EQ(extension_list([](const MeshFormat& f) { return f.id == FormatId::Glb; }), ".glb");
  EXPECT_EQ(extension_list([](const MeshFormat&) { return false; }), "");
}

// Every row is written by `repair` (a plain writer's or the glTF mesh writer's file) and read
// back by read_input_mesh as the mesh written; write_mesh_atomic writes exactly the plain rows;
// read_mesh_document keeps exactly the document rows.
TEST_F(Formats, EveryRowIsWrittenAndReadBack) {
  const std::string input = mesh_path("ico1.off");
  RepairReport report;
  const Mesh mesh = repair_input_mesh(input, &report);
  ASSERT_TRUE(report.already_usable);
  for (const MeshFormat& f : MESH_FORMATS) {
    SCOPED_TRACE(f.ext);
    const std::string repaired = file(std::string("repaired.") + f.ext);
    write_repair_output(input, repaired, mesh, report);
    InputReport back_report;
    const Mesh back = read_input_mesh(repaired, &back_report);
    EXPECT_EQ(back.number_of_vertices(), mesh.number_of_vertices());
    EXPECT_EQ(back.number_of_faces(), mesh.number_of_faces());
    EXPECT_NEAR(back_report.volume, report.input_report.volume, 1e-5 * report.input_report.volume);

    const std::string plain = file(std::string("plain.") + f.ext);
    if (f.plain_writer) {
      write_mesh_atomic(plain, mesh, positions_from_mesh(mesh));
      const Mesh plain_back = read_input_mesh(plain);
      EXPECT_EQ(plain_back.number_of_faces(), mesh.number_of_faces());
      ASSERT_EQ(plain_back.number_of_vertices(), mesh.number_of_vertices());
      EXPECT_TRUE(!f.exact_positions ||
                  positions_from_mesh(plain_back) == positions_from_mesh(mesh));
    } else {
      EXPECT_THROW(write_mesh_atomic(plain, mesh, positions_from_mesh(mesh)), UsageError);
    }
    EXPECT_EQ(read_mesh_document(repaired) != nullptr, f.document);
  }
}

// An extension of no row is refused by every reader and writer, each listing the rows it takes.
TEST_F(Formats, EachRefusalListsTheTablesRows) {
  const std::string tet = write("tet.off",
                                "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const Mesh mesh = read_input_mesh(tet);
  const Positions x = positions_from_mesh(mesh);
  const std::string unknown = write("m.xyz", "whatever"), bare = write("m", "whatever");

  EXPECT_EQ(listed(message_of([&] { read_input_mesh(unknown); })), rows(any_format));
  EXPECT_EQ(listed(message_of([&] { read_input_mesh(bare); })), rows(any_format));
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> polygons;
  SourceLines lines;
  EXPECT_EQ(listed(message_of([&] { read_polygon_soup(unknown, "xyz", points, polygons, lines); })),
            rows(any_format));
  EXPECT_EQ(listed(message_of([&] { write_mesh_atomic(file("out.xyz"), mesh, x); })),
            rows(&MeshFormat::plain_writer));
  EXPECT_EQ(
      listed(message_of([&] { write_polygon_soup_atomic(file("out.xyz"), points, polygons); })),
      rows(&MeshFormat::plain_writer));
  EXPECT_EQ(listed(message_of([&] { check_repair_output_name("-o", file("out.xyz")); })),
            rows([](const MeshFormat& f) { return f.plain_writer || f.gltf; }));
  EXPECT_EQ(listed(message_of([&] { FrameSequenceWriter(dir_.string(), "f", "xyz", mesh, 3); })),
            rows(&MeshFormat::plain_writer));
  // Two vertices at one position are one when an STL is read back: the message names the
  // formats that keep them apart.
  Positions same = x;
  same.row(1) = same.row(0);
  EXPECT_EQ(listed(message_of([&] { write_mesh_atomic(file("out.stl"), mesh, same); }), "write "),
            rows(&MeshFormat::exact_positions));
}

// `repair` read a file of no known extension as an STL (the last reader): "cannot repair: the
// file has no faces" for any text, and a repaired mesh for an STL under another name, which
// `check` and `run` refuse. It is refused now for its extension, as read_input_mesh refuses it.
TEST_F(Formats, ASoupOfNoKnownExtensionIsRefusedBeforeItIsRead) {
  const std::string stl =
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
  for (const char* name : {"m.dat", "m.STL.bak", "m"}) {
    const std::string path = write(name, stl);
    std::vector<Point3> points;
    std::vector<std::vector<std::size_t>> polygons;
    SourceLines lines;
    const std::string why = message_of(
        [&] { read_polygon_soup(path, lower_extension(path), points, polygons, lines); });
    EXPECT_EQ(why, message_of([&] { read_input_mesh(path); })) << name;
    EXPECT_TRUE(points.empty()) << name;
    RepairReport report;
    EXPECT_THROW(repair_input_mesh(path, &report), InputError) << name;
    EXPECT_FALSE(report.usable) << name;
  }
}

}  // namespace
}  // namespace shellcontract
