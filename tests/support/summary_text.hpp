// Reading a run's --summary JSON as text in CLI tests: the whole file, and one option's value.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace shellcontract::test {

/// The file's bytes ("" when it cannot be read).
inline std::string file_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// The value of "key": "..." in the summary's "options" object (the summary writes each option's
/// resolved text as a string); "(missing)" when the key is not there.
inline std::string summary_option(const std::filesystem::path& summary, const std::string& key) {
  const std::string text = file_text(summary);
  const std::size_t options = text.find("\"options\"");
  const std::size_t at = text.find("\"" + key + "\": \"", options);
  if (options == std::string::npos || at == std::string::npos) return "(missing)";
  const std::size_t begin = at + key.size() + 5;
  return text.substr(begin, text.find('"', begin) - begin);
}

}  // namespace shellcontract::test
