// The one rule for an option whose value is a list (bench error's --iterations, --substeps,
// --threads and --orders, bench ccd's --sweep, run's keyframes "0:4, 100:0"): items separated by
// commas, blanks around an item ignored (the documented keyframe example has one after each
// comma), and no empty item: "1,,2" and a trailing "1," were refused in one place and taken in
// another, and "0, 1e-9" the other way round. Each item is then read by its option's own rule (a
// number as parse_decimal, core/decimal_text.hpp).
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace shellcontract {

/// `text` without the blanks (space, tab, CR, LF) at its ends.
inline std::string_view trim_blanks(std::string_view text) {
  const auto b = text.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  return text.substr(b, text.find_last_not_of(" \t\r\n") - b + 1);
}

/// Every item of a comma-separated list, each without the blanks around it, the empty ones
/// included ("" gives one empty item): for a reader that names an item's problems in the list's
/// order (run's keyframes: an empty key is refused where it comes, after the keys before it).
inline std::vector<std::string> list_items(std::string_view text) {
  std::vector<std::string> items;
  for (std::size_t begin = 0;;) {
    const std::size_t comma = text.find(',', begin);
    items.emplace_back(
        trim_blanks(text.substr(begin, comma == std::string_view::npos ? comma : comma - begin)));
    if (comma == std::string_view::npos) return items;
    begin = comma + 1;
  }
}

/// The items of a comma-separated list, each without the blanks around it. False, with `why`
/// ("an empty list", "item 3 is empty (two commas, or one at an end)"), when an item is empty.
inline bool split_list(std::string_view text, std::vector<std::string>& items, std::string& why) {
  items.clear();
  if (trim_blanks(text).empty()) {
    why = "an empty list";
    return false;
  }
  for (std::string& item : list_items(text)) {
    if (item.empty()) {
      why = "item " + std::to_string(items.size() + 1) + " is empty (two commas, or one at an end)";
      return false;
    }
    items.push_back(std::move(item));
  }
  return true;
}

}  // namespace shellcontract
