// One rule for quoting a piece of a file in a message (a token, a name): the bytes may be
// anything, and a message must stay one short, printable line whatever the file holds.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace shellcontract {

/// `s` cut to its first `max` bytes (then "..." follows), every byte outside printable ASCII as
/// '?'. The readers quote tokens at 20 bytes; longer texts (an STL's solid name, a material's
/// name) pass their own `max`.
inline std::string shorten(std::string_view s, std::size_t max = 20) {
  std::string r = s.size() > max ? std::string(s.substr(0, max)) + "..." : std::string(s);
  for (char& c : r)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
  return r;
}

}  // namespace shellcontract
