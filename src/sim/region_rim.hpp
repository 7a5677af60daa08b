// The rule every region source obeys before a run (run_plan.cpp, mark_run_regions): a region
// sinks from its rim, the edges it shares with faces that stay out (docs/math/region-mirror.md:
// the dimple is the cap mirrored through its rim's plane; without a rim there is no plane and the
// volume projection shrinks the whole enclosed volume, which blew the run up).
#pragma once

#include <string>
#include <vector>

#include "shellcontract/mesh.hpp"

namespace shellcontract {

/// Refuses regions that leave no rim: regions that together cover every face of the mesh, and a
/// region that covers a whole closed component (no edge of it borders a face outside it). A
/// region with a rim is accepted however small the rest is: its rim (at least 3 vertices, not on
/// a line) gives the mirror its plane.
/// @param region_of_face one id per face (>= 0) or -1, as stored_regions returns them.
/// @param source         how the message names where the regions came from (a file's path).
/// @throws InputError "<source>: the regions cover every face ..." or "<source>: region R ...".
void check_regions_have_rims(const Mesh& mesh, const std::vector<int>& region_of_face,
                             const std::string& source);

}  // namespace shellcontract
