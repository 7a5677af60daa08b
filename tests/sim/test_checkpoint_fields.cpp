// Checkpoints edited by hand and resealed (tests/support/forged_checkpoint.hpp): the checksum is
// FNV-1a, which anyone can recompute, so each field is checked as input. Every forgery below is
// refused with an InputError naming the file and the field, either by read_checkpoint or, for
// what only the mesh decides, by run_contraction before its first step. Before the checks a
// contact id out of range crashed the warm start (SIGSEGV), a NaN position ended in
// std::terminate, a frame past the run's end was reported as frames run, and the rest was
// resumed into a state no run had.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "shellcontract/options.hpp"
#include "sim/checkpoint.hpp"
#include "sim/simulator.hpp"
#include "support/forged_checkpoint.hpp"
#include "support/memory_checkpointer.hpp"
#include "test_paths.hpp"

namespace shellcontract {
namespace {

namespace fs = std::filesystem;
using test::forge_checkpoint;

using test::MemoryCheckpointer;

class ForgedCheckpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("shellcontract_forged_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// A real checkpoint of `mesh` run with `given`, saved at frame `at`, written to real.ckpt.
  void save(const std::string& mesh_name,
            const std::vector<std::pair<std::string, std::string>>& given, int at) {
    mesh_ = read_input_mesh(std::string(test::MESH_DIR) + "/" + mesh_name);
    for (const auto& [name, value] : given) set_run_option(options_, name, value);
    MemoryCheckpointer saver(mesh_, options_, at, /*stop=*/true);
    run_contraction(mesh_, options_, nullptr, &saver);
    ASSERT_TRUE(saver.saved.has_value());
    write_checkpoint(real(), *saver.saved);
  }
  std::string real() const { return (dir_ / "real.ckpt").string(); }
  std::string forged() const { return (dir_ / "forged.ckpt").string(); }

  /// The message refusing the checkpoint at `path`, read and resumed as the CLI does; "(resumed)"
  /// if it ran.
  std::string refusal(const std::string& path) {
    try {
      const Checkpoint c = read_checkpoint(path);
      MemoryCheckpointer resumer(&c);
      run_contraction(mesh_, options_for_resume(c, RunOptions{}), nullptr, &resumer);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(resumed)";
  }
  /// Forges real.ckpt by `edit` and expects a refusal naming the file and `field`.
  void expect_refused(const std::string& what, const std::function<void(Checkpoint&)>& edit,
                      const std::string& field) {
    SCOPED_TRACE(what);
    forge_checkpoint(real(), forged(), edit);
    const std::string msg = refusal(forged());
    EXPECT_NE(msg.find("checkpoint " + forged()), std::string::npos) << msg;
    EXPECT_NE(msg.find(field), std::string::npos) << msg;
  }

  fs::path dir_;
  Mesh mesh_;
  RunOptions options_;
};

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();
constexpr double Inf = std::numeric_limits<double>::infinity();

Contact contact(CcdPrimitive kind, std::array<int, 2> pair, std::array<int, 4> v) {
  Contact c;
  c.kind = kind;
  c.pair = pair;
  c.v = v;
  c.weights = Eigen::Vector4d(0.25, 0.25, 0.25, 0.25);
  return c;
}

TEST_F(ForgedCheckpoint, TheRealOneResumes) {
  save("ico2.off", {{"frames", "10"}}, 4);
  forge_checkpoint(real(), forged(), [](Checkpoint&) {});
  EXPECT_EQ(refusal(forged()), "(resumed)");
}

TEST_F(ForgedCheckpoint, TheSimulatorsStateIsRefusedNamingTheField) {
  save("ico2.off", {{"frames", "10"}}, 4);
  ASSERT_TRUE(read_checkpoint(real()).sim.has_collision);
  const int n = static_cast<int>(mesh_.number_of_vertices());
  const int f = static_cast<int>(mesh_.number_of_faces());
  const auto face = [&](int i) {
    std::array<int, 4> v{0, 0, 0, 0};
    int k = 1;
    for (VertexIndex w : vertices_around_face(mesh_.halfedge(FaceIndex(i)), mesh_))
      v[k++] = static_cast<int>(w.idx());
    return v;
  };
  // A vertex that is not a corner of face 5, with face 5's corners: the stencil of (vertex, 5).
  std::array<int, 4> vf = face(5);
  while (vf[0] == vf[1] || vf[0] == vf[2] || vf[0] == vf[3]) ++vf[0];
  ASSERT_LT(vf[0], n);
  expect_refused(
      "the hostile review's contact",
      [](Checkpoint& c) {
        c.sim.collision.contact_cache.push_back(
            contact(CcdPrimitive::VertexFace, {0, 1}, {1000000000, -5, 7, 2000000000}));
      },
      "contact 0 of the contact cache");
  expect_refused(
      "a contact's face past the mesh's",
      [&](Checkpoint& c) {
        c.sim.collision.contact_cache.push_back(
            contact(CcdPrimitive::VertexFace, {vf[0], f + 7}, vf));
      },
      "contact 0 of the contact cache names vertex");
  expect_refused(
      "a contact's edge past the mesh's",
      [&](Checkpoint& c) {
        c.sim.collision.contact_cache.push_back(
            contact(CcdPrimitive::EdgeEdge, {0, 100000}, {0, 1, 2, 3}));
      },
      "edge 100000");
  expect_refused(
      "a contact whose vertices are not its pair's",
      [&](Checkpoint& c) {
        std::array<int, 4> other = vf;
        std::swap(other[0], other[1]);
        c.sim.collision.contact_cache.push_back(
            contact(CcdPrimitive::VertexFace, {vf[0], 5}, other));
      },
      "not those of its vertex and face");
  expect_refused(
      "a contact of no kind",
      [&](Checkpoint& c) {
        c.sim.collision.contact_cache.push_back(
            contact(static_cast<CcdPrimitive>(7), {vf[0], 5}, vf));
      },
      "unknown kind");
  expect_refused(
      "a contact's weight",
      [&](Checkpoint& c) {
        Contact k = contact(CcdPrimitive::VertexFace, {vf[0], 5}, vf);
        k.weights(2) = NaN;
        c.sim.collision.contact_cache.push_back(k);
      },
      "contact 0 of the contact cache, weight 2");
  // The stencil the detection would record is accepted (the checks are not stricter than runs).
  forge_checkpoint(real(), forged(), [&](Checkpoint& c) {
    c.sim.collision.contact_cache.push_back(contact(CcdPrimitive::VertexFace, {vf[0], 5}, vf));
  });
  EXPECT_EQ(refusal(forged()), "(resumed)");

  expect_refused(
      "a NaN position", [](Checkpoint& c) { c.sim.x(0, 0) = NaN; }, "the positions: vertex 0");
  expect_refused(
      "an infinite velocity", [](Checkpoint& c) { c.sim.v(3, 2) = -Inf; },
      "the velocities: vertex 3");
  expect_refused(
      "fewer velocities", [](Checkpoint& c) { c.sim.v.conservativeResize(5, 3); },
      "the velocities");
  expect_refused(
      "V/V0", [](Checkpoint& c) { c.sim.volume_ratio = NaN; }, "V/V0");
  expect_refused(
      "a held mark",
      [](Checkpoint& c) {
        c.sim.held_by_contact.assign(static_cast<std::size_t>(c.sim.x.rows()), 0);
        c.sim.held_by_contact[2] = 7;
      },
      "the held vertices: vertex 2");
  expect_refused(
      "held marks not one per vertex", [](Checkpoint& c) { c.sim.held_by_contact.assign(3, 0); },
      "the held vertices");
  expect_refused(
      "a correction not one per vertex",
      [](Checkpoint& c) { c.sim.collision.correction.setZero(4, 3); },
      "the broad phase's correction");
  expect_refused(
      "a NaN correction",
      [](Checkpoint& c) {
        c.sim.collision.correction.setZero(c.sim.x.rows(), 3);
        c.sim.collision.correction(1, 1) = NaN;
      },
      "the broad phase's correction: vertex 1");
  expect_refused(
      "a negative skin",
      [](Checkpoint& c) {
        c.sim.collision.skin.setConstant(c.sim.x.rows(), 0.01);
        c.sim.collision.skin(4) = -1.0;
      },
      "the broad phase's skins: vertex 4");
  expect_refused(
      "skins not one per vertex", [](Checkpoint& c) { c.sim.collision.skin.setConstant(9, 0.01); },
      "the broad phase's skins");
  expect_refused(
      "the stop ratio reached", [](Checkpoint& c) { c.sim.stop_volume_reached = true; },
      "stop ratio");
}

TEST_F(ForgedCheckpoint, AFrameOutsideTheRunIsRefused) {
  save("ico2.off", {{"frames", "10"}}, 4);
  // The hostile review's: frame 1,000,000 of a 10-frame run had run as 1,000,000 frames, exit 0.
  expect_refused(
      "far past the end", [](Checkpoint& c) { c.sim.frame = 1000000; },
      "the frame: 1000000 is not before");
  expect_refused(
      "at the end",
      [](Checkpoint& c) {
        c.sim.frame = 10;
        c.progress.history.resize(11, 0.9);
      },
      "the frame: 10 is not before the run's end (10 frames)");
  expect_refused(
      "negative", [](Checkpoint& c) { c.sim.frame = -3; }, "the frame");
  expect_refused(
      "a history not one per frame", [](Checkpoint& c) { c.sim.frame = 6; }, "the V/V0 history");
  expect_refused(
      "a NaN in the history", [](Checkpoint& c) { c.progress.history[2] = NaN; },
      "the V/V0 history, frame 2");
  expect_refused(
      "the least V/V0", [](Checkpoint& c) { c.progress.min_volume_ratio = Inf; }, "the least V/V0");
  expect_refused(
      "a status", [](Checkpoint& c) { c.progress.status = static_cast<RunStatus>(42); },
      "the run's status");
  expect_refused(
      "a target frame past the frame", [](Checkpoint& c) { c.progress.frame_target_reached = 9; },
      "the frame the target was reached");
  // Beyond int: the file holds 64 bits, which were cast to int unchecked (2^32 + 3 became 3).
  forge_checkpoint(real(), forged(), [](Checkpoint& c) { c.sim.frame = 0x5EC0DE; });
  test::forge_int64(forged(), forged(), 0x5EC0DE, (std::int64_t{1} << 32) + 3);
  const std::string msg = refusal(forged());
  EXPECT_NE(msg.find("checkpoint " + forged() + ": a frame 4294967299 out of range"),
            std::string::npos)
      << msg;
}

TEST_F(ForgedCheckpoint, OptionTextIsTheCheckpointsNotTheUsers) {
  save("ico2.off", {{"frames", "10"}}, 4);
  const auto set = [](OptionValues& o, const std::string& name, const std::string& value) {
    for (auto& [n, v] : o)
      if (n == name) v = value;
  };
  expect_refused(
      "frames 'abc'", [&](Checkpoint& c) { set(c.given, "frames", "abc"); },
      "the options given, option 'frames': 'abc' is not an integer");
  expect_refused(
      "an option of no version", [](Checkpoint& c) { c.given.emplace_back("no-such", "1"); },
      "the options given, option 'no-such': is not an option");
  expect_refused(
      "a resolved value", [&](Checkpoint& c) { set(c.resolved, "pressure", "-nan"); },
      "the options resolved, option 'pressure'");
  // A NUL and an escape in the value are written out, not cut at or obeyed.
  forge_checkpoint(real(), forged(),
                   [&](Checkpoint& c) { set(c.given, "frames", std::string("8\0\x1b[2J", 6)); });
  const std::string msg = refusal(forged());
  EXPECT_NE(msg.find("option 'frames': '8\\x00\\x1b[2J' is not"), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\0'), std::string::npos);
  EXPECT_EQ(msg.find('\x1b'), std::string::npos);
  EXPECT_NE(msg.find("(the file was edited or is damaged"), std::string::npos) << msg;
  // The user's option is not named as if typed: the message has no "--frames".
  EXPECT_EQ(spell_options(msg, OptionSpelling::Cli).find("--frames"), std::string::npos) << msg;
}

// Options each valid alone that exclude each other are the file's fault as well (a run never saves
// them): exit 2 naming the checkpoint, where resolving them as the user's gave a usage error.
TEST_F(ForgedCheckpoint, OptionsThatExcludeEachOtherAreTheCheckpoints) {
  save("ico2.off", {{"frames", "10"}}, 4);
  expect_refused(
      "region-at beside regions",
      [](Checkpoint& c) {
        c.given.emplace_back("region-at", "0,0,1");
        c.given.emplace_back("regions", "auto");
      },
      "the options given: exclude each other: `region_at` excludes `regions`");
}

// Another version's checkpoint may hold options this one does not know: it is refused as
// another version's, not judged by this version's rules as edited.
TEST_F(ForgedCheckpoint, AnotherVersionIsNamedAsSuch) {
  save("ico2.off", {{"frames", "10"}}, 4);
  forge_checkpoint(real(), forged(), [](Checkpoint& c) {
    c.version = "0.0.1";
    c.given.emplace_back("an-option-to-come", "1");
  });
  const std::string msg = refusal(forged());
  EXPECT_NE(msg.find("checkpoint " + forged() + " written by shellcontract 0.0.1, this is "),
            std::string::npos)
      << msg;
}

TEST_F(ForgedCheckpoint, ADimpleLargerThanItsRegionIsRefused) {
  save("ico1.off", {{"frames", "6"}, {"pressure", "0"}, {"region-at", "0,0,1"}}, 3);
  ASSERT_EQ(read_checkpoint(real()).sim.dimple_sizes.size(), 1u);
  expect_refused(
      "too large", [](Checkpoint& c) { c.sim.dimple_sizes[0] = 1000000; },
      "region 0's dimple has 1000000 faces");
  expect_refused(
      "negative", [](Checkpoint& c) { c.sim.dimple_sizes[0] = -2; }, "the dimple sizes: region 0");
}

/// A format-3 checkpoint as its layout (sim/checkpoint.cpp) is written out here, not by the code
/// under test: magic, format, version "v", input "i" and its hash, then `fields`, zeros up to
/// `size` bytes, resealed.
std::string forged_layout(const std::string& fields, std::size_t size) {
  std::string b = "SHELLCONTRACT-CHECKPOINT\n";
  const auto put = [&b](auto v) { b.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(std::uint32_t{3});
  put(std::uint64_t{1});
  b += 'v';
  put(std::uint64_t{1});
  b += 'i';
  put(std::uint64_t{0});
  b += fields;
  b.resize(size, '\0');
  return test::resealed(b);
}

template <class T>
std::string bytes_of(T v) {
  return std::string(reinterpret_cast<const char*>(&v), sizeof v);
}

// Review 7 (F7): a count the bytes left cannot hold is refused before anything is allocated for
// it. Checked against the file's size alone, a count as large as the file made the reader
// allocate each entry (some 80 bytes) for each byte of the file, then fail as "truncated": a
// forged 200 MB file asked for 16 GB. The counts here are as large as their files.
TEST_F(ForgedCheckpoint, ACountPastTheBytesLeftIsRefusedBeforeItIsAllocated) {
  const std::uint64_t n = 4000;
  const auto expect_count_refused = [&](const std::string& what, const std::string& fields) {
    SCOPED_TRACE(what);
    std::ofstream(forged(), std::ios::binary | std::ios::trunc) << forged_layout(fields, n);
    const std::string msg = refusal(forged());
    EXPECT_NE(msg.find("checkpoint " + forged() + ": 4000 " + what + " of at least "),
              std::string::npos)
        << msg;
  };
  const std::string none = bytes_of(std::uint64_t{0}), count = bytes_of(n);
  expect_count_refused("inputs", count);
  expect_count_refused("options", none + count);         // the options given
  expect_count_refused("options", none + none + count);  // the options resolved
  // The state up to the contacts: frame 0, V/V0 0, no stop, one vertex of positions and of
  // velocities, no held vertices, no dimples, collisions on.
  const std::string vertex =
      bytes_of(std::uint64_t{1}) + bytes_of(std::uint64_t{3}) + std::string(24, '\0');
  const std::string state = bytes_of(std::int64_t{0}) + bytes_of(0.0) + std::string(1, '\0') +
                            vertex + vertex + none + none + std::string(1, '\1');
  expect_count_refused("contacts", none + none + none + state + count);
}

}  // namespace
}  // namespace shellcontract
