// Keyframes for the run options that may follow a schedule (--target-volume, -p): the option
// table's number entry, taught to take "FRAME:VALUE, ..." as well (docs/design/keyframes.md).
// Private to the library (included as "sim/keyed_options.hpp").
#pragma once

#include "shellcontract/options.hpp"

namespace shellcontract {

/// Which schedule of SimOptions an option's keys go to.
enum class KeyedValue { TargetVolume, Pressure };

/// `number_entry` (a number() entry of the option table) that also takes keyframes: text with a
/// ':' is parsed as a schedule (parse_volume_schedule or parse_schedule) into the SimOptions
/// schedule, and the scalar field set to what the schedule stands for (the last key's V/V0, the
/// largest pressure); a plain number clears the schedule and is parsed exactly as before. get()
/// gives the schedule's text when it has keys.
OptionSpec with_keyframes(OptionSpec number_entry, KeyedValue which);

}  // namespace shellcontract
