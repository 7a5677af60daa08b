// The warnings of an OBJ's mtllib lines rewritten for a copy in another folder
// (obj_material_paths.hpp): a name that is no library says why, naming the path looked at.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "mesh/obj_material_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

/// A fresh folder of the test's own under the temporary folder, removed at the end.
struct Folder {
  fs::path path;
  explicit Folder(const std::string& name)
      : path(fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path);
    fs::create_directories(path / "in");
    fs::create_directories(path / "out");
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

std::string joined(const std::vector<std::string>& ws) {
  std::string s;
  for (const std::string& w : ws) s += w + "\n";
  return s;
}

/// The names mtllib_names finds on the line "mtllib <names>" when `probe` says which paths are
/// files, with the number of paths it asked about.
std::vector<MtllibName> names_of(const std::string& names,
                                 const std::function<bool(const fs::path&)>& is_file,
                                 std::size_t& probes) {
  const std::string bytes = "mtllib " + names + "\n";
  const MtllibLine line = mtllib_line(bytes, 6, bytes.size() - 1, 1);
  probes = 0;
  return mtllib_names(bytes, line, "in", [&](const fs::path& p) {
    ++probes;
    return is_file(p);
  });
}

// Before: every token was joined with every later one, (n^2)/2 lookups on paths as long as the
// line, so a small file of one long mtllib line held `run` (its output check) for minutes.
TEST(ObjMaterialPaths, ALineOfManyNamesCostsABoundedNumberOfLookupsPerName) {
  std::string line = "x";
  for (int i = 1; i < 4000; ++i) line += " x";
  std::size_t probes = 0;
  const auto names = names_of(
      line, [](const fs::path&) { return false; }, probes);
  ASSERT_EQ(names.size(), 4000u);
  for (const MtllibName& n : names) EXPECT_TRUE(n.name == "x" && !n.found);
  EXPECT_LE(probes, 4000u * kMaxMtllibNameTokens);  // was 4000 * 4001 / 2

  // Names as long as a path can be: no run beyond one is looked up.
  const std::string longest(kMaxMtllibNameBytes - 1, 'y');
  const auto two = names_of(
      longest + " " + longest, [](const fs::path&) { return false; }, probes);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(probes, 2u);
}

// A name with spaces is still found whole, up to kMaxMtllibNameTokens tokens.
TEST(ObjMaterialPaths, ANameOfManySpacesIsFoundUpToTheBound) {
  for (const std::size_t tokens :
       {std::size_t{2}, kMaxMtllibNameTokens, kMaxMtllibNameTokens + 1}) {
    std::string name = "a";
    for (std::size_t i = 1; i < tokens; ++i) name += " a";
    const fs::path file = fs::path("in") / (name + ".mtl");
    std::size_t probes = 0;
    const auto names = names_of(
        "b.mtl " + name + ".mtl c.mtl", [&](const fs::path& p) { return p == file; }, probes);
    if (tokens <= kMaxMtllibNameTokens) {
      ASSERT_EQ(names.size(), 3u) << tokens;
      EXPECT_EQ(names[1].name, name + ".mtl");
      EXPECT_TRUE(names[1].found && !names[0].found && !names[2].found);
    } else {
      EXPECT_EQ(names.size(), tokens + 2) << tokens;  // each token a name of its own, not found
      for (const MtllibName& n : names) EXPECT_FALSE(n.found);
    }
  }
}

// Before: a folder named as the library (mkdir sphere.mtl) was reported as "not found".
TEST(ObjMaterialPaths, AFolderAsTheLibraryIsNamedAsAFolderNotAsMissing) {
  const Folder f("shellcontract_mtllib_folder");
  fs::create_directory(f.path / "in" / "sphere.mtl");
  const std::string in = (f.path / "in" / "a.obj").string(),
                    out = (f.path / "out" / "a.obj").string();
  const std::string bytes = "v 0 0 0\nmtllib sphere.mtl\n";
  std::vector<std::string> w;
  EXPECT_EQ(relocate_material_libraries(bytes, in, out, &w), bytes);  // written unchanged
  ASSERT_EQ(w.size(), 1u) << joined(w);
  EXPECT_NE(w[0].find(in + ": line 2: material library 'sphere.mtl' is not a regular file ('" +
                      (f.path / "in" / "sphere.mtl").string() + "' is a folder)"),
            std::string::npos)
      << w[0];
  EXPECT_EQ(w[0].find("not found"), std::string::npos) << w[0];

  // A name that is nothing at all is still "not found".
  fs::remove(f.path / "in" / "sphere.mtl");
  w.clear();
  relocate_material_libraries(bytes, in, out, &w);
  ASSERT_EQ(w.size(), 1u) << joined(w);
  EXPECT_NE(w[0].find("material library 'sphere.mtl' not found (no file '"), std::string::npos)
      << w[0];
}

}  // namespace
}  // namespace shellcontract
