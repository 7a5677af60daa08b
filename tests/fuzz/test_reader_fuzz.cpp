// Mutation fuzzing of read_input_mesh and of `shellcontract check`: whatever the
// bytes, the reader returns a mesh or throws InputError naming the file; it never crashes, hangs
// or makes an allocation out of proportion to the file.
//
// Environment: SHELLCONTRACT_FUZZ_MUTANTS (default 2400; the `long` test runs 100,000),
// SHELLCONTRACT_FUZZ_SEED (default 30), SHELLCONTRACT_FUZZ_ONLY=K runs mutant K alone.
// A mutant that crashes the process is left on disk; the signal handler prints its path.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <new>
#include <set>
#include <string>
#include <vector>

#include "fuzz/fuzz_inputs.hpp"
#include "mesh/formats.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/mesh_io.hpp"
#include "support/cli_runner.hpp"

// ------------------------------------------------------------------ allocation watch
// Every allocation of this test executable goes through here, so that the test sees the largest
// single request a read makes. A request above HARD_CAP is refused (std::bad_alloc) instead of
// served, so that a reader that trusts a declared count fails the test without taking the
// machine's memory.
namespace {
std::atomic<bool> g_watch{false};
std::atomic<std::size_t> g_largest{0};
constexpr std::size_t HARD_CAP = std::size_t(1) << 30;

void* watched_alloc(std::size_t n) {
  if (g_watch.load(std::memory_order_relaxed)) {
    std::size_t prev = g_largest.load(std::memory_order_relaxed);
    while (n > prev && !g_largest.compare_exchange_weak(prev, n)) {
    }
    if (n > HARD_CAP) throw std::bad_alloc();
  }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return watched_alloc(n); }
void* operator new[](std::size_t n) { return watched_alloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace shellcontract {
namespace {

namespace fs = std::filesystem;

// ------------------------------------------------------------------ crash and hang reporting
char g_current[512] = "";  ///< path and description of the mutant being read

void report_and_die(int sig) {
  const char* head = sig == SIGALRM ? "\nFUZZ HANG (over 10 s) on mutant: " : "\nFUZZ CRASH (signal) on mutant: ";
  (void)!::write(2, head, std::strlen(head));
  (void)!::write(2, g_current, std::strlen(g_current));
  (void)!::write(2, "\n", 1);
  ::signal(sig == SIGALRM ? SIGABRT : sig, SIG_DFL);
  ::raise(sig == SIGALRM ? SIGABRT : sig);
}

void install_handlers() {
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM}) ::signal(sig, report_and_die);
}

std::size_t env_number(const char* name, std::size_t fallback) {
  const char* v = std::getenv(name);
  return v && *v ? static_cast<std::size_t>(std::strtoull(v, nullptr, 10)) : fallback;
}

/// A folder for the mutants, kept when the process dies (so the crashing file can be read).
fs::path fuzz_dir() {
  const fs::path d = fs::temp_directory_path() / ("shellcontract_fuzz_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

/// The mutant `k` of the run with base seed `seed`: which seed file, its bytes and what was done.
struct Mutant {
  const test::SeedFile* seed_file;
  std::string bytes;
  std::string what;
};

Mutant make_mutant(const std::vector<test::SeedFile>& seeds, std::uint64_t seed, std::size_t k) {
  test::Mutator m(seed * 1000003u + k);
  Mutant out{&seeds[k % seeds.size()], "", ""};
  out.bytes = m.mutate(out.seed_file->bytes, out.what);
  return out;
}

/// Largest single allocation allowed while reading a file of `size` bytes: a fixed slack plus a
/// multiple of the size (the mesh, the soup and the checks are each linear in it).
std::size_t allocation_bound(std::size_t size) { return (std::size_t(16) << 20) + 64 * size; }

// The mutants are made of the seeds: a format of the table without one would not be fuzzed, and
// a seed of no format would be refused for its extension alone.
TEST(ReaderFuzz, TheSeedsAreOfEveryFormatOfTheTable) {
  std::set<std::string> seeded, table;
  for (const test::SeedFile& s : test::seed_files()) seeded.insert(s.ext);
  for (const MeshFormat& f : MESH_FORMATS) table.insert(f.ext);
  EXPECT_EQ(seeded, table);
}

TEST(ReaderFuzz, EverySeedFileIsReadAsTheOctahedron) {
  const fs::path dir = fuzz_dir();
  for (const test::SeedFile& s : test::seed_files()) {
    const fs::path p = dir / (s.name + "." + s.ext);
    write_bytes(p, s.bytes);
    std::snprintf(g_current, sizeof g_current, "%s (unmutated seed)", p.c_str());
    install_handlers();
    try {
      InputReport report;
      const Mesh mesh = read_input_mesh(p.string(), &report);
      EXPECT_EQ(mesh.number_of_vertices(), 6u) << s.name;
      EXPECT_EQ(mesh.number_of_faces(), 8u) << s.name;
      // The octahedron with vertices at distance 1 from (1, 1, 1) (the OBJ seed is moved by 0.5
      // in y): volume 4/3.
      EXPECT_NEAR(report.volume, 4.0 / 3.0, 1e-12) << s.name;
      EXPECT_FALSE(report.reoriented) << s.name;
    } catch (const std::exception& e) {
      ADD_FAILURE() << s.name << " (a legal file) was refused: " << e.what();
    }
  }
  fs::remove_all(dir);
}

TEST(ReaderFuzz, MutantsReturnAMeshOrThrowInputErrorNamingTheFile) {
  const std::uint64_t seed = env_number("SHELLCONTRACT_FUZZ_SEED", 30);
  const std::size_t count = env_number("SHELLCONTRACT_FUZZ_MUTANTS", 2400);
  const std::size_t only = env_number("SHELLCONTRACT_FUZZ_ONLY", std::size_t(-1));
  const std::vector<test::SeedFile> seeds = test::seed_files();
  const fs::path dir = fuzz_dir();
  install_handlers();
  std::size_t accepted = 0, refused = 0, failed = 0;
  for (std::size_t k = 0; k < count; ++k) {
    if (only != std::size_t(-1) && k != only) continue;
    const Mutant m = make_mutant(seeds, seed, k);
    const fs::path p = dir / ("mutant_" + std::to_string(k) + "." + m.seed_file->ext);
    write_bytes(p, m.bytes);
    std::snprintf(g_current, sizeof g_current, "%s (SHELLCONTRACT_FUZZ_SEED=%llu SHELLCONTRACT_FUZZ_ONLY=%zu; %s: %s)",
                  p.c_str(), static_cast<unsigned long long>(seed), k, m.seed_file->name.c_str(), m.what.c_str());
    const std::string repro = g_current;
    ::alarm(10);
    g_largest = 0;
    g_watch = true;
    std::string problem;
    try {
      const Mesh mesh = read_input_mesh(p.string());
      // A glTF that reads is also a document (gltf_document.cpp) that writes it back: that
      // path indexes the buffers by the soup's vertices again, so it is fuzzed too.
      if (m.seed_file->ext == "glb" || m.seed_file->ext == "gltf") {
        const std::unique_ptr<MeshDocument> doc = read_mesh_document(p.string());
        if (doc && doc->matches(mesh)) doc->text(input_positions(mesh, positions_from_mesh(mesh)));
      }
      ++accepted;
    } catch (const InputError& e) {
      ++refused;
      if (std::string(e.what()).find(p.string()) == std::string::npos) problem = std::string("message does not name the file: ") + e.what();
    } catch (const std::exception& e) {
      problem = std::string("threw ") + typeid(e).name() + " (not InputError): " + e.what();
    } catch (...) {
      problem = "threw something that is not a std::exception";
    }
    g_watch = false;
    ::alarm(0);
    if (problem.empty() && g_largest > allocation_bound(m.bytes.size()))
      problem = "allocated " + std::to_string(g_largest.load()) + " bytes at once for a file of " + std::to_string(m.bytes.size()) + " bytes";
    if (!problem.empty()) {
      ++failed;
      ADD_FAILURE() << problem << "\n  reproduce: " << repro;
      if (failed >= 20) break;  // enough to see the pattern
      continue;                 // keep the failing file
    }
    fs::remove(p);
  }
  std::printf("reader fuzz: seed %llu, %zu mutants: %zu read, %zu refused with InputError, %zu failures\n",
              static_cast<unsigned long long>(seed), count, accepted, refused, failed);
  if (failed == 0) fs::remove_all(dir);
  // The mix follows from the mutator's design (fuzz_inputs.hpp), not from a run of it; a reader
  // that refused everything, or accepted everything, would pass the checks above and fail here.
  // Each mutant applies 1, 2 or 3 mutations (equally likely), each one of 9 kinds:
  //  - refused at least 1 in 10: a mutant contains a "truncate" with probability
  //    1 - mean((8/9)^n, n = 1..3) = 0.21, and a truncation at a uniform position leaves a file
  //    whose last face or vertex is cut off unless it falls in the trailing newline or the
  //    binary STL's 2-byte attribute (under 1 % of positions); nothing after it restores the
  //    lost counts. "huge count" (another 0.21) mostly adds to that. 0.1 leaves room for the
  //    binomial spread of 2400 draws (sigma 0.008).
  //  - accepted at least 1 in 1000: single mutations that change nothing the reader uses are
  //    common by construction: "swap lines" that picks one line twice, "move line to front"
  //    of line 1 (a tenth of its draws), a bit flip in the 80-byte header, the normals or the
  //    attribute bytes of the binary STL (39 % of its bytes), a duplicated PLY comment line.
  //    One mutation and one of these alone make well over 0.5 % of the mutants.
  if (only == std::size_t(-1) && failed == 0) {
    EXPECT_EQ(accepted + refused, count);
    EXPECT_GE(refused, count / 10) << "the mutants that truncate a file alone are more";
    EXPECT_GE(accepted, count / 1000) << "the mutants that change nothing read are more";
  }
}

// The CLI as a user runs it, on a smaller set: exit 0 or 2, never a signal; on exit 2 the message
// names the file. `run` on the same mutants writes no output file when it exits 2.
TEST(ReaderFuzz, CheckAndRunExitZeroOrTwoOnMutants) {
  if (!fs::exists(SHELLCONTRACT_CLI_PATH)) GTEST_SKIP() << SHELLCONTRACT_CLI_PATH << " has not been built yet";
  const std::uint64_t seed = env_number("SHELLCONTRACT_FUZZ_SEED", 30) + 1;
  const std::size_t count = env_number("SHELLCONTRACT_FUZZ_CLI_MUTANTS", 60);
  const std::vector<test::SeedFile> seeds = test::seed_files();
  const fs::path dir = fuzz_dir();
  std::size_t failed = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const Mutant m = make_mutant(seeds, seed, k);
    const fs::path p = dir / ("cli_" + std::to_string(k) + "." + m.seed_file->ext);
    write_bytes(p, m.bytes);
    const std::string repro = p.string() + " (seed " + std::to_string(seed) + ", mutant " + std::to_string(k) + ": " + m.seed_file->name + ": " + m.what + ")";
    // A 20 s limit and a 4 GB address space, so that a broken reader cannot hold the machine.
#ifdef __SANITIZE_ADDRESS__
    // Under AddressSanitizer (scripts/sanitize.sh) the CLI reserves terabytes of address space for
    // its shadow memory and cannot start under ulimit -v: ASan's own allocator limit instead.
    const std::string limits = "ASAN_OPTIONS=\"$ASAN_OPTIONS:malloc_limit_mb=4000\" timeout 20 ";
#else
    const std::string limits = "ulimit -v 4000000; timeout 20 ";
#endif
    const std::string check = limits + test::quoted(SHELLCONTRACT_CLI_PATH) + " check " + test::quoted(p.string()) + " 2>&1";
    test::RunResult r;
    if (FILE* pipe = ::popen(check.c_str(), "r")) {
      char buf[4096];
      std::size_t n = 0;
      while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
      const int status = ::pclose(pipe);
      r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    bool bad = false;
    if (r.exit_code != 0 && r.exit_code != 2) {
      ADD_FAILURE() << "check exited " << r.exit_code << "\n  reproduce: " << repro << "\n" << r.output;
      bad = true;
    } else if (r.exit_code == 2 && r.output.find(p.string()) == std::string::npos) {
      ADD_FAILURE() << "check's exit-2 message does not name the file\n  reproduce: " << repro << "\n" << r.output;
      bad = true;
    }
    // run must agree with check: the same mutant is refused (exit 2, no output) or runs.
    const fs::path out = dir / ("cli_" + std::to_string(k) + "_out.off");
    const test::RunResult run = test::run_cli({"run", p.string(), "-o", out.string(), "--frames", "2", "--quiet"});
    if (run.exit_code != r.exit_code && !(r.exit_code == 0 && run.exit_code == 3)) {
      ADD_FAILURE() << "check exited " << r.exit_code << " but run exited " << run.exit_code << "\n  reproduce: " << repro << "\n" << run.output;
      bad = true;
    }
    if (run.exit_code == 2 && fs::exists(out)) {
      ADD_FAILURE() << "run exited 2 but wrote " << out << "\n  reproduce: " << repro;
      bad = true;
    }
    if (bad && ++failed >= 10) break;
    if (!bad) fs::remove(p);
    fs::remove(out);
  }
  if (failed == 0) fs::remove_all(dir);
}

}  // namespace
}  // namespace shellcontract
