// A C locale whose decimal point is ',' (as de_DE, fr_FR, ...), set for the life of a
// CommaLocale: the state of a Python program that called setlocale(LC_ALL, "") on such a
// desktop (PyQt and GTK do), in which the library runs as a module. The build and CI machines
// have only C and C.UTF-8 installed, so the locale is built here with localedef (glibc's
// libc-bin, on every Debian system) from a definition written by the test, with its own
// character map: nothing of the `locales` package is needed. Where localedef is missing or its
// locale cannot be set, the test skips with the reason (fails under SHELLCONTRACT_STRICT_TESTS=1,
// support/ci_skip.hpp).
#pragma once

#include <unistd.h>

#include <clocale>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "support/ci_skip.hpp"

namespace shellcontract::test {

class CommaLocale {
 public:
  CommaLocale() {
    namespace fs = std::filesystem;
    dir_ = fs::temp_directory_path() / ("comma-locale-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "comma.def") << "LC_NUMERIC\n"
                                         "decimal_point \"<U002C>\"\n"
                                         "thousands_sep \"<U002E>\"\n"
                                         "grouping 3;3\n"
                                         "END LC_NUMERIC\n";
    std::ofstream map(dir_ / "ascii.map");
    map << "<code_set_name> COMMA_TEST\n<comment_char> %\n<escape_char> /\n<mb_cur_min> 1\n"
           "<mb_cur_max> 1\nCHARMAP\n";
    for (int c = 0; c < 128; ++c) {
      char line[32];
      std::snprintf(line, sizeof line, "<U%04X> /x%02x\n", c, c);
      map << line;
    }
    map << "END CHARMAP\n";
    map.close();
    // -c: localedef warns that the other categories are missing (and exits 1); the locale is
    // written all the same, and setlocale below is the check.
    const std::string command = "localedef -c -i '" + (dir_ / "comma.def").string() + "' -f '" +
                                (dir_ / "ascii.map").string() + "' '" + (dir_ / "xx_XX").string() +
                                "' > '" + (dir_ / "localedef.log").string() + "' 2>&1";
    const int status = std::system(command.c_str());
    const char* old_path = std::getenv("LOCPATH");
    if (old_path) old_locpath_ = old_path, had_locpath_ = true;
    ::setenv("LOCPATH", dir_.c_str(), 1);
    if (std::setlocale(LC_ALL, "xx_XX") == nullptr) {
      why_ = "a decimal-comma locale could not be made (localedef exit status " +
             std::to_string(status) + "; is localedef, from libc-bin, installed?)";
      return;
    }
    const char* point = std::localeconv()->decimal_point;
    if (std::string(point) != ",") {
      why_ = std::string("the locale made has the decimal point '") + point + "'";
      return;
    }
    set_ = true;
  }

  ~CommaLocale() {
    std::setlocale(LC_ALL, "C");
    if (had_locpath_)
      ::setenv("LOCPATH", old_locpath_.c_str(), 1);
    else
      ::unsetenv("LOCPATH");
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }

  CommaLocale(const CommaLocale&) = delete;
  CommaLocale& operator=(const CommaLocale&) = delete;

  /// True when LC_ALL is the decimal-comma locale; otherwise why() says why not.
  bool set() const { return set_; }
  const std::string& why() const { return why_; }

 private:
  std::filesystem::path dir_;
  std::string old_locpath_, why_;
  bool had_locpath_ = false, set_ = false;
};

}  // namespace shellcontract::test

/// Declares `locale_`, a CommaLocale, in the calling test; skips it (fails under
/// SHELLCONTRACT_STRICT_TESTS=1) where the locale cannot be set.
#define SET_COMMA_LOCALE_OR_SKIP()                            \
  ::shellcontract::test::CommaLocale locale_;                 \
  do {                                                        \
    if (!locale_.set()) SKIP_OR_FAIL_UNDER_CI(locale_.why()); \
  } while (false)
