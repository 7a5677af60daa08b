// The one rule for an option whose value is a list (bench error's --iterations, --substeps,
// --threads and --orders, bench ccd's --sweep, run's keyframes "0:4, 100:0"): items separated by
// commas, blanks around an item ignored (the documented keyframe example has one after each
// comma), and no empty item: "1,,2" and a trailing "1," were refused in one place and taken in
// another, and "0, 1e-9" the other way round. Each item is then read by its option's own rule (a
// number as parse_decimal, core/decimal_text.hpp).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace shellcontract {

/// `text` without the blanks (space, tab, CR, LF) at its ends.
inline std::string_view trim_blanks(std::string_view text) {
  const auto b = text.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  return text.substr(b, text.find_last_not_of(" \t\r\n") - b + 1);
}

/// The items of a comma-separated list, each without the blanks around it. False, with `why`
/// ("an empty list", "item 3 is empty (two commas, or one at an end)"), when an item is empty.
inline bool split_list(std::string_view text, std::vector<std::string>& items, std::string& why) {
  items.clear();
  if (trim_blanks(text).empty()) {
    why = "an empty list";
    return false;
  }
  for (std::size_t begin = 0;;) {
    const std::size_t comma = text.find(',', begin);
    const std::string_view item =
        trim_blanks(text.substr(begin, comma == std::string_view::npos ? comma : comma - begin));
    if (item.empty()) {
      why = "item " + std::to_string(items.size() + 1) + " is empty (two commas, or one at an end)";
      return false;
    }
    items.emplace_back(item);
    if (comma == std::string_view::npos) return true;
    begin = comma + 1;
  }
}

}  // namespace shellcontract
