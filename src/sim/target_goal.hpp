// The goal of a run's volume (run_contraction): from which frame a keyed target volume stays at
// the value the run ends on, the stall rule of the run loop, and the texts its messages share.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/simulation_options.hpp"

namespace shellcontract {

/// The first frame from which `keys` keeps, through frame `last` (the run's last frame), the
/// value it has there: where the schedule arrives at the goal the run is judged by. A hold (two
/// equal keys, exactly constant between them) that lasts to `last` counts from its first key; a
/// curve still moving at `last` arrives there only. 0 for an empty schedule.
int schedule_settles_at(const Schedule& keys, int last);

/// Whether V/V0 has stalled at frame `n` of `history` (V/V0 after each frame, frame 0 first): it
/// changed by less than STALL_CHANGE over the STALL_FRAMES frames up to `n` while it is off
/// `goal` (target_volume_reached). False before frame STALL_FRAMES.
bool volume_stalled(const std::vector<double>& history, std::size_t n, double goal);

/// The first frame before `settled` (schedule_settles_at) at which the volume of `history`
/// stalled off the value of `keys` there: a key the shell could not reach, which the run does not
/// stop for because a later key changes the goal. -1 when there is none.
int first_stall_before(const std::vector<double>& history, const Schedule& keys, int settled);

/// The first frame n >= max(from, 1) of `history` at which V/V0 came to `goal`: within its
/// tolerance (target_volume_reached), or on the other side of it than at frame n - 1. A run that
/// misses its goal after that went past it (its momentum, which the volume constraint did not
/// undo in the frames left) rather than falling short of it. -1 when there is none.
int frame_goal_met(const std::vector<double>& history, double goal, int from);

/// A V/V0 in the messages: four decimals, or three digits below 0.01 (four decimals would hide a
/// collapse to 1e-7 as 0.0000).
std::string volume_ratio_text(double r);

/// Where V/V0 stopped moving (volume_stalled): "the volume stalled at V/V0 ... at frame N".
std::string stall_text(double ratio, int frame);

/// How far the run ended from its goal, for the message of a target not reached: a factor where
/// V/V0 is off by more than 2 either way (a collapse far below a small target), otherwise the
/// difference and its share of the goal; for a target volume (`target`), also the tolerance it
/// missed.
std::string miss_text(double ratio, double goal, bool target);

}  // namespace shellcontract
