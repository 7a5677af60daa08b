#include "geometry/region_stage_hook.hpp"

#include <atomic>

namespace shellcontract::detail {
namespace {
std::atomic<RegionStageHook> hook{nullptr};
}  // namespace

void set_region_stage_hook(RegionStageHook h) { hook.store(h); }

RegionStageHook region_stage_hook() { return hook.load(); }

}  // namespace shellcontract::detail
