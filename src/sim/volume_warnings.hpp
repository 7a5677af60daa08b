// Warnings at the end of a run on how its volume went: a shell that grew under an outside
// pressure, and a volume that swings from frame to frame (run_contraction).
#pragma once

#include <string>
#include <vector>

namespace shellcontract {

/// V/V0 above which a shell compressed by an outside pressure has grown, not rebounded: a damped
/// shell released from rest under a compressive load comes back at most to its rest volume, so a
/// percent above it is neither a rebound nor rounding.
inline constexpr double GROWTH_WARNING_RATIO = 1.01;

/// The factor by which V/V0 changes between consecutive frames in a swing: a rise and a fall of
/// more than it, both in the second half of the run. A shell that contracts or settles does not
/// halve and double its volume from one frame to the next once the run is under way.
inline constexpr double SWING_FACTOR = 2.0;

/// The warnings for a run whose V/V0 after each frame is `history` (frame 0, the rest state,
/// first). `compressed`: every step had an outside pressure above 0 and no target volume drove the
/// volume. A swing is named rather than a growth where both apply: its last V/V0 is either side.
std::vector<std::string> volume_warnings(const std::vector<double>& history, bool compressed);

}  // namespace shellcontract
