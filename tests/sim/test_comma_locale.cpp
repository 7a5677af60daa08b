// A run's files and messages are the same whatever C locale the host program set (the Python
// module runs in the caller's process; PyQt and GTK set LC_NUMERIC from the desktop). Under a
// decimal-comma locale std::strtod refused every weight with a decimal ("'0.5' is not a
// weight"), a checkpoint's log read back as zeros (the Python module's resume=), and snprintf's
// "%.4f" wrote "0,5000" into the message of a target not reached. Checked to fail on the code
// before parse_c_number and fixed_text/general_text.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "shellcontract/report.hpp"
#include "shellcontract/run.hpp"
#include "sim/region_weights.hpp"
#include "sim/volume_warnings.hpp"
#include "support/cgal_mesh.hpp"
#include "support/comma_locale.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

class CommaLocaleSimTest : public test::ScratchDirTest {
 protected:
  CommaLocaleSimTest() : ScratchDirTest("comma_locale_sim_") {}
};

TEST_F(CommaLocaleSimTest, WeightFileKeepsItsDecimals) {
  const std::string path = write("w.txt", "0.5\n0.25\n1e-1\n");
  SET_COMMA_LOCALE_OR_SKIP();
  EXPECT_EQ(read_vertex_weights(path, 3), (std::vector<double>{0.5, 0.25, 0.1}));
  EXPECT_THROW(read_vertex_weights(write("c.txt", "0,5\n0\n0\n"), 3), InputError);
}

TEST_F(CommaLocaleSimTest, LogRowsReadBackToTheSameDoubles) {
  LogRow a{}, b{};
  for (std::size_t c = 0; c < LOG_COLUMN_COUNT; ++c) {
    a[c] = LOG_INTEGER[c] ? static_cast<double>(c + 3) : 0.1 * static_cast<double>(c) + 0.99612048;
    b[c] = LOG_INTEGER[c] ? static_cast<double>(2 * c) : 1.0 / (3.0 + static_cast<double>(c));
  }
  SET_COMMA_LOCALE_OR_SKIP();
  const std::string csv = log_csv_header() + log_csv_line(a) + log_csv_line(b);
  EXPECT_NE(csv.find(",0.25,"), std::string::npos) << csv;  // a point, not the locale's comma
  const std::vector<LogRow> rows = log_csv_rows(csv, "the log");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0], a);
  EXPECT_EQ(rows[1], b);
  // A row that does not read (strtod's reading of it was 0s, silently): refused, naming it.
  std::string damaged = log_csv_header() + log_csv_line(a);
  damaged.replace(damaged.find("1.19612048"), 10, "1,19612048");
  try {
    log_csv_rows(damaged, "the log");
    ADD_FAILURE() << "a damaged row was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the log: line 2: "), std::string::npos) << e.what();
  }
}

TEST_F(CommaLocaleSimTest, ATargetNotReachedIsWordedAsInTheCLocale) {
  // Five frames of a pressure of 1 do not take ico1 to the stop ratio 0.5.
  RunOptions o;
  o.sim.frames = 5;
  o.sim.pressure = 1.0;
  o.sim.stop_volume_ratio = 0.5;
  const Mesh mesh = test::to_surface_mesh(test::icosphere(1));
  const RunResult in_c = run_contraction(mesh, o);
  ASSERT_NE(
      in_c.message.find("stop volume ratio 0.5000 not reached: the frames ran out at V/V0 0."),
      std::string::npos)
      << in_c.message;
  SET_COMMA_LOCALE_OR_SKIP();
  EXPECT_EQ(run_contraction(mesh, o).message, in_c.message);
  // The volume warnings' "%.3g" too: a shell that grew under an outside pressure.
  const std::vector<std::string> grew = volume_warnings({1.0, 1.0, 1.25, 1.5}, true);
  ASSERT_EQ(grew.size(), 1u);
  EXPECT_NE(grew[0].find("V/V0 ended at 1.5, above 1"), std::string::npos) << grew[0];
}

}  // namespace
}  // namespace shellcontract
