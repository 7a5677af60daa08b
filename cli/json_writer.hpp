// Minimal JSON text builder for the run summary (flat objects, numbers, strings, arrays).
#pragma once

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace shellcontract::cli {

/// Escapes a string for a JSON string literal (quotes, backslash, control characters).
inline std::string json_quote(const std::string& s) {
  std::ostringstream o;
  o << '"';
  for (unsigned char c : s) {
    switch (c) {
      case '"': o << "\\\""; break;
      case '\\': o << "\\\\"; break;
      case '\n': o << "\\n"; break;
      case '\t': o << "\\t"; break;
      default:
        if (c < 0x20) o << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(c) << std::dec;
        else o << c;
    }
  }
  o << '"';
  return o.str();
}

/// A JSON number; non-finite values become null (JSON has no NaN).
inline std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream o;
  o << std::setprecision(17) << v;
  return o.str();
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
