// glTF 2.0 inputs (src/mesh/gltf_reader.cpp; docs/design/input-readers.md): a .glb or .gltf is
// read like an OBJ, its triangle primitives at their world positions, seam copies welded; every
// malformed file is an InputError that names the file and the element at fault. Before the
// reader, every file here was refused with "unknown extension '.glb'".
#include <CGAL/boost/graph/helpers.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "mesh/gltf_reader.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/gltf_files.hpp"
#include "support/gltf_shared_positions.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::GltfScene;

class GltfReader : public test::ScratchDirTest {
 protected:
  GltfReader() : ScratchDirTest("shellcontract_gltf_reader_") {}
  std::string glb(const std::string& name, const GltfScene& s) const {
    return write(name, test::glb_bytes(test::gltf_parts(s)));
  }
  /// The refusal of the file, or "(no error)".
  static std::string error_of(const std::string& path) {
    try {
      read_input_mesh(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  }
};

GltfScene octahedron(bool split = false, bool uv = false) {
  GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(split, uv));
  return s;
}

TEST_F(GltfReader, ReadsAnIndexedOctahedronWithEveryIndexType) {
  for (const int type : {5121, 5123, 5125}) {
    GltfScene s = octahedron();
    s.primitives[0].index_type = type;
    InputReport report;
    const Mesh mesh = read_input_mesh(glb("octa_" + std::to_string(type) + ".glb", s), &report);
    EXPECT_EQ(mesh.number_of_vertices(), 6u) << type;
    EXPECT_EQ(mesh.number_of_faces(), 8u) << type;
    EXPECT_TRUE(CGAL::is_closed(mesh)) << type;
    EXPECT_NEAR(report.volume, 4.0 / 3.0, 1e-12) << type;
    EXPECT_FALSE(report.reoriented) << type;
    EXPECT_EQ(report.welded_vertices, 0u) << type;
  }
}

TEST_F(GltfReader, ReadsAGltfWithADataUriAndOneWithAnExternalBuffer) {
  const test::GltfParts parts = test::gltf_parts(octahedron());
  const Mesh embedded = read_input_mesh(write("octa.gltf", test::gltf_text(parts)));
  EXPECT_EQ(embedded.number_of_vertices(), 6u);
  write("octa.bin", parts.bin);
  const Mesh external = read_input_mesh(write("octa_ext.gltf", test::gltf_text(parts, "octa.bin")));
  EXPECT_EQ(external.number_of_faces(), 8u);
  // The positions as written (file order kept).
  const Positions x = positions_from_mesh(external);
  EXPECT_EQ(x.row(2), Eigen::RowVector3d(0, 1, 0));
}

TEST_F(GltfReader, AppliesTheNodeTransform) {
  GltfScene s = octahedron();
  s.node_transform =
      "\"translation\":[10,0,-1],\"scale\":[2,2,2],\"rotation\":[0,0,0.7071067811865476,0."
      "7071067811865476]";
  InputReport report;
  const Positions x = positions_from_mesh(read_input_mesh(glb("moved.glb", s), &report));
  // 90 degrees about z: (1, 0, 0) -> (0, 1, 0), scaled by 2, then moved.
  EXPECT_NEAR(x(0, 0), 10.0, 1e-12);
  EXPECT_NEAR(x(0, 1), 2.0, 1e-12);
  EXPECT_NEAR(x(0, 2), -1.0, 1e-12);
  EXPECT_NEAR(x(4, 2), 1.0, 1e-12);  // (0, 0, 1) -> (0, 0, 2) - 1
  EXPECT_NEAR(report.volume, 8 * 4.0 / 3.0, 1e-9);

  GltfScene m = octahedron();  // a column-major matrix: translation in the last column
  m.node_transform = "\"matrix\":[1,0,0,0, 0,1,0,0, 0,0,1,0, 5,6,7,1]";
  const Positions y = positions_from_mesh(read_input_mesh(glb("matrix.glb", m)));
  EXPECT_EQ(y.row(0), Eigen::RowVector3d(6, 6, 7));
}

TEST_F(GltfReader, AMirroringNodeKeepsTheOutsideOut) {
  GltfScene s = octahedron();
  s.node_transform = "\"scale\":[-1,1,1]";
  InputReport report;
  read_input_mesh(glb("mirror.glb", s), &report);
  EXPECT_FALSE(report.reoriented);  // the winding was reversed with the mirror, as renderers do
  EXPECT_NEAR(report.volume, 4.0 / 3.0, 1e-12);
}

TEST_F(GltfReader, WeldsAVertexSplitAtAUvSeam) {
  InputReport report;
  const Mesh mesh = read_input_mesh(glb("seam.glb", octahedron(true, true)), &report);
  EXPECT_EQ(mesh.number_of_vertices(), 6u);
  EXPECT_EQ(report.welded_vertices, 1u);
  EXPECT_EQ(input_vertex_count(mesh), 7u);
  EXPECT_TRUE(CGAL::is_closed(mesh));
}

TEST_F(GltfReader, WeldsAnUnindexedTriangleListAndPrimitivesThatShareAnEdge) {
  const test::GltfPrimitive indexed = test::octahedron_primitive(false, false);
  test::GltfPrimitive list;
  list.indices.clear();
  for (const std::uint32_t i : indexed.indices) list.positions.push_back(indexed.positions[i]);
  GltfScene s;
  s.primitives.push_back(list);
  InputReport report;
  const Mesh mesh = read_input_mesh(glb("list.glb", s), &report);
  EXPECT_EQ(mesh.number_of_vertices(), 6u);
  EXPECT_EQ(report.welded_vertices, 18u);

  // The upper and lower halves as two primitives (two materials, say): welded along the equator.
  GltfScene halves;
  for (int h = 0; h < 2; ++h) {
    test::GltfPrimitive p = indexed;
    p.indices.assign(indexed.indices.begin() + 12 * h, indexed.indices.begin() + 12 * (h + 1));
    halves.primitives.push_back(p);
  }
  const Mesh two = read_input_mesh(glb("halves.glb", halves), &report);
  EXPECT_EQ(two.number_of_vertices(), 6u);
  EXPECT_EQ(two.number_of_faces(), 8u);
}

TEST_F(GltfReader, PrimitivesSharingOnePositionAccessorDrawItsElementsAsOneSetOfVertices) {
  // One POSITION accessor of 8 elements (element i at (i, 10 i, 100 i)); primitive 0 draws
  // elements 5 2 7, 7 2 0 and primitive 1 elements 3 6 1: the elements their corners use are
  // vertices once, in accessor order, whatever order the indices name them in, each with the
  // first primitive that draws it (found by sorting the corners, review7 F8: not by a walk of the
  // whole accessor per primitive). Before, each primitive had copies of its own, so that an
  // element that two primitives drew was two vertices, welded or refused as a seam.
  std::string bin;
  for (int i = 0; i < 8; ++i) {
    const float x[3] = {float(i), 10.0f * i, 100.0f * i};
    test::gltf_put(bin, x, 12);
  }
  for (const std::uint32_t i : {5u, 2u, 7u, 7u, 2u, 0u, 3u, 6u, 1u}) test::gltf_put(bin, &i, 4);
  const std::string json =
      "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
      "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":["
      "{\"attributes\":{\"POSITION\":0},\"indices\":1},"
      "{\"attributes\":{\"POSITION\":0},\"indices\":2}]}],\"accessors\":["
      "{\"bufferView\":0,\"componentType\":5126,\"count\":8,\"type\":\"VEC3\"},"
      "{\"bufferView\":1,\"componentType\":5125,\"count\":6,\"type\":\"SCALAR\"},"
      "{\"bufferView\":2,\"componentType\":5125,\"count\":3,\"type\":\"SCALAR\"}],"
      "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":96},"
      "{\"buffer\":0,\"byteOffset\":96,\"byteLength\":24},"
      "{\"buffer\":0,\"byteOffset\":120,\"byteLength\":12}],"
      "\"buffers\":[{\"byteLength\":132%URI%}]}";
  const std::string bytes = test::glb_bytes(test::GltfParts{json, bin});
  const GltfSoup s = read_gltf(write("shared.glb", bytes), bytes);
  const std::vector<std::pair<std::size_t, std::size_t>> from = {{0, 0}, {1, 1}, {0, 2}, {1, 3},
                                                                 {0, 5}, {1, 6}, {0, 7}};
  ASSERT_EQ(s.points.size(), from.size());
  for (std::size_t v = 0; v < from.size(); ++v) {
    EXPECT_EQ(s.sources[v].drawn, from[v].first) << v;
    EXPECT_EQ(s.sources[v].element, from[v].second) << v;
    const double e = static_cast<double>(from[v].second);
    EXPECT_EQ(s.points[v], (std::array<double, 3>{e, 10 * e, 100 * e})) << v;
  }
  const std::vector<std::vector<std::size_t>> faces = {{4, 2, 6}, {6, 2, 0}, {3, 5, 1}};
  EXPECT_EQ(s.faces, faces);
  EXPECT_EQ(s.face_drawn, (std::vector<std::size_t>{0, 0, 1}));
}

TEST_F(GltfReader, AClosedMeshSplitIntoPrimitivesOverOnePositionAccessorReadsClosed) {
  // An icosphere (162 vertices, 320 faces) as one POSITION accessor drawn by K primitives, each
  // over a slice of the faces, as exporters split a mesh per material: one vertex per element,
  // the closed mesh it is, nothing welded. Before, each primitive had its own copies, welded
  // like seam copies for K = 2 and refused for K = 3 and 7 ("open boundary: ... as given, its
  // faces are not a polygon mesh with boundary").
  const test::TriMesh sphere = test::icosphere(2);
  for (const std::size_t k : {1u, 3u, 7u})
    for (const bool binary : {true, false}) {
      const test::GltfParts parts = test::shared_position_parts(sphere, std::vector<int>(k, -1));
      const std::string path = write("split" + std::to_string(k) + (binary ? ".glb" : ".gltf"),
                                     binary ? test::glb_bytes(parts) : test::gltf_text(parts));
      SCOPED_TRACE(path);
      InputReport report;
      const Mesh mesh = read_input_mesh(path, &report);
      EXPECT_EQ(mesh.number_of_vertices(), 162u);
      EXPECT_EQ(mesh.number_of_faces(), 320u);
      EXPECT_TRUE(CGAL::is_closed(mesh));
      EXPECT_EQ(report.welded_vertices, 0u);
      EXPECT_TRUE(report.notes.empty()) << report.notes.front();
      EXPECT_EQ(input_vertex_count(mesh), 162u);
    }
}

TEST_F(GltfReader, PrimitivesWithTheirOwnNormalsOnASharedPositionHaveCopiesOfTheirOwn) {
  // Four primitives on one POSITION accessor: 0 and 1 share NORMAL accessor 1, 2 and 3 NORMAL
  // accessor 2 (the same values). An element that 1 and 2 draw has two normals, so two vertices,
  // welded as seam copies are (a note); 0 and 1 (2 and 3) share theirs. Before, every primitive
  // had copies of its own, and the file was refused as open.
  const test::TriMesh sphere = test::icosphere(2);
  const test::GltfParts parts = test::shared_position_parts(sphere, {0, 0, 1, 1});
  const std::string bytes = test::glb_bytes(parts);
  const std::string path = write("normals.glb", bytes);
  const GltfSoup s = read_gltf(path, bytes);
  ASSERT_EQ(s.faces.size(), 320u);
  ASSERT_EQ(s.face_drawn.size(), 320u);
  std::vector<std::vector<std::size_t>> copies(162);  // per element, its vertices
  for (std::size_t v = 0; v < s.points.size(); ++v) copies.at(s.sources[v].element).push_back(v);
  std::size_t twice = 0;
  for (const auto& c : copies) {
    ASSERT_FALSE(c.empty());
    ASSERT_LE(c.size(), 2u);
    if (c.size() == 2) {
      ++twice;
      // One copy of primitives 0 and 1 (which come first), one of primitives 2 and 3.
      EXPECT_LT(s.sources[c[0]].drawn, 2u);
      EXPECT_GE(s.sources[c[1]].drawn, 2u);
      EXPECT_EQ(s.points[c[0]], s.points[c[1]]);
    }
  }
  EXPECT_GT(twice, 0u);
  EXPECT_EQ(s.points.size(), 162u + twice);
  InputReport report;
  const Mesh mesh = read_input_mesh(path, &report);
  EXPECT_EQ(mesh.number_of_vertices(), 162u);
  EXPECT_TRUE(CGAL::is_closed(mesh));
  EXPECT_EQ(report.welded_vertices, twice);
}

TEST_F(GltfReader, RefusesMalformedFilesNamingTheProblem) {
  const auto expect = [&](const std::string& path, const std::vector<std::string>& parts) {
    const std::string e = error_of(path);
    EXPECT_NE(e.find(path + ": "), std::string::npos) << e;
    for (const std::string& p : parts)
      EXPECT_NE(e.find(p), std::string::npos) << "'" << p << "' not in: " << e;
  };
  GltfScene lines = octahedron();
  lines.primitives[0].mode = 1;
  expect(glb("lines.glb", lines), {"mesh 0 primitive 0: mode 1 (lines) is not triangles"});

  GltfScene out = octahedron();
  out.primitives[0].indices[5] = 9;
  expect(glb("index.glb", out),
         {"vertex index out of range", "mesh 0 primitive 0 triangle 1 refers to vertex 9",
          "POSITION has 6"});

  test::GltfParts parts = test::gltf_parts(octahedron());
  const std::string good = test::glb_bytes(parts);
  expect(write("truncated.glb", good.substr(0, good.size() - 7)),
         {"truncated .glb", "the header says"});
  expect(write("short.glb", good.substr(0, 9)), {"truncated .glb"});
  std::string bad_version = good;
  bad_version[4] = 1;
  expect(write("v1.glb", bad_version), {"unsupported glTF version", "version 1"});
  expect(write("json.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [ "),
         {"cannot read .gltf"});
  expect(write("empty_scene.gltf", "{\"asset\":{\"version\":\"2.0\"}}"), {"no scene"});
  expect(write("missing_bin.gltf", test::gltf_text(parts, "nowhere.bin")),
         {"cannot read .gltf", "nowhere.bin"});

  // An accessor longer than its buffer view: count raised in the JSON.
  test::GltfParts longer = parts;
  const std::size_t at = longer.json.find("\"count\":6");
  longer.json.replace(at, 9, "\"count\":600");
  expect(write("count.glb", test::glb_bytes(longer)),
         {"accessor out of range", "mesh 0 primitive 0 POSITION (accessor 0)", "600 elements"});

  test::GltfParts sparse = parts;
  sparse.json.replace(sparse.json.find("\"count\":6"), 9,
                      "\"count\":6,\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":1,"
                      "\"componentType\":5125},\"values\":{\"bufferView\":0}}");
  expect(write("sparse.glb", test::glb_bytes(sparse)), {"sparse accessor", "accessor 0"});

  GltfScene draco = octahedron();
  draco.extra =
      "\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],\"extensionsRequired\":[\"KHR_draco_"
      "mesh_compression\"]";
  expect(glb("draco.glb", draco), {"unsupported extension", "requires KHR_draco_mesh_compression"});

  GltfScene shorts = octahedron();
  shorts.primitives[0].indices.pop_back();
  expect(glb("not3.glb", shorts), {"bad triangle list", "23 indices"});
}

TEST_F(GltfReader, AnExtensionUsedButNotRequiredReadsTheFallback) {
  // Draco with the uncompressed accessors beside it (the spec's fallback): those are read.
  GltfScene s = octahedron();
  s.extra = "\"extensionsUsed\":[\"KHR_draco_mesh_compression\"]";
  test::GltfParts parts = test::gltf_parts(s);
  const std::string attrs = "{\"attributes\":{\"POSITION\":0}";
  parts.json.replace(parts.json.find(attrs), attrs.size(),
                     "{\"attributes\":{\"POSITION\":0},\"extensions\":{\"KHR_draco_mesh_"
                     "compression\":{\"bufferView\":0,\"attributes\":{\"POSITION\":0}}}");
  EXPECT_EQ(read_input_mesh(write("fallback.glb", test::glb_bytes(parts))).number_of_faces(), 8u);
}

TEST_F(GltfReader, AMaterialOnlyRequiredExtensionIsRead) {
  GltfScene s = octahedron();
  s.extra =
      "\"extensionsUsed\":[\"KHR_materials_unlit\"],\"extensionsRequired\":[\"KHR_materials_"
      "unlit\"]";
  EXPECT_EQ(read_input_mesh(glb("unlit.glb", s)).number_of_faces(), 8u);
}

}  // namespace
}  // namespace shellcontract
