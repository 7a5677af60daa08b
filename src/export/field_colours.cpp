#include "export/field_colours.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "sim/fields.hpp"

namespace shellcontract {

namespace {

/// sRGB transfer function inverted (IEC 61966-2-1).
float srgb_to_linear(double c) {
  return static_cast<float>(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
}

}  // namespace

FieldColours field_colours(const Eigen::VectorXd& values) {
  FieldColours out;
  if (!values.allFinite()) throw std::invalid_argument("field_colours: a value is not finite");
  const std::vector<double> v(values.data(), values.data() + values.size());
  out.low = field_percentile(v, 0.02);
  out.high = field_percentile(v, 0.98);
  out.rgb.resize(values.size(), 3);
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    const double t = out.high > out.low
                         ? std::clamp((values(i) - out.low) / (out.high - out.low), 0.0, 1.0)
                         : 0.5;
    // blue -> white over [0, 0.5], white -> red over [0.5, 1] (sRGB)
    const double r = t < 0.5 ? t / 0.5 : 1.0;
    const double g = t < 0.5 ? t / 0.5 : (1.0 - t) / 0.5;
    const double b = t < 0.5 ? 1.0 : (1.0 - t) / 0.5;
    out.rgb.row(i) << srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b);
  }
  return out;
}

}  // namespace shellcontract
