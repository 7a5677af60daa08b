// The PLY scalar types' facts (ply_header.hpp), apart from the reader that parses them: the PLY
// document (ply_document.cpp) sizes and writes values by them too.
#include "mesh/ply_header.hpp"

namespace shellcontract::ply {

int size_of(Type t) {
  switch (t) {
    case Type::Int8:
    case Type::UInt8:
      return 1;
    case Type::Int16:
    case Type::UInt16:
      return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32:
      return 4;
    case Type::Float64:
      return 8;
  }
  return 8;
}

bool is_integer(Type t) { return t != Type::Float32 && t != Type::Float64; }

bool is_signed(Type t) { return t != Type::UInt8 && t != Type::UInt16 && t != Type::UInt32; }

double colour_value(Type t, double value) {
  switch (t) {
    case Type::UInt8:
      return value / 255.0;
    case Type::Int8:
      return value / 127.0;
    case Type::UInt16:
      return value / 65535.0;
    case Type::Int16:
      return value / 32767.0;
    case Type::UInt32:
      return value / 4294967295.0;
    case Type::Int32:
      return value / 2147483647.0;
    default:
      return value;
  }
}

}  // namespace shellcontract::ply
