// The warnings of an OBJ's mtllib lines rewritten for a copy in another folder
// (obj_material_paths.hpp): a name that is no library says why, naming the path looked at.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
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
