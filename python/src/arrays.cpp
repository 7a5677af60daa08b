// numpy arrays <-> Mesh and Positions. Input arrays of the right dtype and layout are read in
// place (the soup view points into numpy's buffer); only other dtypes or strided arrays are
// converted first, by numpy.
#include "arrays.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "contract.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/face_error.hpp"
#include "shellcontract/mesh_io.hpp"

namespace shellcontract::python {
namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

void require_n_by_3(const py::array& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(std::string(what) + " must be an N by 3 array, got shape " + shape_text(a));
}

/// Whether `value` is a numpy masked array with a masked element: its `mask` (numpy.ma.nomask,
/// False, when none is) has a true entry. Read from the object, not through numpy.ma, which
/// cannot be imported while the interpreter finalizes (a call from a __del__ then).
bool has_masked_element(const py::handle& value) {
  if (!py::hasattr(value, "mask") || !py::hasattr(value, "filled") ||
      !py::isinstance<py::array>(value))
    return false;
  const auto mask = py::array_t<bool, py::array::forcecast>::ensure(value.attr("mask"));
  if (!mask) return false;
  const auto flat = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(mask);
  return flat && std::any_of(flat.data(), flat.data() + flat.size(), [](bool b) { return b; });
}

/// `value` as a numpy array, by numpy's conversion, whose own error reaches the caller when it is
/// memory (MemoryError) and is named in a TypeError otherwise (an object whose __array__ raises:
/// its reason, not only "an array-like"). py::array::ensure cleared the error and returned null,
/// which a conversion out of memory then dereferenced. A masked array with a masked element is
/// refused: numpy hands on the values under its mask.
py::array numpy_array(const py::handle& value, const char* what, const char* expected) {
  if (has_masked_element(value))
    throw py::value_error(
        std::string(what) +
        ": a masked array with masked elements; numpy would pass on the "
        "values under the mask: fill them (a.filled(...)) or leave them out first");
  try {
    return py::array(py::reinterpret_borrow<py::object>(value));
  } catch (py::error_already_set& e) {
    // Memory, and what is no Exception (KeyboardInterrupt, SystemExit), go on as raised.
    if (e.matches(PyExc_MemoryError) || !e.matches(PyExc_Exception)) throw;
    throw py::type_error(std::string(what) + " must be " + expected + " (" +
                         std::string(py::str(e.type().attr("__name__"))) + ": " +
                         std::string(py::str(e.value())) + ")");
  }
}

/// float64, C-contiguous: the caller's own buffer when it already is one. A conversion numpy
/// cannot allocate raises its MemoryError (the converting constructor throws it; ensure() gave
/// null).
py::array_t<double, py::array::c_style> vertex_array(const py::handle& vertices) {
  const py::array any = numpy_array(vertices, "vertices", "an array-like of numbers");
  const char kind = any.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error("vertices must hold real numbers, got dtype " + std::string(py::str(any.dtype())));
  require_n_by_3(any, "vertices");
  return py::array_t<double, py::array::c_style | py::array::forcecast>(any);
}

/// int32 or int64 kept as they are when C-contiguous; any other integer type becomes int64.
py::array face_array(const py::handle& faces) {
  py::array any = numpy_array(faces, "faces", "an array-like of integers");
  const char kind = any.dtype().kind();
  if (kind != 'i' && kind != 'u')  // a float index array is a mistake, not something to round
    throw py::type_error("faces must hold integers, got dtype " + std::string(py::str(any.dtype())));
  require_n_by_3(any, "faces");
  const bool c_contiguous = (any.flags() & py::array::c_style) != 0;
  if (!(c_contiguous && (any.dtype().is(py::dtype::of<std::int32_t>()) ||
                         any.dtype().is(py::dtype::of<std::int64_t>()))))
    any = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>(any);
  return any;
}

}  // namespace

/// uint64 indices beyond int64 would wrap to negative ones when converted: such an index is
/// reported as given, with the message the library gives any index out of range.
static void check_uint64_indices(const py::handle& faces, std::size_t num_vertices) {
  const py::array any = numpy_array(faces, "faces", "an array-like of integers");
  if (any.dtype().kind() != 'u' || any.itemsize() < 8) return;
  require_n_by_3(any, "faces");  // the shape first: an index is named by its face
  const auto u = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>(any);
  const std::uint64_t* p = u.data();
  for (py::ssize_t i = 0; i < u.size(); ++i)
    if (p[i] >= num_vertices)
      throw FaceListError(
          std::string(ARRAY_INPUT_NAME) + ": vertex index out of range: face " +
              std::to_string(i / 3) + " refers to vertex " + std::to_string(p[i]) +
              ", but the mesh has " + std::to_string(num_vertices) +
              (num_vertices == 1 ? " vertex" : " vertices") +
              (num_vertices > 0 ? " (0.." + std::to_string(num_vertices - 1) + ")" : ""),
          {static_cast<std::size_t>(i / 3)});
}

Mesh mesh_from_numpy(const py::handle& vertices, const py::handle& faces, InputReport* report, bool reorient) {
  const auto v = vertex_array(vertices);
  check_uint64_indices(faces, static_cast<std::size_t>(v.shape(0)));
  const py::array f = face_array(faces);
  TriangleSoupView soup;
  soup.vertices = v.data();
  soup.num_vertices = static_cast<std::size_t>(v.shape(0));
  soup.num_faces = static_cast<std::size_t>(f.shape(0));
  if (f.dtype().is(py::dtype::of<std::int32_t>()))
    soup.faces32 = static_cast<const std::int32_t*>(f.data());
  else
    soup.faces64 = static_cast<const std::int64_t*>(f.data());
  // The library's check of the soup is long on a large mesh: other Python threads (a user
  // interface's, Blender's) go on meanwhile, as during read_mesh. `v` and `f` keep the arrays
  // alive; the GIL is taken again before they are let go, and before an exception of the check
  // reaches pybind11; the interpreter's exit waits for the check.
  Mesh mesh;
  without_gil([&] { mesh = mesh_from_arrays(soup, ARRAY_INPUT_NAME, report, reorient); });
  return mesh;
}

py::array_t<double> positions_to_numpy(const Positions& x) {
  py::array_t<double> out({static_cast<py::ssize_t>(x.rows()), py::ssize_t{3}});
  // Positions is row-major N by 3, the same layout as the new C-contiguous array.
  std::copy(x.data(), x.data() + x.size(), out.mutable_data());
  return out;
}

py::array_t<std::int64_t> faces_to_numpy(const Mesh& mesh) {
  py::array_t<std::int64_t> out({static_cast<py::ssize_t>(mesh.number_of_faces()), py::ssize_t{3}});
  std::int64_t* p = out.mutable_data();
  // Corners from the face's halfedge, as write_mesh_atomic lists them, by the input's vertices
  // (a mesh welded along its seams gives its copies back).
  for (const auto& corners : input_faces(mesh))
    for (const std::size_t v : corners) *p++ = static_cast<std::int64_t>(v);
  return out;
}

Positions positions_from_numpy(const py::handle& vertices) {
  const auto v = vertex_array(vertices);
  Positions x(v.shape(0), 3);
  std::copy(v.data(), v.data() + v.size(), x.data());
  return x;
}

std::string file_name_bytes(const py::handle& text) {
  return std::string(py::module_::import("os").attr("fsencode")(text).cast<py::bytes>());
}

py::str file_name_text(const std::string& bytes) {
  PyObject* s =
      PyUnicode_DecodeFSDefaultAndSize(bytes.data(), static_cast<Py_ssize_t>(bytes.size()));
  if (s == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(s);
}

py::str message_text(const std::string& message) {
  PyObject* s = PyUnicode_DecodeUTF8(message.data(), static_cast<Py_ssize_t>(message.size()),
                                     "backslashreplace");
  if (s == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::str>(s);
}

std::string path_argument(const py::handle& path, const std::string& what) {
  if (!py::isinstance<py::str>(path) && !py::isinstance<py::bytes>(path) &&
      !PyObject_HasAttrString(path.ptr(), "__fspath__"))
    throw py::type_error(what + " must be a str or an os.PathLike, got " +
                         std::string(py::str(path.get_type().attr("__name__"))));
  // Not a cast of os.fspath's str to std::string: that encodes strict UTF-8, and a surrogate
  // escape (a non-UTF-8 byte of the name) failed with pybind11's "Unable to cast".
  const std::string s = file_name_bytes(path);
  if (s.find('\0') != std::string::npos) throw py::value_error(what + " must not hold a NUL byte");
  // As the CLI: an empty name is not "none" (None is), so that an unset variable is not silent.
  if (s.empty()) throw py::value_error(what + " must not be empty");
  return s;
}

}  // namespace shellcontract::python
