// The one way every subcommand reads its command line (command_line.hpp): boost's parser without
// its guessing of abbreviated names, the positional arguments checked here so that a stray one is
// named, and an unknown option answered with the names it was probably meant to be.
#include "command_line.hpp"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "shellcontract/error.hpp"
#include "shellcontract/options.hpp"

namespace shellcontract::cli {

namespace po = boost::program_options;

namespace {

/// The optimal string alignment distance: insertions, deletions, substitutions and swaps of two
/// neighbours each count 1 (`--presure`, `--fields-color`, `--target_volume`, `--frmaes`: 1).
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

/// A typographic dash that a word processor puts where "--" was typed (en dash, em dash, minus
/// sign, hyphen), which the shell passes on as an ordinary argument.
bool starts_with_pasted_dash(const std::string& token) {
  for (const char* dash : {"\xE2\x80\x93", "\xE2\x80\x94", "\xE2\x88\x92", "\xE2\x80\x90"})
    if (token.rfind(dash, 0) == 0) return true;
  return false;
}

/// The parsed options with the positional ones checked: the first is INPUT when `input_name`
/// is given, any other is refused by name.
void assign_positional(po::parsed_options& parsed, const char* input_name) {
  bool have_input = false;
  std::string first;
  for (po::option& o : parsed.options) {
    if (!o.string_key.empty() || o.value.empty()) continue;
    const std::string& token = o.value.front();
    if (input_name != nullptr && !have_input) {  // an empty one: refuse_empty_values says so
      o.string_key = input_name;
      have_input = true;
      first = token;
      continue;
    }
    std::string what = "unexpected argument '" + token + "'";
    if (starts_with_pasted_dash(token))
      what +=
          ": it begins with a typographic dash (pasted from a document?); options begin with "
          "two ASCII hyphens, --";
    else if (input_name != nullptr)
      what += ": INPUT is already '" + first + "' (one INPUT only)";
    else
      what += ": this command takes no positional argument, only options";
    throw UsageError(what);
  }
}

/// Refuses `-o=o.off`: boost takes what follows a short option's letter as its value, so the
/// output would be a file named "=o.off" (and `-p=3` "'=3' is not a number").
void refuse_equals_after_short_name(const po::parsed_options& parsed) {
  for (const po::option& o : parsed.options) {
    if (o.original_tokens.empty()) continue;
    const std::string& t = o.original_tokens.front();
    if (t.size() > 2 && t[0] == '-' && t[1] != '-' && t[2] == '=')
      throw UsageError("'" + t + "': a short option takes no '=' (write -" + std::string(1, t[1]) +
                       " " + t.substr(3) + ", or --" + o.string_key + "=" + t.substr(3) + ")");
  }
}

po::variables_map parse(int argc, char** argv, const po::options_description& visible,
                        const po::options_description& all, const char* input_name) {
  // Guessing off: boost took any unique prefix for the whole name (`--frame 3` ran as --frames),
  // which docs/cli.md never promised and an option added later would turn into an error.
  const int style = po::command_line_style::default_style & ~po::command_line_style::allow_guessing;
  po::parsed_options parsed(&all);
  try {
    parsed = po::command_line_parser(argc, argv).options(all).style(style).run();
  } catch (const po::unknown_option& e) {
    throw UsageError(std::string(e.what()) + option_suggestion(e.get_option_name(), visible));
  } catch (const po::invalid_command_line_syntax& e) {
    // A run option given without its value: the values it takes, as its help ends with them
    // (OptionSpec::help), so that `--validate` alone does not read like a switch that failed.
    std::string name = e.get_option_name();
    name.erase(0, name.find_first_not_of('-'));
    const OptionSpec* spec = find_run_option(name);
    const std::size_t last = spec ? spec->help.rfind("; ") : std::string::npos;
    if (e.kind() != po::invalid_syntax::missing_parameter || last == std::string::npos) throw;
    throw UsageError(std::string(e.what()) + ": " + spec->value_name + " is " +
                     spec->help.substr(last + 2));
  }
  assign_positional(parsed, input_name);
  po::variables_map vm;
  po::store(parsed, vm);
  if (vm.count("help")) return vm;
  refuse_equals_after_short_name(parsed);
  refuse_empty_values(vm);
  po::notify(vm);
  return vm;
}

}  // namespace

std::string option_suggestion(const std::string& unknown, const po::options_description& visible) {
  std::string name = unknown;
  name.erase(0, name.find_first_not_of('-'));
  if (const std::size_t eq = name.find('='); eq != std::string::npos) name.erase(eq);
  if (name.size() < 2) return {};
  std::vector<std::string> prefixed, nearest;
  std::size_t best = 3;  // at most 2 edits
  for (const auto& option : visible.options()) {
    const std::string& candidate = option->long_name();
    if (candidate.empty()) continue;
    if (candidate.rfind(name, 0) == 0) prefixed.push_back(candidate);
    const std::size_t d = edit_distance(name, candidate);
    if (2 * d >= name.size() || d > best) continue;
    if (d < best) nearest.clear();
    best = d;
    nearest.push_back(candidate);
  }
  const std::vector<std::string>& names = prefixed.empty() ? nearest : prefixed;
  if (names.empty() || names.size() > 4) return {};
  std::string text = " (did you mean ";
  for (std::size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + std::string("--") + names[i];
  return text + "?)";
}

po::variables_map parse_command_line(int argc, char** argv, const po::options_description& visible,
                                     std::string& input) {
  po::options_description hidden;
  hidden.add_options()("input", po::value(&input), "input mesh");
  po::options_description all;
  all.add(visible).add(hidden);
  return parse(argc, argv, visible, all, "input");
}

po::variables_map parse_options_only(int argc, char** argv,
                                     const po::options_description& visible) {
  return parse(argc, argv, visible, visible, nullptr);
}

}  // namespace shellcontract::cli
