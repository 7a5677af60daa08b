// A test hook of the cap finder (not installed): called on the finder's thread as each of its
// stages ends. tests/tools/staged_cli.cpp prints a line there, so that a test can signal the
// CLI while the regions are selected without sleeping; the shipped tool sets none.
#pragma once

namespace shellcontract::detail {

using RegionStageHook = void (*)(const char* stage);

/// Sets the hook (nullptr: none, the default).
void set_region_stage_hook(RegionStageHook hook);

/// The hook set, or nullptr.
RegionStageHook region_stage_hook();

}  // namespace shellcontract::detail
