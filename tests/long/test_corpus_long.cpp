// Issue 30 item 6: camel.off of CGAL's demo data (scripts/fetch_paper_meshes.sh) runs the default
// 200 frames to the end with no new self-intersection (it blew up at step 9 before the mass floor
// of rest_state.cpp). Label "long" (240 s measured on a shared, loaded 2-core machine).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "shellcontract/mesh/io.hpp"
#include "shellcontract/sim/run.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

TEST(CorpusLong, CamelRunsTheDefault200Frames) {
  const std::string path = std::string(test::PAPER_MESH_DIR) + "/camel.off";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is absent: run scripts/fetch_paper_meshes.sh";
  RunOptions options;
  options.sim.validate = ValidateMode::End;
  ASSERT_EQ(options.sim.frames, 200);
  const RunResult r = run_contraction(read_input_mesh(path), options);
  EXPECT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.frames_run, 200);
  EXPECT_EQ(r.new_intersections, 0);
}

}  // namespace
}  // namespace shellcontract
