// The compiled part of the `shellcontract` Python package (shellcontract._core): contract and
// options (contract.cpp), and the mesh helpers that mirror the CLI's check, regions and the
// library's reader and writer. python/shellcontract/__init__.py wraps them.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "contract.hpp"
#include "shellcontract/core/error.hpp"
#include "shellcontract/geometry/region_selection.hpp"
#include "shellcontract/mesh/eigen_point_map.hpp"
#include "shellcontract/mesh/from_arrays.hpp"
#include "shellcontract/mesh/io.hpp"
#include "shellcontract/validation/self_intersection.hpp"

namespace shellcontract::python {
namespace {

/// What `shellcontract check` reports, for a mesh that passed the input checks.
py::dict check(const py::handle& vertices, const py::handle& faces) {
  InputReport report;
  const Mesh mesh = mesh_from_numpy(vertices, faces, &report);
  const Positions x = positions_from_mesh(mesh);
  std::vector<FacePair> pairs;
  {
    py::gil_scoped_release release;
    pairs = self_intersecting_pairs(mesh, x);
  }
  const auto chi = static_cast<long long>(mesh.number_of_vertices()) - static_cast<long long>(mesh.number_of_edges()) +
                   static_cast<long long>(mesh.number_of_faces());
  py::array_t<std::int64_t> pair_array({static_cast<py::ssize_t>(pairs.size()), py::ssize_t{2}});
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    pair_array.mutable_at(i, 0) = static_cast<std::int64_t>(pairs[i].first.idx());
    pair_array.mutable_at(i, 1) = static_cast<std::int64_t>(pairs[i].second.idx());
  }
  py::dict d;
  d["vertices"] = report.vertices;
  d["faces"] = report.faces;
  d["edges"] = static_cast<std::size_t>(mesh.number_of_edges());
  d["components"] = report.components;
  d["euler_characteristic"] = chi;
  // The checks refuse open, non-manifold and non-orientable input: chi = sum (2 - 2 g_i).
  d["genus"] = (2 * static_cast<long long>(report.components) - chi) / 2;
  d["volume"] = report.volume;
  d["bounding_box_diagonal"] = (x.colwise().maxCoeff() - x.colwise().minCoeff()).norm();
  d["reoriented"] = report.reoriented;
  d["zero_area_faces"] = report.zero_area_faces;
  d["self_intersections"] = pair_array;
  d["warnings"] = report.warnings;
  return d;
}

/// The regions `run --regions auto` would choose: one ascending face-index array per region.
/// The options are the CLI's (`shellcontract regions --help`), with '_' or '-':
/// regions(V, F, max_area_fraction=0.1) or regions(V, F, **{"region-at": [(x, y, z)]}).
py::list regions(const py::handle& vertices, const py::handle& faces, const py::kwargs& kwargs) {
  RegionOptions o;
  std::vector<Vec3> at;
  for (const auto& [key, value] : kwargs) {
    std::string name = key.cast<std::string>();
    std::replace(name.begin(), name.end(), '_', '-');
    if (name == "fit-tolerance") o.fit_tolerance = value.cast<double>();
    else if (name == "max-concave-fraction") o.max_concave_fraction = value.cast<double>();
    else if (name == "min-cap-angle") o.min_cap_angle_deg = value.cast<double>();
    else if (name == "contrast") o.min_curvature_contrast = value.cast<double>();
    else if (name == "max-compactness") o.max_compactness = value.cast<double>();
    else if (name == "min-faces") o.min_faces = value.cast<int>();
    else if (name == "min-area-fraction") o.min_area_fraction = value.cast<double>();
    else if (name == "max-area-fraction") o.max_area_fraction = value.cast<double>();
    else if (name == "region-at") {
      for (const py::handle p : value) {
        const auto xyz = p.cast<std::vector<double>>();
        if (xyz.size() != 3) throw py::value_error("regions(): region_at takes points of three coordinates");
        at.emplace_back(xyz[0], xyz[1], xyz[2]);
      }
    } else
      throw py::type_error("regions() got an unknown option '" + key.cast<std::string>() +
                           "'; valid options (those of `shellcontract regions`, '-' or '_'): fit_tolerance, "
                           "max_concave_fraction, min_cap_angle, contrast, max_compactness, min_faces, "
                           "min_area_fraction, max_area_fraction, region_at");
  }
  const Mesh mesh = mesh_from_numpy(vertices, faces);
  const std::vector<int> ids = at.empty() ? select_spherical_regions(mesh, positions_from_mesh(mesh), o)
                                          : select_regions_at(mesh, positions_from_mesh(mesh), at, o);
  py::list out;
  for (const std::vector<int>& r : regions_from_face_ids(ids)) {
    py::array_t<std::int64_t> a(static_cast<py::ssize_t>(r.size()));
    for (std::size_t i = 0; i < r.size(); ++i) a.mutable_at(i) = r[i];
    out.append(a);
  }
  return out;
}

py::tuple read_mesh(const std::string& path) {
  const Mesh mesh = read_input_mesh(path);
  return py::make_tuple(positions_to_numpy(positions_from_mesh(mesh)), faces_to_numpy(mesh));
}

void write_mesh(const std::string& path, const py::handle& vertices, const py::handle& faces) {
  // The faces are written as given (no reorientation): this writes a result back.
  const Mesh mesh = mesh_from_numpy(vertices, faces, nullptr, /*reorient=*/false);
  write_mesh_atomic(path, mesh, positions_from_numpy(vertices));
}

}  // namespace
}  // namespace shellcontract::python

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  using namespace shellcontract;
  using namespace shellcontract::python;
  m.doc() = "ShellContract's compiled core; use the shellcontract package";
  // The library's errors as Python's: a bad mesh or a bad option value is a ValueError with the
  // library's message (what the CLI prints before exiting with 2 or 1).
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const UsageError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const SimulationError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  m.def("contract", &contract, py::arg("vertices"), py::arg("faces"), py::kw_only(), py::arg("callback") = py::none());
  m.def("option_table", &option_table);
  m.def("check", &check, py::arg("vertices"), py::arg("faces"));
  m.def("regions", &regions, py::arg("vertices"), py::arg("faces"));
  m.def("read_mesh", &read_mesh, py::arg("path"));
  m.def("write_mesh", &write_mesh, py::arg("path"), py::arg("vertices"), py::arg("faces"));
}
