// What read_checkpoint checks of a checkpoint's fields (check_checkpoint_fields): the checksum
// at the end of the file is FNV-1a, which finds a damaged byte but not an edit, since anyone can
// recompute it. So every field is checked as the input it is before a run trusts it: an index
// out of range crashed the warm start, a position that is not finite ended in an uncaught
// exception, a frame past the run's end was reported as frames run.
#include <algorithm>
#include <cmath>
#include <string>

#include "mesh/file_safety.hpp"
#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"
#include "sim/checkpoint.hpp"

namespace shellcontract {
namespace {

/// The reason in the table's refusal of `value` ("`frames`: 'abc' is not an integer in ..."),
/// without its start: that names the option in backquotes, which each front end spells as its
/// own option (--frames), and the value, which is cut at a NUL (what() is a C string).
std::string why_refused(const std::string& name, const std::string& value,
                        const std::string& message) {
  std::string why = message;
  const std::string start = "`" + option_field(name) + "`: '" + value + "' ";
  if (why.compare(0, start.size(), start) == 0)
    why.erase(0, start.size());
  else if (value.find('\0') != std::string::npos)
    return "is not accepted (it holds a NUL)";
  else
    why = "is not accepted: " + why;
  for (char& ch : why)
    if (ch == '`') ch = '\'';
  return printable(why);
}

class FieldCheck {
 public:
  explicit FieldCheck(const std::string& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError("checkpoint " + printable(path_) + ": " + field + ": " + what +
                     " (the file was edited or is damaged; a run never saves this)");
  }
  void finite(const std::string& field, double v) const {
    if (!std::isfinite(v)) fail(field, "is not a finite number (" + std::to_string(v) + ")");
  }
  /// Rows of 3 finite coordinates; `rows` of them where rows >= 0.
  void positions(const std::string& field, const Positions& m, Eigen::Index rows) const {
    if (rows >= 0 && m.rows() != rows)
      fail(field,
           "has " + std::to_string(m.rows()) + " rows for " + std::to_string(rows) + " vertices");
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index k = 0; k < m.cols(); ++k)
        if (!std::isfinite(m(i, k)))
          fail(field, "vertex " + std::to_string(i) + " has a coordinate that is not finite (" +
                          std::to_string(m(i, k)) + ")");
  }
  /// Each option is one the table knows, with a value it accepts. An empty value is an option
  /// unset where `unset` allows it (every one resolved), and weights given as numbers, which
  /// have no text (options_for_resume skips them too). The option's own message would name it
  /// as if the user had typed it (--frames: 'abc' ...): here it is the file's. Returns the
  /// options set (each alone: options that exclude each other are resolve_run_options' refusal).
  RunOptions options(const std::string& field, const OptionValues& values, bool unset) const {
    RunOptions set;
    for (const auto& [name, value] : values) {
      const std::string which = field + ", option '" + printable(name, 60) + "'";
      if (!find_run_option(name)) fail(which, "is not an option of this version");
      if (value.empty() && (unset || name == "region-weights")) continue;
      try {
        set_run_option(set, name, value);
      } catch (const UsageError& e) {
        fail(which, "'" + printable(value, 60) + "' " + why_refused(name, value, e.what()));
      }
    }
    return set;
  }

 private:
  const std::string& path_;
};

}  // namespace

void check_checkpoint_fields(const Checkpoint& c, const std::string& path) {
  const FieldCheck check(path);
  RunOptions given = check.options("the options given", c.given, false);
  // Options each valid alone may still exclude each other (`region_at` beside `regions`). A run
  // never saves such a set, so it is the file's fault (exit 2), not the user's usage (exit 1).
  // Regions or weights given as arrays (Python) have no text here: options_for_resume asks for
  // them again, and judges the whole then.
  const bool all_text = std::none_of(c.inputs.begin(), c.inputs.end(),
                                     [](const RunInput& in) { return in.arrays; }) &&
                        std::none_of(c.given.begin(), c.given.end(), [](const auto& o) {
                          return o.first == "region-weights" && o.second.empty();
                        });
  if (all_text) {
    try {
      resolve_run_options(given);
    } catch (const UsageError& e) {
      check.fail("the options given", std::string("exclude each other: ") + e.what());
    }
  }
  const RunOptions resolved = check.options("the options resolved", c.resolved, true);

  const SimulatorState& s = c.sim;
  if (s.frame < 0) check.fail("the frame", "is negative (" + std::to_string(s.frame) + ")");
  // A run saves only while it goes on (run_contraction): a frame at or past its end is no state
  // of that run (one past it was reported as the frames run).
  if (s.frame >= resolved.sim.frames)
    check.fail("the frame", std::to_string(s.frame) + " is not before the run's end (" +
                                std::to_string(resolved.sim.frames) + " frames)");
  check.finite("V/V0", s.volume_ratio);
  const Eigen::Index n = s.x.rows();
  if (n == 0) check.fail("the positions", "hold no vertex");
  check.positions("the positions", s.x, -1);
  check.positions("the velocities", s.v, n);
  if (!s.held_by_contact.empty() && s.held_by_contact.size() != static_cast<std::size_t>(n))
    check.fail("the held vertices", std::to_string(s.held_by_contact.size()) + " marks for " +
                                        std::to_string(n) + " vertices");
  for (std::size_t i = 0; i < s.held_by_contact.size(); ++i)
    if (s.held_by_contact[i] != 0 && s.held_by_contact[i] != 1)
      check.fail("the held vertices", "vertex " + std::to_string(i) + "'s mark is neither 0 nor 1");
  for (std::size_t i = 0; i < s.dimple_sizes.size(); ++i)
    if (s.dimple_sizes[i] < 0)
      check.fail("the dimple sizes", "region " + std::to_string(i) + "'s is negative");
  const std::vector<Contact>& cache = s.collision.contact_cache;
  if (!s.has_collision && !cache.empty())
    check.fail("the contact cache", "holds contacts of a run without collisions");
  for (std::size_t i = 0; i < cache.size(); ++i) {
    const Contact& k = cache[i];
    const std::string field = "contact " + std::to_string(i) + " of the contact cache";
    if (k.kind != CcdPrimitive::VertexFace && k.kind != CcdPrimitive::EdgeEdge)
      check.fail(field, "has an unknown kind (" + std::to_string(static_cast<int>(k.kind)) + ")");
    for (const int id : k.pair)
      if (id < 0) check.fail(field, "names a negative element id (" + std::to_string(id) + ")");
    for (const int id : k.v)
      if (id < 0 || id >= n)
        check.fail(field, "names vertex " + std::to_string(id) + "; the checkpoint has " +
                              std::to_string(n) + " vertices");
    for (int j = 0; j < 4; ++j) check.finite(field + ", weight " + std::to_string(j), k.weights(j));
    for (int j = 0; j < 3; ++j) check.finite(field + ", normal", k.normal(j));
    check.finite(field + ", side", k.side);
  }
  // The speculative broad phase starts afresh from none (no rows), else holds one per vertex.
  const Positions& correction = s.collision.correction;
  check.positions("the broad phase's correction", correction, correction.rows() == 0 ? 0 : n);
  const Eigen::VectorXd& skin = s.collision.skin;
  if (skin.size() != 0 && skin.size() != n)
    check.fail("the broad phase's skins",
               std::to_string(skin.size()) + " for " + std::to_string(n) + " vertices");
  for (Eigen::Index i = 0; i < skin.size(); ++i)
    if (!(std::isfinite(skin(i)) && skin(i) >= 0.0))
      check.fail("the broad phase's skins",
                 "vertex " + std::to_string(i) + "'s is not a finite length >= 0");

  const RunProgress& p = c.progress;
  // The run loop appends one V/V0 a frame to the rest state's 1.
  if (p.history.size() != static_cast<std::size_t>(s.frame) + 1)
    check.fail("the V/V0 history", std::to_string(p.history.size()) + " values at frame " +
                                       std::to_string(s.frame) +
                                       " (one a frame, and the rest state's)");
  for (std::size_t i = 0; i < p.history.size(); ++i)
    check.finite("the V/V0 history, frame " + std::to_string(i), p.history[i]);
  check.finite("the least V/V0", p.min_volume_ratio);
  for (const auto& [name, value] : p.totals.per_step(1))
    check.finite("the run's totals, " + name, value);
  if (p.new_intersections < -1)
    check.fail("the new self-intersections",
               "a count below -1 (" + std::to_string(p.new_intersections) + ")");
  const int status = static_cast<int>(p.status);
  if (status < static_cast<int>(RunStatus::Completed) ||
      status > static_cast<int>(RunStatus::Cancelled))
    check.fail("the run's status", "unknown (" + std::to_string(status) + ")");
  if (p.frame_target_reached < -1 || p.frame_target_reached > s.frame)
    check.fail("the frame the target was reached",
               std::to_string(p.frame_target_reached) + " at frame " + std::to_string(s.frame));
  if (p.last_pairs < 0) check.fail("the last step's pairs", "a negative count");
}

}  // namespace shellcontract
