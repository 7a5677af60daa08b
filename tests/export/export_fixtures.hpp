// Helpers of the export tests: a scratch folder, a mesh read from meshes/, a fake contraction.
#pragma once

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/types.hpp"
#include "test_paths.hpp"

namespace shellcontract::test {

/// A fresh folder for one test, removed afterwards.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    static int n = 0;
    path_ = std::filesystem::temp_directory_path() /
            ("shellcontract_test_export_" + tag + "_" + std::to_string(::getpid()) + "_" +
             std::to_string(n++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string str() const { return path_.string(); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

/// A file's bytes.
inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Faces of a triangle mesh in face index order.
inline Faces faces_of(const Mesh& mesh) {
  Faces f(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
  for (const FaceIndex face : mesh.faces()) {
    int k = 0;
    for (const VertexIndex v : vertices_around_face(mesh.halfedge(face), mesh))
      f(static_cast<Eigen::Index>(face.idx()), k++) = static_cast<int>(v.idx());
  }
  return f;
}

/// Frame `frame` of a made-up contraction of x (not physics): an anisotropic shrink about the
/// centroid with a wave along z that grows with time, so every frame differs from the others.
inline Positions fake_frame(const Positions& x, int frame, int frames) {
  const double t = frames > 0 ? static_cast<double>(frame) / frames : 0.0;
  const Eigen::RowVector3d c = x.colwise().mean();
  Positions y = x;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Eigen::RowVector3d d = x.row(i) - c;
    const double s = 1.0 - 0.45 * t + 0.12 * t * std::sin(7.0 * d(2) + 2.0 * d(0));
    y.row(i) = c + Eigen::RowVector3d(s * d(0), s * d(1), (1.0 - 0.25 * t) * s * d(2));
  }
  return y;
}

}  // namespace shellcontract::test
