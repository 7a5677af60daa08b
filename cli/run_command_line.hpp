// The run command's command line (run.cpp parses it): the --help texts around the options, and
// the library's option table (run_option_table) turned into boost::program_options.
#pragma once

#include <boost/program_options.hpp>
#include <map>
#include <string>
#include <vector>

namespace shellcontract::cli {

/// run --help's head (usage, what the command does) and tail (the exit codes).
extern const char* const RUN_USAGE;
extern const char* const RUN_EXIT_CODES;

/// The table's options as text values for boost, switches as bool_switch, repeatable ones as
/// lists, in the task groups of run --help (help_groups.hpp), each group added to `desc`.
void add_table_options(boost::program_options::options_description& desc,
                       std::map<std::string, std::string>& values,
                       std::map<std::string, bool>& switches,
                       std::map<std::string, std::vector<std::string>>& lists);

/// The value of a frame-count option (--checkpoint-every, --export-every), read as text so that
/// '2,5' is refused with the range, as every other numeric option is, and not with the parser's
/// "the argument ... is invalid": UsageError "OPTION: 'TEXT' is not an integer in [1, INT_MAX]".
int frame_count(const std::string& option, const std::string& text);

}  // namespace shellcontract::cli
