// A face-list file's region strengths ("0.5: 0 1 2") read the same whatever C locale the host
// program set: std::strtod, which read them, stopped at the '.' under a decimal-comma
// LC_NUMERIC, so every strength with a decimal was refused ("strength '0.5' is not a number in
// [0, 1]"), the file the Python module writes for region_strengths= included. Checked to fail on
// the code before parse_c_number.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/regions.hpp"
#include "support/comma_locale.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

class RegionFileCommaLocaleTest : public test::ScratchDirTest {
 protected:
  RegionFileCommaLocaleTest() : ScratchDirTest("region_file_comma_") {}
};

TEST_F(RegionFileCommaLocaleTest, StrengthsKeepTheirDecimals) {
  const std::string path = write("faces.txt", "0.5: 0 1 2 3\n0.25 : 4 5\n1e-1:6\n7\n");
  SET_COMMA_LOCALE_OR_SKIP();
  const RegionFile f = read_region_file_with_strengths(path, 8);
  ASSERT_EQ(f.regions.size(), 4u);
  EXPECT_EQ(f.strength, (std::vector<double>{0.5, 0.25, 0.1, 1.0}));
  EXPECT_EQ(f.regions[0], (std::vector<int>{0, 1, 2, 3}));
}

TEST_F(RegionFileCommaLocaleTest, ADecimalCommaIsRefusedAsInTheCLocale) {
  const std::string path = write("comma.txt", "0,5: 0 1 2 3\n");
  SET_COMMA_LOCALE_OR_SKIP();
  EXPECT_THROW(read_region_file_with_strengths(path, 8), InputError);
}

}  // namespace
}  // namespace shellcontract
