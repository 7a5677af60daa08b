// Streams that write and read numbers in the classic "C" form, whatever locale the host program
// set. A stream takes the global C++ locale when it is made: a host that called
// std::locale::global(std::locale("")) in a German environment gave every stream the library made
// after that a thousands separator and a decimal comma, so an OFF header said "13.826" vertices,
// faces listed vertex "1.000", the CSV log wrote "0,97" between its commas, and the library then
// refused its own files. Every stream the library makes is one of these (or imbued with the
// classic locale where it is made), so files and messages are the same bytes in every host.
#pragma once

#include <locale>
#include <sstream>
#include <string>
#include <utility>

namespace shellcontract {

/// A std::ostringstream in the classic locale.
class ClassicOStringStream : public std::ostringstream {
 public:
  ClassicOStringStream() { imbue(std::locale::classic()); }
};

/// A std::istringstream of `text` in the classic locale.
class ClassicIStringStream : public std::istringstream {
 public:
  explicit ClassicIStringStream(std::string text) : std::istringstream(std::move(text)) {
    imbue(std::locale::classic());
  }
};

}  // namespace shellcontract
