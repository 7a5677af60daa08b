// Colours of a per-vertex scalar field for the glTF (the fields PLY's blue - white - red map).
#pragma once

#include <Eigen/Core>

namespace shellcontract {

/// Linear-RGB float colours of a field and the value range they span.
struct FieldColours {
  double low = 0.0;   ///< 2nd percentile of the values: mapped to blue
  double high = 0.0;  ///< 98th percentile: mapped to red (white half way)
  Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> rgb;  ///< #V by 3, each in [0, 1]
};

/// Maps values from their 2nd to 98th percentile (clamped outside; all white when they are equal)
/// onto blue (0, 0, 1) - white - red (1, 0, 0), the map of the fields PLY (sim/fields.hpp), and
/// converts the sRGB result to linear RGB, the colour space of glTF's COLOR_n attributes.
/// @throws std::invalid_argument if a value is not finite
FieldColours field_colours(const Eigen::VectorXd& values);

}  // namespace shellcontract
