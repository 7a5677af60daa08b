// The regions of a run in its .glb (docs/design/export.md, "Regions"): the categorical attribute
// _REGION, each face's three corners holding its region's id, listed in the mesh's extras as
// categorical (ids, no percentiles). The ids a face should have are computed here from the face
// lists (a --regions file, `regions --face-list`), not read from the writer's input.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "export/gltf_size.hpp"
#include "export_fixtures.hpp"
#include "gltf_reader.hpp"
#include "shellcontract/export.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// Per face, the region whose line of the face-list file `path` lists it (lines in order, ids
/// from 0; a strength "S:" in front is skipped), or -1.
std::vector<int> regions_of_face_list(const std::string& path, std::size_t faces) {
  std::vector<int> region(faces, -1);
  std::ifstream in(path);
  std::string line;
  int r = 0;
  while (std::getline(in, line)) {
    if (line.find(':') != std::string::npos) line = line.substr(line.find(':') + 1);
    std::istringstream ids(line);
    int f = 0;
    bool any = false;
    while (ids >> f) {
      region.at(static_cast<std::size_t>(f)) = r;
      any = true;
    }
    if (any) ++r;
  }
  return region;
}

/// The glTF vertices a split by region makes: per vertex, one for each region among its faces
/// (none, -1, counting as one).
std::size_t vertices_split_by_region(const Faces& faces, const std::vector<int>& region,
                                     Eigen::Index nv) {
  std::vector<std::set<int>> ids(static_cast<std::size_t>(nv));
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      ids[static_cast<std::size_t>(faces(f, k))].insert(region[static_cast<std::size_t>(f)]);
  std::size_t n = 0;
  for (const auto& s : ids) n += std::max<std::size_t>(1, s.size());
  return n;
}

/// The .glb's _REGION per glTF vertex, after checking its accessor is float SCALAR.
test::Floats region_values(const tinygltf::Model& m) {
  const tinygltf::Primitive& p = m.meshes.at(0).primitives.at(0);
  const int acc = p.attributes.at("_REGION");
  EXPECT_EQ(m.accessors.at(static_cast<std::size_t>(acc)).type, TINYGLTF_TYPE_SCALAR);
  return test::read_floats(m, acc);
}

/// Every face's corners carry its region's id (the .glb's faces are the input's, in order: one
/// primitive), and every id is a whole number.
void expect_corner_ids(const tinygltf::Model& m, const std::vector<int>& region) {
  const test::Floats ids = region_values(m);
  const std::vector<std::uint32_t> idx =
      test::read_indices(m, m.meshes.at(0).primitives.at(0).indices);
  ASSERT_EQ(idx.size(), 3 * region.size());
  for (std::size_t c = 0; c < idx.size(); ++c)
    ASSERT_EQ(ids(static_cast<Eigen::Index>(idx[c]), 0), static_cast<float>(region[c / 3]))
        << "face " << c / 3 << " corner " << c % 3;
}

/// The extras' entry of the categorical field: name, attribute, none, and the ids used, in order.
void expect_categorical_entry(const tinygltf::Model& m, const std::vector<int>& region) {
  const tinygltf::Value& extras = m.meshes.at(0).extras;
  ASSERT_TRUE(extras.Has("categorical_fields"));
  const tinygltf::Value& list = extras.Get("categorical_fields");
  ASSERT_EQ(list.ArrayLen(), 1u);
  const tinygltf::Value& e = list.Get(0);
  EXPECT_EQ(e.Get("name").Get<std::string>(), "region");
  EXPECT_EQ(e.Get("values_attribute").Get<std::string>(), "_REGION");
  EXPECT_EQ(e.Get("none").GetNumberAsInt(), -1);
  EXPECT_FALSE(e.Has("low"));  // ids, not a range a viewer maps onto a ramp
  EXPECT_FALSE(e.Has("high"));
  std::set<int> used(region.begin(), region.end());
  used.erase(-1);
  const tinygltf::Value& ids = e.Get("ids");
  ASSERT_EQ(ids.ArrayLen(), used.size());
  int k = 0;
  for (const int r : used) EXPECT_EQ(ids.Get(k++).GetNumberAsInt(), r);
  // Not among the colour fields, whose entries have a range.
  if (extras.Has("colour_fields")) {
    for (std::size_t i = 0; i < extras.Get("colour_fields").ArrayLen(); ++i) {
      EXPECT_NE(extras.Get("colour_fields").Get(static_cast<int>(i)).Get("name").Get<std::string>(),
                "region");
    }
  }
}

/// Regions of bumpy_sphere by where each face's centroid is, for the library's tests: a cap at
/// +z (region 0) meeting a band at +x (region 2; no face has 1), so some vertices touch three ids.
std::vector<int> made_up_regions(const Positions& x, const Faces& faces) {
  std::vector<int> region(static_cast<std::size_t>(faces.rows()), -1);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 c = (x.row(faces(f, 0)) + x.row(faces(f, 1)) + x.row(faces(f, 2))).transpose() / 3;
    if (c.z() > 0.3)
      region[static_cast<std::size_t>(f)] = 0;
    else if (c.x() > 0.25)
      region[static_cast<std::size_t>(f)] = 2;
  }
  return region;
}

GltfAnimation bumpy_animation(std::vector<int>* region) {
  const Mesh mesh = read_input_mesh(std::string(test::MESH_DIR) + "/bumpy_sphere.off");
  GltfAnimation a;
  a.faces = test::faces_of(mesh);
  const Positions x0 = positions_from_mesh(mesh);
  for (int f = 0; f <= 8; f += 4) {
    a.frame_numbers.push_back(f);
    a.frames.push_back(test::fake_frame(x0, f, 8));
  }
  a.colour_fields.push_back({"mean_curvature", x0.col(2)});
  if (region) {
    *region = made_up_regions(x0, a.faces);
    a.face_region = *region;
  }
  return a;
}

TEST(GltfRegions, EachFacesCornersHoldItsRegionAndRimVerticesAreSplit) {
  std::vector<int> region;
  const GltfAnimation a = bumpy_animation(&region);
  ASSERT_GT(std::count(region.begin(), region.end(), 0), 0);
  ASSERT_GT(std::count(region.begin(), region.end(), 2), 0);
  test::ScratchDir dir("regions");
  write_gltf_animation(dir.file("r.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("r.glb"));
  ASSERT_EQ(m.meshes.at(0).primitives.size(), 1u);
  expect_corner_ids(m, region);
  expect_categorical_entry(m, region);

  // One copy per region a vertex's faces are in, each at its vertex in every frame, with its
  // normal (a rim shows no seam).
  const tinygltf::Primitive& p = m.meshes[0].primitives[0];
  const test::Floats x = test::read_positions(m, p.attributes.at("POSITION"));
  const test::Floats n = test::read_floats(m, p.attributes.at("NORMAL"));
  const Eigen::Index nv = a.frames[0].rows();
  ASSERT_EQ(static_cast<std::size_t>(x.rows()), vertices_split_by_region(a.faces, region, nv));
  ASSERT_GT(x.rows(), nv);
  const std::vector<std::uint32_t> idx = test::read_indices(m, p.indices);
  for (std::size_t c = 0; c < idx.size(); ++c) {
    const auto v = static_cast<Eigen::Index>(idx[c]);
    const int source = a.faces(static_cast<Eigen::Index>(c / 3), static_cast<int>(c % 3));
    EXPECT_LE((x.row(v).cast<double>() - a.frames[0].row(source)).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LE((n.row(v) - n.row(source)).cwiseAbs().maxCoeff(), 1e-6f);
    for (std::size_t k = 0; k < p.targets.size(); ++k) {
      const test::Floats d = test::read_floats(m, p.targets[k].at("POSITION"));
      EXPECT_EQ(d.row(v), d.row(source)) << "frame " << a.frame_numbers[k + 1];
    }
  }
}

TEST(GltfRegions, NoRegionsNoAttribute) {
  const GltfAnimation a = bumpy_animation(nullptr);
  test::ScratchDir dir("no_regions");
  write_gltf_animation(dir.file("r.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("r.glb"));
  EXPECT_EQ(m.meshes.at(0).primitives.at(0).attributes.count("_REGION"), 0u);
  EXPECT_FALSE(m.meshes.at(0).extras.Has("categorical_fields"));
  EXPECT_EQ(test::read_floats(m, m.meshes[0].primitives[0].attributes.at("POSITION")).rows(),
            a.frames[0].rows());
}

TEST(GltfRegions, AColourFieldCalledRegionKeepsItsOwnAttribute) {
  std::vector<int> region;
  GltfAnimation a = bumpy_animation(&region);
  a.colour_fields.push_back({"region", a.frames[0].col(0)});
  test::ScratchDir dir("region_field");
  write_gltf_animation(dir.file("r.glb"), a);
  const tinygltf::Model m = test::load_glb(dir.file("r.glb"));
  expect_corner_ids(m, region);
  const tinygltf::Value& fields = m.meshes[0].extras.Get("colour_fields");
  const std::string attr = fields.Get(1).Get("values_attribute").Get<std::string>();
  EXPECT_NE(attr, "_REGION");
  EXPECT_EQ(m.meshes[0].primitives[0].attributes.count(attr), 1u);
}

TEST(GltfRegions, TheSizeBoundCountsTheRegionsAttributeAndCopies) {
  std::vector<int> region;
  const GltfAnimation a = bumpy_animation(&region);
  GltfAnimation layout = a;  // what the bound is given: frame 0, the faces, their regions
  layout.frames.resize(1);
  layout.frame_numbers.resize(1);
  for (NamedVertexField& f : layout.colour_fields) f.values.resize(0);
  const std::size_t vertices = gltf::glb_vertices(layout);
  EXPECT_EQ(vertices, vertices_split_by_region(a.faces, region, a.frames[0].rows()));
  test::ScratchDir dir("regions_size");
  const GltfStats stats = write_gltf_animation(dir.file("r.glb"), a);
  EXPECT_GE(gltf::glb_size_bound(layout, a.frames.size(), vertices), stats.bytes);
  EXPECT_GE(gltf::buffer_capacity(layout, vertices, a.frames.size()), stats.buffer_bytes);
}

TEST(GltfRegions, BadRegionIdsAreRefused) {
  std::vector<int> region;
  test::ScratchDir dir("bad_regions");
  for (const int bad : {-2, 1 << 24}) {
    GltfAnimation a = bumpy_animation(&region);
    a.face_region[7] = bad;
    EXPECT_THROW(write_gltf_animation(dir.file("r.glb"), a), std::invalid_argument) << bad;
  }
  GltfAnimation a = bumpy_animation(&region);
  a.face_region.pop_back();
  EXPECT_THROW(write_gltf_animation(dir.file("r.glb"), a), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir.file("r.glb")));
}

TEST(CliGltfRegions, ARegionsRunsGlbHoldsEachFacesRegion) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  test::ScratchDir dir("cli_regions");
  const std::string mesh = std::string(test::MESH_DIR) + "/bumpy_sphere.off";
  const std::string bumps = std::string(test::MESH_DIR) + "/bumpy_sphere.bumps.txt";
  const Faces faces = test::faces_of(read_input_mesh(mesh));
  const auto faces_count = static_cast<std::size_t>(faces.rows());

  // A --regions file: its lines' faces.
  auto r = test::run_cli({"run", mesh, "-o", dir.file("file.off"), "-n", "4", "-q", "--regions",
                          bumps, "--gltf", dir.file("file.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<int> from_file = regions_of_face_list(bumps, faces_count);
  ASSERT_EQ(*std::max_element(from_file.begin(), from_file.end()), 2);  // the three bumps
  tinygltf::Model m = test::load_glb(dir.file("file.glb"));
  expect_corner_ids(m, from_file);
  expect_categorical_entry(m, from_file);
  EXPECT_EQ(static_cast<std::size_t>(region_values(m).rows()),
            vertices_split_by_region(faces, from_file, 642));

  // --regions auto: the regions `shellcontract regions --face-list` lists.
  r = test::run_cli({"regions", mesh, "--face-list", dir.file("auto.txt")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::run_cli({"run", mesh, "-o", dir.file("auto.off"), "-n", "4", "-q", "--regions", "auto",
                     "--gltf", dir.file("auto.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<int> found = regions_of_face_list(dir.file("auto.txt"), faces_count);
  ASSERT_GE(*std::max_element(found.begin(), found.end()), 0);
  m = test::load_glb(dir.file("auto.glb"));
  expect_corner_ids(m, found);
  expect_categorical_entry(m, found);

  // No regions: no attribute, no entry, the input's vertices.
  r = test::run_cli(
      {"run", mesh, "-o", dir.file("plain.off"), "-n", "4", "-q", "--gltf", dir.file("plain.glb")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  m = test::load_glb(dir.file("plain.glb"));
  EXPECT_EQ(m.meshes.at(0).primitives.at(0).attributes.count("_REGION"), 0u);
  EXPECT_FALSE(m.meshes.at(0).extras.Has("categorical_fields"));
  EXPECT_EQ(test::read_floats(m, m.meshes[0].primitives[0].attributes.at("POSITION")).rows(), 642);
}

}  // namespace
}  // namespace shellcontract
