// Minimal JSON text builder for the run summary (flat objects, numbers, strings, arrays).
#pragma once

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "core/classic_locale.hpp"
#include "shellcontract/options.hpp"  // shortest_text

namespace shellcontract::cli {

/// Length of the well-formed UTF-8 sequence at s[i] (1 to 4), or 0 if the byte there does not
/// start one (a stray continuation byte, an overlong form, a surrogate, beyond U+10FFFF).
inline std::size_t utf8_sequence_length(const std::string& s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // range of the second byte
  if (c >= 0xC2 && c <= 0xDF) n = 2;
  else if (c >= 0xE0 && c <= 0xEF) n = 3, lo = c == 0xE0 ? 0xA0 : 0x80, hi = c == 0xED ? 0x9F : 0xBF;
  else if (c >= 0xF0 && c <= 0xF4) n = 4, lo = c == 0xF0 ? 0x90 : 0x80, hi = c == 0xF4 ? 0x8F : 0xBF;
  else return 0;
  if (i + n > s.size() || b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k)
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  return n;
}

/// Escapes a string for a JSON string literal (quotes, backslash, control characters). The
/// result is always valid UTF-8: a byte that is not part of a well-formed UTF-8 sequence (a file
/// name in Latin-1, say) becomes the escape of the code point of the same value (U+0000 to U+00FF).
inline std::string json_quote(const std::string& s) {
  ClassicOStringStream o;
  o << '"';
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const std::size_t n = utf8_sequence_length(s, i);
    if (n > 1) {
      o.write(s.data() + i, static_cast<std::streamsize>(n));
      i += n;
      continue;
    }
    ++i;
    switch (c) {
      case '"': o << "\\\""; break;
      case '\\': o << "\\\\"; break;
      case '\n': o << "\\n"; break;
      case '\t': o << "\\t"; break;
      default:
        if (c < 0x20 || n == 0) o << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(c) << std::dec;
        else o << c;
    }
  }
  o << '"';
  return o.str();
}

/// A JSON number in the shortest form that reads back as the same double (shortest_text, as
/// the sweep's results and `run --help` write it); non-finite values become null (JSON has no NaN).
inline std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  return shortest_text(v);
}

/// Builds one JSON object field by field, in insertion order.
class JsonObject {
 public:
  JsonObject& add_raw(const std::string& key, const std::string& raw) {
    fields_.push_back(json_quote(key) + ": " + raw);
    return *this;
  }
  JsonObject& add(const std::string& key, double v) { return add_raw(key, json_number(v)); }
  JsonObject& add(const std::string& key, int v) { return add_raw(key, std::to_string(v)); }
  JsonObject& add(const std::string& key, std::size_t v) { return add_raw(key, std::to_string(v)); }
  JsonObject& add(const std::string& key, bool v) { return add_raw(key, v ? "true" : "false"); }
  JsonObject& add(const std::string& key, const std::string& v) { return add_raw(key, json_quote(v)); }
  JsonObject& add(const std::string& key, const char* v) { return add_raw(key, json_quote(v)); }
  JsonObject& add(const std::string& key, const std::vector<std::string>& v) {
    std::string raw = "[";
    for (std::size_t i = 0; i < v.size(); ++i) raw += (i ? ", " : "") + json_quote(v[i]);
    return add_raw(key, raw + "]");
  }
  JsonObject& add(const std::string& key, const JsonObject& v) { return add_raw(key, v.str(1)); }

  /// The object as text, indented by `depth` levels of two spaces.
  std::string str(int depth = 0) const {
    const std::string pad(2 * (depth + 1), ' ');
    std::string out = "{\n";
    for (std::size_t i = 0; i < fields_.size(); ++i)
      out += pad + fields_[i] + (i + 1 < fields_.size() ? ",\n" : "\n");
    return out + std::string(2 * depth, ' ') + "}";
  }

 private:
  std::vector<std::string> fields_;
};

}  // namespace shellcontract::cli
