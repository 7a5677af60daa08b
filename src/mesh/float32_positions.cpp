// A result stored as 32-bit floats (float32_positions.hpp).
#include "mesh/float32_positions.hpp"

#include <cmath>
#include <limits>

#include "shellcontract/options.hpp"

namespace shellcontract {

double float32_spacing(double v) {
  const float f = static_cast<float>(std::abs(v));
  return static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())) -
         static_cast<double>(f);
}

bool float32_too_coarse(double spacing, double gap) {
  // Rounding moves each coordinate by at most half the spacing, so the two primitives of a pair
  // towards each other by at most sqrt(3) spacings. A pair that the collision response left at
  // the gap (RESPONSE_FACTOR delta) keeps more than half of it, delta, while the spacing is at
  // most a quarter of the gap: rounding then cannot close what the run kept open. Beyond that a
  // pair in contact can end on the other side of its partner in the file.
  return gap > 0.0 && spacing > gap / 4.0;
}

double stored_float32_spacing(const MeshDocument& doc, const Positions& x) {
  if (const std::optional<double> s = ply_float32_spacing(doc, x)) return *s;
  if (const std::optional<double> s = gltf_float32_spacing(doc, x)) return *s;
  return 0.0;
}

std::string text_keeping_gap(const MeshDocument& doc, const std::string& output_path,
                             const Positions& x, double gap, std::vector<std::string>* warnings) {
  const std::optional<double> spacing = ply_float32_spacing(doc, x);
  if (!spacing || !float32_too_coarse(*spacing, gap)) return doc.text_for(output_path, x, warnings);
  if (warnings)
    warnings->push_back(
        "the result's x, y, z are written as double, not as the input's 32-bit floats: at its "
        "largest coordinate the float32 spacing " +
        shortest_text(*spacing) + " is more than a quarter of the contact gap " +
        shortest_text(gap) +
        " that the run kept between the surfaces (2 delta times the mesh's diagonal), and "
        "rounding to it could make the written result pass through itself");
  return *ply_text_for(doc, output_path, x, true, warnings);
}

std::optional<Positions> stored_positions(const MeshDocument& doc, const Positions& x, double gap) {
  if (const std::optional<double> spacing = ply_float32_spacing(doc, x)) {
    if (*spacing == 0.0 || float32_too_coarse(*spacing, gap)) return std::nullopt;
    return ply_rounded(doc, x);
  }
  return gltf_rounded(doc, x);
}

}  // namespace shellcontract
