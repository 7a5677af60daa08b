// Files are the same bytes whatever global C++ locale the host program set
// (core/classic_locale.hpp). A host that called std::locale::global(std::locale("de_DE.UTF-8"))
// got "13.826" as an OFF file's vertex count, face corners such as "1.000", decimal commas in the
// CSV log (which then had more fields than columns), and the library refused its own files. The
// test builds such a locale itself (a numpunct facet: no system locale needed); the C locale
// (LC_NUMERIC, strtod's) is not changed by it, only the C++ one.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <iterator>
#include <locale>
#include <sstream>
#include <string>
#include <vector>

#include "shellcontract/mesh_io.hpp"
#include "shellcontract/report.hpp"
#include "support/cgal_mesh.hpp"
#include "support/mesh_fixtures.hpp"
#include "support/scratch_dir.hpp"

namespace shellcontract {
namespace {

/// A German-like numpunct: '.' groups thousands, ',' is the decimal point.
class GroupingCommaPunct : public std::numpunct<char> {
 protected:
  char do_decimal_point() const override { return ','; }
  char do_thousands_sep() const override { return '.'; }
  std::string do_grouping() const override { return "\3"; }
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class HostLocale : public test::ScratchDirTest {
 protected:
  HostLocale() : ScratchDirTest("shellcontract_host_locale_") {}

  /// Runs `f` with the host's locale as the global C++ locale; the previous one is restored.
  static void as_host(const std::function<void()>& f) {
    const std::locale before =
        std::locale::global(std::locale(std::locale::classic(), new GroupingCommaPunct));
    try {
      f();
    } catch (...) {
      std::locale::global(before);
      throw;
    }
    std::locale::global(before);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
};

// The locale does what a German one does to a stream made under it, or the tests below could
// not fail.
TEST_F(HostLocale, TheTestLocaleGroupsAndUsesADecimalComma) {
  std::string text;
  as_host([&] {
    std::ostringstream s;
    s << 13826 << ' ' << 0.5;
    text = s.str();
  });
  EXPECT_EQ(text, "13.826 0,5");
}

TEST_F(HostLocale, MeshFilesAreTheClassicBytesAndReadBack) {
  // More than 1000 vertices and faces: counts and face corners reach four digits.
  const Mesh mesh = test::to_surface_mesh(test::icosphere(4));
  const Positions x = positions_from_mesh(mesh);
  ASSERT_GT(mesh.number_of_vertices(), 1000u);
  struct Output {
    std::string ext;
    bool binary;
  };
  const std::vector<Output> outputs{{"off", false}, {"obj", false}, {"stl", false}, {"ply", false}};
  for (const Output& o : outputs) {
    SCOPED_TRACE(o.ext);
    const std::string classic = path("classic." + o.ext), host = path("host." + o.ext);
    const auto write = [&](const std::string& p) {
      if (o.ext == "ply")
        write_ply_atomic(p, mesh_for_output(mesh, x), "", o.binary);
      else
        write_mesh_atomic(p, mesh, x, o.binary);
    };
    write(classic);
    as_host([&] { write(host); });
    const std::string expected = slurp(classic);
    ASSERT_NE(expected.find('.'), std::string::npos) << "a decimal point to lose";
    EXPECT_TRUE(slurp(host) == expected) << "the file differs from the classic locale's";
    // Read back under the host's locale too (the ASCII STL goes through a stream).
    as_host([&] {
      const Mesh back = read_input_mesh(host);
      EXPECT_EQ(back.number_of_vertices(), mesh.number_of_vertices());
      EXPECT_EQ(back.number_of_faces(), mesh.number_of_faces());
    });
  }
}

TEST_F(HostLocale, LogLineIsTheClassicText) {
  LogRow row{};
  for (std::size_t c = 0; c < row.size(); ++c) row[c] = 1234.5 + static_cast<double>(c);
  row[0] = 12345;
  const std::string classic = log_csv_line(row);
  ASSERT_EQ(classic.substr(0, 13), "12345,1235.5,");
  std::string host;
  as_host([&] { host = log_csv_line(row); });
  EXPECT_EQ(host, classic);
}

// write_file_atomic's stream, which callers (the glTF writers) print numbers into.
TEST_F(HostLocale, WriteFileAtomicStreamIsClassic) {
  as_host([&] {
    write_file_atomic(path("n.txt"), [](std::ostream& out) { out << 13826 << ' ' << 0.5; });
  });
  EXPECT_EQ(slurp(path("n.txt")), "13826 0.5");
}

}  // namespace
}  // namespace shellcontract
