// The PLY document: extra vertex properties (texture coordinates, colours), face
// properties, comments and other elements come back unchanged; x, y, z are the new positions in
// their declared type. The layouts are written here by hand, so the bytes to compare are known.
#include <gtest/gtest.h>
#include <unistd.h>  // getpid: temporary files of this process's own

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "mesh/ply_reader.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract {
namespace {

// A tetrahedron: 4 vertices, 4 faces, outward.
const double TET[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const int TET_FACES[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

Positions moved_tet() {
  Positions y(4, 3);
  y << 0.1, -0.2, 0.3, 1.25, 0.01, -0.125, 0.1 / 3.0, 0.9, 0.02, -0.01, 0.03, 0.7;
  return y;
}

std::string ascii_tet() {
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\n"
       "property float x\nproperty float y\nproperty float z\nproperty float s\nproperty float t\n"
       "property uchar red\nproperty uchar green\nproperty uchar blue\n"
       "element face 4\nproperty list uchar int vertex_indices\nproperty int flags\n"
       "element material 1\nproperty float shininess\nend_header\n";
  for (int i = 0; i < 4; ++i)
    o << TET[i][0] << ' ' << TET[i][1] << ' ' << TET[i][2] << ' ' << 0.25 * i << ' ' << 1.0 - 0.125 * i << ' '
      << 10 * i << ' ' << 20 * i + 1 << ' ' << 255 - i << '\n';
  for (int f = 0; f < 4; ++f) o << "3 " << TET_FACES[f][0] << ' ' << TET_FACES[f][1] << ' ' << TET_FACES[f][2] << ' ' << 7 * f << '\n';
  o << "0.5\n";
  return o.str();
}

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> t;
  for (std::string w; in >> w;) t.push_back(w);
  return t;
}

TEST(PlyDocument, AsciiKeepsEveryOtherValueAndWritesTheFloatPositions) {
  const std::string in = ascii_tet();
  const auto doc = parse_ply_document("tet.ply", in);
  ASSERT_EQ(doc->vertex_count(), 4u);
  ASSERT_EQ(doc->polygon_count(), 4u);
  const Positions y = moved_tet();
  const std::string out = doc->text(y);
  // The header verbatim; the body token by token: x, y, z are the first 3 of each 8-token vertex.
  const std::size_t h = in.find("end_header\n") + 11;
  ASSERT_EQ(out.substr(0, h), in.substr(0, h));
  const std::vector<std::string> a = tokens(in.substr(h)), b = tokens(out.substr(h));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    if (i >= 32 || i % 8 >= 3) {
      EXPECT_EQ(a[i], b[i]) << "token " << i;
    }
  // Read back by the project's reader (which parses ascii as double): a reader that stores the
  // float properties as floats gets exactly the floats of the new positions.
  const PlyData d = read_ply("out.ply", out);
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(static_cast<float>(d.points[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)]), static_cast<float>(y(i, k)));
  EXPECT_EQ(d.faces.size(), 4u);
}

// An element without properties has nothing to read: within the file's size its count changes
// nothing but its header line; beyond it the file is refused, naming the element (the document
// walked every declared instance: 10^15 of them would take days, so the old code times out here).
TEST(PlyDocument, AnElementWithoutPropertiesIsSkippedOrRefused) {
  const std::string in = ascii_tet();
  const std::size_t at = in.find("end_header\n");
  const std::string line = "element marker 100\n";
  const std::string with = in.substr(0, at) + line + in.substr(at);
  const Positions y = moved_tet();
  const std::string out = parse_ply_document("marked.ply", with)->text(y);
  const std::string plain = parse_ply_document("tet.ply", in)->text(y);
  EXPECT_EQ(out, plain.substr(0, at) + line + plain.substr(at));
  const std::string huge = in.substr(0, at) + "element marker 1000000000000000\n" + in.substr(at);
  try {
    (void)parse_ply_document("huge.ply", huge);
    ADD_FAILURE() << "a count of 10^15 instances in " << huge.size() << " bytes was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("huge.ply: implausible count: element 'marker' (line 18)"),
              std::string::npos)
        << e.what();
  }
}

/// The same tetrahedron in binary: double x y z, float u v, uchar alpha; faces with a float
/// property before the list. Big or little endian.
std::string binary_tet(bool big) {
  std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
                  "property float u\nproperty float v\nproperty uchar alpha\n"
                  "element face 4\nproperty float quality\nproperty list uchar uint vertex_indices\nend_header\n";
  auto put = [&](const void* p, std::size_t n) {
    unsigned char b[8];
    std::memcpy(b, p, n);
    if (big)
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    s.append(reinterpret_cast<const char*>(b), n);
  };
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 3; ++k) put(&TET[i][k], 8);
    const float u = 0.1f * static_cast<float>(i), v = 0.5f + 0.1f * static_cast<float>(i);
    put(&u, 4);
    put(&v, 4);
    const unsigned char alpha = static_cast<unsigned char>(200 + i);
    put(&alpha, 1);
  }
  for (int f = 0; f < 4; ++f) {
    const float q = 0.25f * static_cast<float>(f);
    put(&q, 4);
    const unsigned char n = 3;
    put(&n, 1);
    for (int k = 0; k < 3; ++k) {
      const auto idx = static_cast<std::uint32_t>(TET_FACES[f][k]);
      put(&idx, 4);
    }
  }
  return s;
}

TEST(PlyDocument, BinaryOfEitherByteOrderChangesOnlyThePositionBytes) {
  for (const bool big : {false, true}) {
    const std::string in = binary_tet(big);
    const auto doc = parse_ply_document("tet.ply", in);
    const Positions y = moved_tet();
    const std::string out = doc->text(y);
    ASSERT_EQ(out.size(), in.size());
    const std::size_t h = in.find("end_header\n") + 11;
    // Vertex i's record is 33 bytes at h + 33 i: x y z are its first 24, the rest must not change.
    for (std::size_t b = 0; b < in.size(); ++b) {
      const bool position = b >= h && b < h + 4 * 33 && (b - h) % 33 < 24;
      if (!position) {
        EXPECT_EQ(in[b], out[b]) << "byte " << b << (big ? " (big endian)" : "");
      }
    }
    const PlyData d = read_ply("out.ply", out);
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(d.points[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)], y(i, k));
  }
}

/// The mesh and the document of a PLY file with `text` (written to the temp folder as `name`
/// after this process's id, and removed again), as a run reads its input.
std::pair<Mesh, std::unique_ptr<MeshDocument>> read_ply_file(const std::string& name,
                                                             const std::string& text) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name);
  std::ofstream(path) << text;
  Mesh mesh = read_input_mesh(path.string());
  auto doc = read_mesh_document(path.string());
  std::filesystem::remove(path);
  return {std::move(mesh), std::move(doc)};
}

TEST(PlyDocument, TextureCoordinatesArePerVertex) {
  // Vertex i has (s, t) = (0.25 i, 1 - 0.125 i) in ascii_tet (exact in float): every corner of
  // every simulation face must get its vertex's.
  const auto [mesh, doc] = read_ply_file("shellcontract_ply_document_uv.ply", ascii_tet());
  ASSERT_TRUE(doc && doc->matches(mesh));
  const CornerTexcoords tc = doc->texcoords(mesh);
  ASSERT_EQ(tc.face_uv.size(), 4u);
  for (const FaceIndex f : mesh.faces()) {
    std::size_t k = 0;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) {
      const auto& uv = tc.uv.at(tc.face_uv[f.idx()][k++]);
      EXPECT_EQ(uv[0], 0.25 * v.idx());
      EXPECT_EQ(uv[1], 1.0 - 0.125 * v.idx());
    }
  }
  const auto none = parse_ply_document("plain.ply",
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  EXPECT_TRUE(none->texcoords(mesh).empty());
}

TEST(PlyDocument, TextureCoordinatesPerFaceCornerAreRead) {
  // MeshLab's wedge texture coordinates: a face list `texcoord` of u v per corner, so a vertex
  // has one pair per face around it (a seam without split vertices). Corner k of face f has
  // (f / 8 + k / 64, 1 - k / 16) (exact in float); every simulation corner must get its own.
  auto uv_of = [](std::size_t f, std::size_t k) {
    return std::array<double, 2>{static_cast<double>(f) / 8 + static_cast<double>(k) / 64,
                                 1.0 - static_cast<double>(k) / 16};
  };
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 4\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
       "property int flags\nend_header\n";
  for (int i = 0; i < 4; ++i) o << TET[i][0] << ' ' << TET[i][1] << ' ' << TET[i][2] << '\n';
  for (std::size_t f = 0; f < 4; ++f) {
    o << "3 " << TET_FACES[f][0] << ' ' << TET_FACES[f][1] << ' ' << TET_FACES[f][2] << " 6";
    for (std::size_t k = 0; k < 3; ++k) o << ' ' << uv_of(f, k)[0] << ' ' << uv_of(f, k)[1];
    o << " 9\n";
  }
  const auto [mesh, doc] = read_ply_file("shellcontract_ply_document_wedge.ply", o.str());
  ASSERT_TRUE(doc && doc->matches(mesh));
  const CornerTexcoords tc = doc->texcoords(mesh);
  ASSERT_EQ(tc.face_uv.size(), 4u);
  for (const FaceIndex f : mesh.faces()) {
    std::size_t k = 0;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(f), mesh)) {
      std::size_t corner = 0;  // the file's corner of face f at vertex v
      while (corner < 3 && TET_FACES[f.idx()][corner] != static_cast<int>(v.idx())) ++corner;
      ASSERT_LT(corner, 3u);
      const auto& uv = tc.uv.at(tc.face_uv[f.idx()][k++]);
      EXPECT_EQ(uv[0], uv_of(f.idx(), corner)[0]) << "face " << f.idx() << ", vertex " << v.idx();
      EXPECT_EQ(uv[1], uv_of(f.idx(), corner)[1]) << "face " << f.idx() << ", vertex " << v.idx();
    }
  }
  // Corners with equal pairs share one coordinate (the glTF splits a vertex only at a seam): each
  // face giving vertex v the same pair (v / 4, v / 8) makes 4 coordinates, not 12.
  std::ostringstream same;
  same << o.str().substr(0, o.str().find("end_header\n") + 11);
  for (int i = 0; i < 4; ++i) same << TET[i][0] << ' ' << TET[i][1] << ' ' << TET[i][2] << '\n';
  for (std::size_t f = 0; f < 4; ++f) {
    same << "3";
    for (std::size_t k = 0; k < 3; ++k) same << ' ' << TET_FACES[f][k];
    same << " 6";
    for (std::size_t k = 0; k < 3; ++k) same << ' ' << TET_FACES[f][k] / 4.0 << ' ' << TET_FACES[f][k] / 8.0;
    same << " 9\n";
  }
  EXPECT_EQ(parse_ply_document("same.ply", same.str())->texcoords(mesh).uv.size(), 4u);
  // A face whose list does not hold two numbers per corner: no texture coordinates at all.
  std::string bad = o.str();
  bad.replace(bad.rfind(" 6 "), 3, " 8 ");
  bad.replace(bad.rfind(" 9\n"), 3, " 0 0 9\n");
  const auto wrong_count = parse_ply_document("wrong_count.ply", bad);
  EXPECT_TRUE(wrong_count->texcoords(mesh).empty());
}

}  // namespace
}  // namespace shellcontract

namespace shellcontract {
namespace {

/// A unit box of 24 vertices, 4 per side (each side's own copies, as a flat-shaded export writes
/// them), as an ASCII PLY with nx, ny, nz: `flat` gives each copy its side's normal; otherwise
/// every copy at a corner has the corner's diagonal (a smooth export's one normal per position).
/// `corners` gets the 24 rest positions and `quads` the 6 sides, outward.
std::string box_ply(bool flat, Positions& corners, std::vector<std::array<int, 4>>& quads) {
  const int axes[6][3] = {{0, 1, 2}, {0, 1, 2}, {1, 2, 0}, {1, 2, 0}, {2, 0, 1}, {2, 0, 1}};
  corners.resize(24, 3);
  quads.clear();
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\nelement vertex 24\nproperty double x\nproperty double y\n"
       "property double z\nproperty double nx\nproperty double ny\nproperty double nz\n"
       "element face 6\nproperty list uchar int vertex_indices\nend_header\n";
  for (int s = 0; s < 6; ++s) {
    const int n = axes[s][2], u = axes[s][0], v = axes[s][1];
    const double side = s % 2 == 0 ? 1.0 : 0.0;  // sides at 1 face +axis, at 0 face -axis
    const double uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
      Eigen::Vector3d p;
      p[n] = side;
      p[u] = uv[k][0];
      p[v] = uv[k][1];
      corners.row(4 * s + k) = p.transpose();
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      normal[n] = side > 0.5 ? 1.0 : -1.0;
      if (!flat) normal = (2.0 * p - Eigen::Vector3d::Ones()).normalized();
      o << p[0] << ' ' << p[1] << ' ' << p[2] << ' ' << normal[0] << ' ' << normal[1] << ' '
        << normal[2] << '\n';
    }
    // (u, v, n) is right-handed, so 0 1 2 3 turns about +n: reversed on the sides facing -n.
    quads.push_back(side > 0.5 ? std::array<int, 4>{4 * s, 4 * s + 1, 4 * s + 2, 4 * s + 3}
                               : std::array<int, 4>{4 * s, 4 * s + 3, 4 * s + 2, 4 * s + 1});
  }
  for (const auto& q : quads)
    o << "4 " << q[0] << ' ' << q[1] << ' ' << q[2] << ' ' << q[3] << '\n';
  return o.str();
}

/// The written nx, ny, nz of the 24 vertices of box_ply's layout.
/// An affine map with shear, so that no side of the box stays parallel to an axis.
Eigen::Matrix3d shear() {
  Eigen::Matrix3d a;
  a << 2.0, 0.3, 0.0, 0.0, 1.0, 0.2, 0.1, 0.0, 0.7;
  return a;
}

/// The Newell vector of quad q at positions y (twice its area along its normal).
Eigen::Vector3d newell(const Positions& y, const std::array<int, 4>& q) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (int k = 0; k < 4; ++k)
    n += Eigen::Vector3d(y.row(q[k])).cross(Eigen::Vector3d(y.row(q[(k + 1) % 4])));
  return n;
}

Positions written_normals(const std::string& out) {
  const std::vector<std::string> t = tokens(out.substr(out.find("end_header\n") + 11));
  Positions n(24, 3);
  for (int i = 0; i < 24; ++i)
    for (int k = 0; k < 3; ++k) n(i, k) = std::stod(t.at(static_cast<std::size_t>(6 * i + 3 + k)));
  return n;
}

TEST(PlyDocument, AFlatShadedBoxKeepsItsHardEdges) {
  // Each side's corners carry the side's normal in the file: after an affine map (a plane stays a
  // plane) each corner's new normal is its own side's normal at the new positions (the side's
  // Newell vector, computed here), not the mean of the three sides at its position. Fails when
  // the copies at one position share one normal (the document's former behaviour).
  Positions rest;
  std::vector<std::array<int, 4>> quads;
  const std::string in = box_ply(true, rest, quads);
  const Positions y = (rest * shear().transpose()).rowwise() + Eigen::RowVector3d(0.5, -1.0, 2.0);
  const Positions got = written_normals(parse_ply_document("box.ply", in)->text(y));
  for (const auto& q : quads)
    for (const int v : q)
      EXPECT_NEAR((Eigen::Vector3d(got.row(v)) - newell(y, q).normalized()).norm(), 0.0, 1e-12)
          << "vertex " << v;
}

TEST(PlyDocument, CopiesWithOneNormalStaySmooth) {
  // The same box, every copy at a corner with the corner's one normal (a smooth export split at
  // seams): the three copies at a position get one normal, the normalized sum of the three
  // sides' Newell vectors there, bit for bit the same.
  Positions rest;
  std::vector<std::array<int, 4>> quads;
  const std::string in = box_ply(false, rest, quads);
  const Positions y = rest * shear().transpose();
  const Positions got = written_normals(parse_ply_document("box.ply", in)->text(y));
  for (int v = 0; v < 24; ++v) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& q : quads) {
      bool here = false;
      for (const int c : q) here = here || rest.row(c) == rest.row(v);
      if (here) sum += newell(y, q);
    }
    EXPECT_NEAR((Eigen::Vector3d(got.row(v)) - sum.normalized()).norm(), 0.0, 1e-12)
        << "vertex " << v;
    for (int w = 0; w < 24; ++w) {
      if (rest.row(w) == rest.row(v)) {
        EXPECT_EQ(got.row(w), got.row(v)) << v << " and " << w;
      }
    }
  }
}

/// Vertex i's normal at positions y: the normalized sum of its faces' edge-vector cross products.
Eigen::Vector3d tet_vertex_normal(const Positions& y, int i) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& f : TET_FACES)
    if (f[0] == i || f[1] == i || f[2] == i) {
      const Eigen::Vector3d a = y.row(f[0]), b = y.row(f[1]), c = y.row(f[2]);
      sum += (b - a).cross(c - a);
    }
  return sum.normalized();
}

TEST(PlyDocument, NormalsAreThoseOfTheNewShape) {
  // A tetrahedron whose nx, ny, nz (double, between y and z and after a colour, so that the
  // slots are not contiguous) all say +z: the output's are each vertex's normalized sum of its
  // faces' cross products at the moved positions, computed here from the faces; every other
  // token is kept. Fails with the normals left as read (the document's former behaviour) or
  // taken at the rest positions.
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
       "property double nx\nproperty float z\nproperty uchar red\nproperty double ny\n"
       "property double nz\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 4; ++i)
    o << TET[i][0] << ' ' << TET[i][1] << " 0 " << TET[i][2] << ' ' << 10 * i << " 0 1\n";
  for (const auto& f : TET_FACES) o << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  const std::string in = o.str();
  const auto doc = parse_ply_document("tet.ply", in);
  const Positions y = moved_tet();
  const std::string out = doc->text(y);
  const std::string body = out.substr(out.find("end_header\n") + 11);
  const std::vector<std::string> t = tokens(body);
  ASSERT_EQ(t.size(), 4u * 7u + 4u * 4u);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d want = tet_vertex_normal(y, i);
    const std::size_t at = 7 * static_cast<std::size_t>(i);
    const Eigen::Vector3d got(std::stod(t[at + 2]), std::stod(t[at + 5]), std::stod(t[at + 6]));
    EXPECT_NEAR((got - want).norm(), 0.0, 1e-12) << "vertex " << i;
    EXPECT_EQ(std::stof(t[at]), static_cast<float>(y(i, 0)));
    EXPECT_EQ(t[at + 4], std::to_string(10 * i));
  }
  EXPECT_EQ(std::vector<std::string>(t.begin() + 28, t.end()),
            tokens(in.substr(in.rfind("3 0 2 1"))));
}

TEST(PlyDocument, NormalsOfAResultFarFromTheOriginAreThoseOfItsShape) {
  // The tetrahedron moved to UTM-like metres (500000, 5000000, 100): its new normals are its
  // faces' edge-vector cross products, as at the origin. A Newell sum of absolute cross products
  // (terms of size 1e13 cancelling to areas of order 1) returned rounding noise instead (review
  // numguards M1).
  std::ostringstream o;
  o << "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
       "property double z\nproperty double nx\nproperty double ny\nproperty double nz\n"
       "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 4; ++i) o << TET[i][0] << ' ' << TET[i][1] << ' ' << TET[i][2] << " 0 0 1\n";
  for (const auto& f : TET_FACES) o << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  const Positions y = moved_tet().rowwise() + Eigen::RowVector3d(500000.0, 5000000.0, 100.0);
  const std::vector<std::string> t = tokens(
      parse_ply_document("far.ply", o.str())->text(y).substr(o.str().find("end_header\n") + 11));
  ASSERT_EQ(t.size(), 4u * 6u + 4u * 4u);
  for (int i = 0; i < 4; ++i) {
    const std::size_t at = 6 * static_cast<std::size_t>(i);
    const Eigen::Vector3d got(std::stod(t[at + 3]), std::stod(t[at + 4]), std::stod(t[at + 5]));
    EXPECT_NEAR((got - tet_vertex_normal(y, i)).norm(), 0.0, 1e-12) << "vertex " << i;
  }
}

}  // namespace
}  // namespace shellcontract
