// The library's own way from an observer's FrameView to the Simulator behind it: for the exporters
// that need more than the view shows (the per-vertex fields, the rest mesh's curvature). Not
// installed, so that a caller outside the library sees the view alone.
#pragma once

#include "shellcontract/observer.hpp"

namespace shellcontract {

class Simulator;

/// The Simulator `view` shows; valid as long as the view is.
const Simulator& simulator_of(const FrameView& view);

}  // namespace shellcontract
