// `regions --region-at X,Y,Z --max-area-fraction F --face-list FILE`: the region stays within F
// and its table row describes the faces written to FILE, recomputed here from the file and the
// mesh (support/region_measures.hpp). Before, bumpy_sphere's top bump at F = 0.05 printed 7.00 %,
// and at the default F the row printed residual 0.000 and angle 83 for faces that give 0.010
// and 80 (the grown disc's fit and geodesic angle, not the region's).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/eigen_point_map.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"
#include "support/region_measures.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::run_cli;

/// The cells of the table row of region 0 ("   0  +x, +y, +z  radius  area%  faces  compact.
/// residual  angle"), commas dropped.
std::vector<std::string> row_zero(const std::string& output) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("   0  ", 0) == 0) {
      std::vector<std::string> cells;
      std::istringstream words(line);
      for (std::string w; words >> w;) {
        if (!w.empty() && w.back() == ',') w.pop_back();
        cells.push_back(w);
      }
      return cells;
    }
  return {};
}

TEST(CliRegionAtTable, TheRowDescribesTheFacesWrittenWithinTheBound) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " not built";
  const fs::path dir = fs::temp_directory_path() / "shellcontract_cli_region_at_table";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string input = std::string(test::MESH_DIR) + "/bumpy_sphere.off",
                    list = (dir / "f.txt").string();
  const Mesh mesh = read_input_mesh(input);
  const Positions x = positions_from_mesh(mesh);
  Faces faces(static_cast<Eigen::Index>(mesh.number_of_faces()), 3);
  for (FaceIndex f : mesh.faces()) {
    int k = 0;
    for (VertexIndex v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
      faces(static_cast<Eigen::Index>(f.idx()), k++) = static_cast<int>(v.idx());
  }
  for (const char* fraction : {"0.05", "0.08", "0.1", "0.25"}) {
    const auto r = run_cli({"regions", input, "--region-at=0,0,1", "--max-area-fraction", fraction,
                            "--face-list", list});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::ifstream in(list);
    std::vector<int> region;
    for (int f; in >> f;) region.push_back(f);
    ASSERT_FALSE(region.empty()) << fraction;
    const std::vector<std::string> cells = row_zero(r.output);
    ASSERT_EQ(cells.size(), 10u) << r.output;
    const test::MeasuredRegion want = test::measure_region(x, faces, region);
    const double radius = std::stod(cells[4]);
    EXPECT_LE(want.area / want.total_area, std::stod(fraction)) << r.output;
    EXPECT_NEAR(std::stod(cells[5]), 100.0 * want.area / want.total_area, 0.005 + 1e-9) << r.output;
    EXPECT_EQ(std::stoul(cells[6]), region.size()) << r.output;
    for (int a = 0; a < 3; ++a)  // 4 significant digits, or a coordinate near 0 next to the radius
      EXPECT_NEAR(std::stod(cells[static_cast<std::size_t>(1 + a)]), want.centre(a),
                  5e-4 * std::abs(want.centre(a)) + 1e-9 * want.radius)
          << r.output;
    EXPECT_NEAR(radius, want.radius, 5e-5 + 1e-9) << r.output;
    EXPECT_NEAR(std::stod(cells[8]), want.residual, 5e-4 + 1e-9)
        << "residual, F = " << fraction << "\n"
        << r.output;
    EXPECT_NEAR(std::stod(cells[9]), want.angle_deg, 0.5 + 1e-6)
        << "angle, F = " << fraction << "\n"
        << r.output;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
