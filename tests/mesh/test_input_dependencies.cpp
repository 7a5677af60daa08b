// The files an OBJ names (input_dependencies.hpp): a material library named on many mtllib lines,
// or by several spellings, is listed and read once, at its first name (review7 F10: each name
// read and parsed the library again, 1,000 names of a 5 MB library took 31 s before any run).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mesh/input_dependencies.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

TEST(InputDependencies, ALibraryNamedManyTimesIsListedAndReadOnce) {
  const fs::path dir =
      fs::temp_directory_path() / ("shellcontract_deps_once_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "a.mtl") << "newmtl a\nmap_Kd tex.png\nbump b.png\n";
  std::ofstream(dir / "c.mtl") << "newmtl c\nmap_Kd c.png\n";
  std::string obj = "mtllib a.mtl\nmtllib a.mtl ./a.mtl\nmtllib c.mtl a.mtl\n";
  for (int k = 0; k < 20; ++k) obj += "mtllib a.mtl\n";
  obj += "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  const std::string path = (dir / "m.obj").string();
  std::ofstream(path) << obj;

  const std::vector<InputDependency> deps = input_dependencies(path);
  std::vector<std::string> names;
  for (const InputDependency& d : deps) names.push_back(fs::path(d.path).filename().string());
  // Each file once, in the order of first naming: a.mtl and its images, then c.mtl and its own.
  EXPECT_EQ(names, (std::vector<std::string>{"a.mtl", "tex.png", "b.png", "c.mtl", "c.png"}))
      << ::testing::PrintToString(names);
  ASSERT_FALSE(deps.empty());
  EXPECT_NE(deps[0].role.find("line 1)"), std::string::npos) << deps[0].role;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
