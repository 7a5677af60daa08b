// FrameView: an observer's read-only window on the Simulator (shellcontract/observer.hpp), so
// that the Simulator's members are not part of the public surface.
#include "shellcontract/observer.hpp"
#include "sim/frame_access.hpp"
#include "sim/simulator.hpp"

namespace shellcontract {

int FrameView::frame() const { return sim_->frame(); }
bool FrameView::last() const { return sim_->finished(); }
double FrameView::volume_ratio() const { return sim_->volume_ratio(); }
Positions FrameView::positions() const { return sim_->positions_in_input_units(); }
const Positions& FrameView::normalized_positions() const { return sim_->positions(); }
std::size_t FrameView::regions() const { return sim_->region_count(); }

const Simulator& simulator_of(const FrameView& view) { return *view.sim_; }

}  // namespace shellcontract
