// The ranges of the region finders' thresholds (check_region_options, regions.hpp): one table,
// which the library's check, the `regions` command and Python's regions() all say in the same
// words, each option named with its value; and the one list of the finders' names.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/regions.hpp"

namespace shellcontract {
namespace {

struct RegionRange {
  const char* field;
  double lo, hi;
  bool lo_open;
  const char* text;
};

constexpr double INF = std::numeric_limits<double>::infinity();

// max_compactness > 0: a cap on a sphere measures below 1, so any bound above 0 is a threshold,
// and 0 keeps nothing. The fractions are shares of the surface, the angle at most a sphere's.
constexpr RegionRange RANGES[] = {
    {"fit_tolerance", 0.0, INF, false, "a finite number >= 0"},
    {"max_concave_fraction", 0.0, 1.0, false, "a number in [0, 1]"},
    {"min_cap_angle", 0.0, 180.0, false, "a number of degrees in [0, 180]"},
    {"contrast", 0.0, INF, false, "a finite number >= 0"},
    {"max_compactness", 0.0, INF, true, "a finite number > 0"},
    {"min_area_fraction", 0.0, 1.0, false, "a number in [0, 1]"},
    {"max_area_fraction", 0.0, 1.0, false, "a number in [0, 1]"},
};

/// The one list of the finders' names (regions --method, Python's method=), in the enum's order.
constexpr std::pair<const char*, RegionMethod> METHODS[] = {
    {"caps", RegionMethod::Caps}, {"tips", RegionMethod::Tips}, {"parts", RegionMethod::Parts}};

const RegionRange* find_range(const std::string& field) {
  for (const RegionRange& r : RANGES)
    if (field == r.field) return &r;
  return nullptr;
}

}  // namespace

std::optional<RegionMethod> region_method_named(std::string_view name) {
  for (const auto& [text, method] : METHODS)
    if (name == text) return method;
  return std::nullopt;
}

std::string region_method_names(const std::string& quote) {
  std::string out;
  const std::size_t n = std::size(METHODS);
  for (std::size_t i = 0; i < n; ++i)
    out += (i == 0 ? "" : i + 1 == n ? " or " : ", ") + quote + METHODS[i].first + quote;
  return out;
}

std::string region_option_range(const std::string& field) {
  const RegionRange* r = find_range(field);
  return r ? r->text : "";
}

bool in_region_option_range(const std::string& field, double value) {
  const RegionRange* r = find_range(field);
  return r && std::isfinite(value) && (r->lo_open ? value > r->lo : value >= r->lo) &&
         value <= r->hi;
}

void check_region_options(const RegionOptions& o) {
  const std::pair<const char*, double> values[] = {
      {"fit_tolerance", o.fit_tolerance},        {"max_concave_fraction", o.max_concave_fraction},
      {"min_cap_angle", o.min_cap_angle_deg},    {"contrast", o.min_curvature_contrast},
      {"max_compactness", o.max_compactness},    {"min_area_fraction", o.min_area_fraction},
      {"max_area_fraction", o.max_area_fraction}};
  for (const auto& [field, value] : values)
    if (!in_region_option_range(field, value))
      throw UsageError(std::string("`") + field + "` " + shortest_text(value) + ": must be " +
                       region_option_range(field));
  if (o.min_faces < 1)
    throw UsageError("`min_faces` " + std::to_string(o.min_faces) + ": must be an integer >= 1");
  if (std::none_of(std::begin(METHODS), std::end(METHODS),
                   [&](const auto& m) { return m.second == o.method; }))
    throw UsageError("`method` " + std::to_string(static_cast<int>(o.method)) + ": must be " +
                     region_method_names());
  if (o.max_area_fraction < o.min_area_fraction)
    throw UsageError("`max_area_fraction` " + shortest_text(o.max_area_fraction) +
                     " is below `min_area_fraction` " + shortest_text(o.min_area_fraction) +
                     ": no region could be kept");
}

}  // namespace shellcontract
