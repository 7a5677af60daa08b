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

}  // namespace shellcontract::cli
