// The `shellcontract` tool (cli_main, the same code) with lowered size limits: the largest .glb
// (gltf::glb_max_bytes, 4 GiB - 1 in the tool) and the outputs' size that is warned of
// (big_output_bytes, 1 GiB), so that a test meets both with a small mesh
// (tests/export/test_cli_output_sizes.cpp): no test writes 4 GiB.
//   limited_cli GLB_MAX_BYTES BIG_OUTPUT_BYTES COMMAND [options]   as `shellcontract COMMAND ...`
#include <cstdio>
#include <cstdlib>

#include "cli/commands.hpp"
#include "cli/output_sizes.hpp"
#include "export/gltf_size.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: limited_cli GLB_MAX_BYTES BIG_OUTPUT_BYTES COMMAND [options]\n");
    return 1;
  }
  shellcontract::gltf::set_glb_max_bytes_for_test(std::strtoull(argv[1], nullptr, 10));
  shellcontract::cli::set_big_output_bytes_for_test(std::strtoull(argv[2], nullptr, 10));
  argv[2] = argv[0];  // the tool sees `limited_cli COMMAND [options]`
  return shellcontract::cli::cli_main(argc - 2, argv + 2);
}
