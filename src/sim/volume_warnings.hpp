// Warnings on the volume: before a run, one that nothing drives or whose stop ratio its
// direction cannot reach (plan_run); at its end, a shell that grew under an outside pressure, a
// volume that swings from frame to frame, and a shell the collision fail-safe froze
// (run_contraction).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// V/V0 above which a shell compressed by an outside pressure has grown, not rebounded: a damped
/// shell released from rest under a compressive load comes back at most to its rest volume, so a
/// percent above it is neither a rebound nor rounding.
inline constexpr double GROWTH_WARNING_RATIO = 1.01;

/// The factor by which V/V0 changes between consecutive frames in a swing: a rise and a fall of
/// more than it, both in the second half of the run. A shell that contracts or settles does not
/// halve and double its volume from one frame to the next once the run is under way.
inline constexpr double SWING_FACTOR = 2.0;

/// The warnings before a run with options `s` (options named as `field`, spell_options) when
/// - nothing drives it: no pressure (`pressure` 0, every key 0), no target volume, no region
///   that contracts (`regions_act`: regions were found and an inward term or `aniso` acts on
///   them) and no isometric bending (whose flat rest state moves a curved shell): the result is
///   the input, and a stop ratio is never reached;
/// - a stop ratio is asked of a shell that only inflates (`pressure` <= 0 with a key below 0,
///   and nothing else acting): V/V0 grows, so the run uses every frame.
/// Runs that something else might contract are left alone: only these sure cases are said.
std::vector<std::string> drive_warnings(const SimOptions& s, bool regions_act);

/// The share of V/V0 by which a sustained swing rises and falls: a reversal counts where V/V0
/// has moved back from its last peak or trough by at least this share of the larger of the two.
/// A V/V0 that still rises and falls by a tenth of itself late in a run has no end value to
/// speak of, while a shell that settles, or rings down after a collapse, moves by far less.
inline constexpr double SWING_SHARE = 0.1;

/// The reversals (each by SWING_SHARE, see above) in the second half of a run that make a
/// sustained swing: two whole periods after the first rise or fall, which neither a collapse, a
/// single rebound (a pressure key that drops), nor a step to a new key makes.
inline constexpr int SWING_REVERSALS = 4;

/// The reversals of `history` from index `from` on: V/V0 turns back from its last peak (trough)
/// by at least SWING_SHARE of the peak (of the value it rose to), after a first move by as
/// much; a value not above 0 (inside out) starts the count of moves again.
int swing_reversals(const std::vector<double>& history, std::size_t from);

/// The warnings for a run whose V/V0 after each frame is `history` (frame 0, the rest state,
/// first). `compressed`: every step had an outside pressure above 0 and no target volume drove the
/// volume. A swing, in the second half of the frames, is a rise and a fall by more than
/// SWING_FACTOR between two frames, or at least SWING_REVERSALS reversals (swing_reversals); it
/// is named rather than a growth where both apply and it goes below GROWTH_WARNING_RATIO: its
/// last V/V0 is then either side. A swing wholly above it is named with the growth.
/// `scheduled`: keys drive the load (a keyed target volume or pressure), which may move V/V0 up
/// and down on purpose (a breathing shell), so the reversals are not counted; the frame-to-frame
/// factor still is.
std::vector<std::string> volume_warnings(const std::vector<double>& history, bool compressed,
                                         bool scheduled = false);

/// The share of all vertex moves (vertices x steps) the collision fail-safe may revert before a
/// run counts as frozen: nearly every vertex in nearly every step, so that the result is about
/// the input, which the run would otherwise report as a plain "ok".
inline constexpr double FROZEN_SHARE = 0.9;

/// The warning for a run whose fail-safe reverted `reverted` vertex moves over `steps` steps of
/// a mesh of `vertices` vertices, when that is at least FROZEN_SHARE of them (options named as
/// `field`, spell_options); empty otherwise.
std::string frozen_warning(double reverted, std::size_t vertices, int steps);

/// For a run that reached its stop ratio `stop` and ended at `final_ratio`: a free shell ends on
/// it, but where contacts held the shell the step's lift onto it was capped
/// (simulator_volume.cpp) and it can end a whole step's change below, which "reached" alone
/// does not tell. Empty unless final_ratio < stop - target_volume_tolerance(stop).
std::string stop_below_warning(double final_ratio, double stop);

/// A shell pushed through itself (`collisions` off) can end inside out: no face pair then
/// intersects (the validation finds nothing), but the enclosed volume is negative. Empty unless
/// frames > 0 and final_ratio <= 0.
std::string inside_out_warning(double final_ratio, int frames, bool collisions);

}  // namespace shellcontract
