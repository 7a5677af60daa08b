// The PLY header as read_ply parses and checks it (private to src/mesh): the format, the elements
// with their properties, and where the body starts. The reader (ply_reader.cpp) and the document
// that writes a PLY file back with new positions (ply_document.cpp) share it, so that both see
// the same header.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace shellcontract::ply {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

int size_of(Type t);  ///< bytes in a binary file
bool is_integer(Type t);
bool is_signed(Type t);  ///< the signed integer types and both floating-point types
/// A colour component on glTF's scale, 0 to 1: an integer type's value divided by the type's
/// largest (uchar 255: 1), a float as the file has it.
double colour_value(Type t, double value);

struct Property {
  std::string name;
  bool list = false;
  Type count_type = Type::UInt8;  ///< lists only
  Type type = Type::Float32;      ///< the value's (or the list items') type
  /// Byte span of the type's name in the header (scalars only): where the PLY document writes
  /// `double` in place of an integer type of x, y, z (ply_document.cpp says why).
  std::size_t type_begin = 0, type_end = 0;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::size_t line = 0;  ///< header line that declares it
  std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// A `comment` line of the header (MeshLab names its texture files there: ply_textures.hpp).
struct Comment {
  std::size_t line = 0;  ///< header line (1-based)
  std::string text;      ///< the rest of the line after the keyword, as written
};

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t body = 0;       ///< byte offset of the body (after the 'end_header' line)
  std::size_t body_line = 0;  ///< its line (ascii)
  std::vector<Comment> comments;  ///< in header order
};

/// The header of a PLY file held in memory, checked as read_ply checks it (a UTF-8 byte-order
/// mark is skipped). The declared counts are not checked against the body, but an element without
/// properties that declares more instances than the file has bytes is refused.
/// @throws InputError "<path>: <problem>: <where>" for a header that is not valid PLY
Header read_ply_header(const std::string& path, const std::string& bytes);

}  // namespace shellcontract::ply
