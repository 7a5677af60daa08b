// The regions' coloured PLY (shellcontract/regions.hpp: region_colour, write_region_ply). The
// file is the one CGAL's write_PLY gives for mesh_for_output's copy with the maps attached
// (header, "x y z H K " and "3 a b c r g b a id " lines, doubles at 17 significant digits as
// std::to_chars writes them, as write_ply_atomic's stream does), formatted here in chunks in
// parallel and joined in order: CGAL's stream formats every number in turn, a large part of the
// `regions` command on a large mesh (lab/regions/speed.md).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesh/properties.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/regions.hpp"

namespace shellcontract {
namespace {

/// Vertices or faces formatted per chunk (a chunk's text is a few hundred kilobytes).
constexpr std::size_t CHUNK = 8192;

/// write_ply_atomic's precision (every double reads back bitwise).
constexpr int FULL_PRECISION = 17;

void put_double(std::string& out, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, FULL_PRECISION);
  out.append(buf, r.ptr);
}

void put_int(std::string& out, long long v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

/// Formats items [0, n) in chunks in parallel (format(i, text) appends item i's line) and
/// appends the chunks to out in order.
template <typename Format>
void append_lines(std::string& out, std::size_t n, std::size_t bytes_per_item, Format format) {
  const std::size_t chunks = (n + CHUNK - 1) / CHUNK;
  std::vector<std::string> text(chunks);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    std::string& t = text[c];
    const std::size_t end = std::min(n, (c + 1) * CHUNK);
    t.reserve((end - c * CHUNK) * bytes_per_item);
    for (std::size_t i = c * CHUNK; i < end; ++i) format(i, t);
  });
  for (const std::string& t : text) out += t;
}

}  // namespace

std::array<unsigned char, 3> region_colour(int id) {
  if (id < 0) return {160, 160, 160};
  // Hue = id * golden angle (mod 1), full saturation, value 0.95; HSV -> RGB.
  const double hue = std::fmod(static_cast<double>(id) * 0.6180339887498949, 1.0) * 6.0;
  const double v = 0.95, s = 0.85;
  const int sector = static_cast<int>(hue) % 6;
  const double frac = hue - std::floor(hue);
  const double p = v * (1.0 - s), q = v * (1.0 - s * frac), t = v * (1.0 - s * (1.0 - frac));
  double r = v, g = t, b = p;
  switch (sector) {
    case 0: r = v; g = t; b = p; break;
    case 1: r = q; g = v; b = p; break;
    case 2: r = p; g = v; b = t; break;
    case 3: r = p; g = q; b = v; break;
    case 4: r = t; g = p; b = v; break;
    default: r = v; g = p; b = q; break;
  }
  const auto byte = [](double c) { return static_cast<unsigned char>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); };
  return {byte(r), byte(g), byte(b)};
}

void write_region_ply(const std::string& path, const Mesh& mesh, const Positions& x) {
  const std::vector<int> region_of_face = stored_regions(mesh);
  const auto [H, has_H] = mesh.property_map<VertexIndex, double>(property::MEAN_CURVATURE);
  const auto [K, has_K] = mesh.property_map<VertexIndex, double>(property::GAUSSIAN_CURVATURE);
  // A mesh welded along its seams is written with the input's vertices and faces, as -o writes
  // it (mesh_for_output): the file lines up with the input vertex for vertex, so its UVs and
  // other per-vertex data still apply. Each copy gets its welded vertex's curvature.
  const bool welded = has_welded_seams(mesh);
  const std::size_t rows = static_cast<std::size_t>(x.rows());
  if (rows != mesh.number_of_vertices() && !(welded && rows == input_vertex_count(mesh)))
    throw UsageError("write_region_ply: " + std::to_string(x.rows()) + " positions for " +
                     std::to_string(mesh.number_of_vertices()) + " vertices");
  // As write_mesh_atomic refuses them: "nan" in a PLY is a file no reader, ours included, takes
  // back.
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    if (!x.row(i).allFinite())
      throw std::invalid_argument("write_region_ply: vertex " + std::to_string(i) +
                                  " has a coordinate that is not finite; nothing written to '" +
                                  path + "'");
  // mesh_for_output's refusal, in its words (vertices and faces are numbered by their indices).
  if (mesh.has_garbage())
    throw std::invalid_argument("mesh_for_output: the mesh has removed elements; call collect_garbage() first");
  const Positions expanded = welded ? input_positions(mesh, x) : Positions();
  const Positions& xs = welded ? expanded : x;
  const std::vector<std::size_t> vertex_of = input_vertex_map(mesh);  // the identity if not welded
  const std::vector<std::array<std::size_t, 3>> corners =
      welded ? input_faces(mesh) : std::vector<std::array<std::size_t, 3>>();
  const bool curvature = has_H && has_K;
  const std::size_t nv = static_cast<std::size_t>(xs.rows()), nf = mesh.number_of_faces();
  std::string text =
      "ply\nformat ascii 1.0\ncomment Generated by the CGAL library\n"
      "comment shellcontract regions: face colour = region, grey = none\n"
      "element vertex " + std::to_string(nv) + "\nproperty double x\nproperty double y\nproperty double z\n";
  if (curvature) text += "property double mean_curvature\nproperty double gaussian_curvature\n";
  text += "element face " + std::to_string(nf) +
          "\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
          "property uchar alpha\nproperty int region\nend_header\n";
  append_lines(text, nv, curvature ? 120 : 72, [&](std::size_t i, std::string& t) {
    const auto r = static_cast<Eigen::Index>(i);
    for (int k = 0; k < 3; ++k) {
      if (k) t += ' ';
      put_double(t, xs(r, k));
    }
    t += ' ';
    if (curvature) {
      const VertexIndex v(static_cast<Mesh::size_type>(vertex_of[i]));
      put_double(t, H[v]);
      t += ' ';
      put_double(t, K[v]);
      t += ' ';
    }
    t += '\n';
  });
  append_lines(text, nf, 48, [&](std::size_t i, std::string& t) {
    // CGAL lists a face's corners from the target of its halfedge; input_faces lists a welded
    // face's input corners in that order.
    if (welded) {
      t += "3 ";
      for (const std::size_t c : corners[i]) {
        put_int(t, static_cast<long long>(c));
        t += ' ';
      }
    } else {
      const FaceIndex f(static_cast<Mesh::size_type>(i));
      const HalfedgeIndex h0 = mesh.halfedge(f);
      std::size_t degree = 0;
      HalfedgeIndex h = h0;
      do ++degree, h = mesh.next(h);
      while (h != h0);
      put_int(t, static_cast<long long>(degree));
      t += ' ';
      do {
        put_int(t, static_cast<long long>(mesh.target(h).idx()));
        t += ' ';
        h = mesh.next(h);
      } while (h != h0);
    }
    const int id = region_of_face[i];
    for (unsigned char c : region_colour(id)) {
      put_int(t, c);
      t += ' ';
    }
    t += "255 ";
    put_int(t, id);
    t += " \n";
  });
  write_text_atomic(path, text);
}

}  // namespace shellcontract
