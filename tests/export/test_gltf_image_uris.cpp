// A .gltf result in another folder than its input names the same image files (docs/design/
// attributes.md, "glTF inputs"), as an OBJ's mtllib and a PLY's TextureFile paths do. Before,
// each relative image uri was written as read: from the result's folder it named nothing, and
// the result lost its textures without a word (exit 0).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "export_fixtures.hpp"
#include "support/cli_runner.hpp"
#include "support/gltf_files.hpp"
#include "support/textured_octahedron.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::ScratchDir;

std::string write(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

nlohmann::json images_of(const std::string& gltf) {
  std::ifstream in(gltf, std::ios::binary);
  const nlohmann::json j =
      nlohmann::json::parse(std::string(std::istreambuf_iterator<char>(in), {}));
  return j.at("images");
}

const std::string DATA_URI = "data:image/png;base64,iVBORw0KGgo=";

/// The textured octahedron as a .gltf in `folder`, its images three: a file in a subfolder (a
/// space in both names, percent-encoded), a data URI and a file that does not exist.
std::string textured_gltf(const fs::path& folder) {
  fs::create_directories(folder / "tex dir");
  const auto& png = test::tiny_png();
  write((folder / "tex dir" / "skin a.png").string(), std::string(png.begin(), png.end()));
  test::GltfScene s;
  s.primitives.push_back(test::octahedron_primitive(true, true));
  s.png.assign(png.begin(), png.end());
  test::GltfParts parts = test::gltf_parts(s);
  const std::size_t image = parts.json.find("\"images\":[");
  parts.json.replace(image, parts.json.find(']', image) + 1 - image,
                     "\"images\":[{\"uri\":\"tex%20dir/skin%20a.png\"},{\"uri\":\"" + DATA_URI +
                         "\"},{\"uri\":\"missing.png\"}]");
  return write((folder / "seam.gltf").string(), test::gltf_text(parts));
}

TEST(GltfImageUris, AResultInAnotherFolderNamesTheSameImageFiles) {
  ScratchDir dir("gltf_image_uris");
  const std::string in = textured_gltf(fs::path(dir.str()) / "in");
  fs::create_directories(dir.file("out/sub"));
  const std::string out = dir.file("out/sub/seam.gltf");
  const auto r = test::run_cli({"run", in, "-o", out, "-n", "3", "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json images = images_of(out);
  ASSERT_EQ(images.size(), 3u);
  EXPECT_EQ(images[0].at("uri"), "../../in/tex%20dir/skin%20a.png");
  EXPECT_TRUE(fs::is_regular_file(fs::path(out).parent_path() / "../../in/tex dir/skin a.png"));
  EXPECT_EQ(images[1].at("uri"), DATA_URI);  // data URIs stay
  // A uri that names no file is written as read, with a warning naming the input and the image.
  EXPECT_EQ(images[2].at("uri"), "missing.png");
  EXPECT_NE(r.output.find("warning: " + in +
                          ": images[2].uri 'missing.png' is no file from the "
                          "glTF's folder"),
            std::string::npos)
      << r.output;

  // Beside the input, every uri as read.
  const std::string beside = dir.file("in/seam_out.gltf");
  const auto same = test::run_cli({"run", in, "-o", beside, "-n", "3", "-q"});
  ASSERT_EQ(same.exit_code, 0) << same.output;
  EXPECT_EQ(images_of(beside)[0].at("uri"), "tex%20dir/skin%20a.png");
  EXPECT_EQ(same.output.find("missing.png"), std::string::npos) << same.output;
}

}  // namespace
}  // namespace shellcontract
