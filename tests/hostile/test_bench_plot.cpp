// `bench error --plot` hands gnuplot no file name, and its plot is written through a temporary
// (docs/design/output-safety.md, "Temporaries"). Each test failed against the code before: the
// script named the plot, the CSV and the input between single quotes, so a `'` made gnuplot write
// another file (or run what followed a `;`), a name beginning with `|` or `<` was a command to
// gnuplot, a `'`, backquote or newline in the input's name broke the title after every run, and
// gnuplot opened the plot itself, so one that failed half way cut the previous plot.
#include "hostile/hostile_support.hpp"

namespace shellcontract {
namespace {

using test::Hostile;

bool has_gnuplot() { return test::run_command("command -v gnuplot >/dev/null").exit_code == 0; }

/// bench error on `input` with the smallest ladder, run in `dir` (relative names stay relative).
test::RunResult bench_in(const fs::path& dir, const std::string& input,
                         const std::vector<std::string>& outputs, const std::string& env = "") {
  std::vector<std::string> args{"bench", "error",      input, "--frames", "2",    "--iterations",
                                "1",     "--substeps", "1",   "--solver", "xpbd", "--no-check"};
  args.insert(args.end(), outputs.begin(), outputs.end());
  return test::run_command("cd " + test::quoted(dir.string()) + " && " + env +
                           test::cli_command(args));
}

bool is_svg(const std::string& bytes) {
  return bytes.find("<svg") != std::string::npos && bytes.find("</svg>") != std::string::npos;
}

bool is_png(const std::string& bytes) { return bytes.rfind("\x89PNG\r\n\x1a\n", 0) == 0; }

TEST_F(Hostile, BenchErrorPlotNamesGnuplotWouldMisreadWriteThatFileAndNoOther) {
  if (!has_gnuplot()) GTEST_SKIP() << "gnuplot is not installed";
  fs::copy_file(test::mesh("ico1.off"), dir_ / "in.off");
  struct Case {
    std::vector<std::string> outputs;  // the options
    std::vector<std::string> files;    // what they name, relative to dir_
  };
  const std::string inject = "a.png'; system 'touch PWNED'; set output 'b.png";
  const std::string csv_command = "<touch PWN3; echo 1 2 #.csv";
  const std::vector<Case> cases = {
      {{"--plot", "it's.svg"}, {"it's.svg"}},
      {{"--plot", inject}, {inject}},
      {{"--plot", "|touch PWN2 #.svg"}, {"|touch PWN2 #.svg"}},
      {{"--csv", csv_command, "--plot", "p.svg"}, {csv_command, "p.svg"}},
  };
  for (const Case& c : cases) {
    for (const std::string& f : c.files) fs::remove(dir_ / f);
    const auto r = bench_in(dir_, "in.off", c.outputs);
    const std::string plot = c.files.back();
    EXPECT_EQ(r.exit_code, 0) << plot << ": " << r.output;
    EXPECT_NE(r.output.find("plot written to " + plot), std::string::npos) << r.output;
    std::vector<std::string> expected{"in.off"};
    expected.insert(expected.end(), c.files.begin(), c.files.end());
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(test::listing(dir_), expected) << plot << ": " << r.output;
    const std::string bytes = test::slurp(dir_ / plot);
    EXPECT_TRUE(fs::path(plot).extension() == ".svg" ? is_svg(bytes) : is_png(bytes))
        << plot << ": not a whole plot (" << bytes.size() << " bytes)";
    for (const std::string& f : c.files) fs::remove(dir_ / f);
  }
}

TEST_F(Hostile, BenchErrorPlotExtensionInAnyCaseDrawsThatFormat) {
  // The mesh formats' extensions are read in any case; --plot's were not (P.SVG was refused).
  if (!has_gnuplot()) GTEST_SKIP() << "gnuplot is not installed";
  fs::copy_file(test::mesh("ico1.off"), dir_ / "in.off");
  for (const std::string plot : {"P.SVG", "q.Png"}) {
    const auto r = bench_in(dir_, "in.off", {"--plot", plot});
    EXPECT_EQ(r.exit_code, 0) << plot << ": " << r.output;
    const std::string bytes = test::slurp(dir_ / plot);
    EXPECT_TRUE(plot == "P.SVG" ? is_svg(bytes) : is_png(bytes)) << plot << ": not that format";
  }
}

TEST_F(Hostile, BenchErrorPlotTitleFromAnyInputNameIsOneString) {
  if (!has_gnuplot()) GTEST_SKIP() << "gnuplot is not installed";
  // A quote, a backquote (a command to gnuplot outside single quotes), a macro and a newline.
  for (const std::string& name :
       {std::string("o'k`touch BQ`@GPVAL_PWD.off"), std::string("new\nline.off")}) {
    fs::create_directories(dir_ / "d");
    fs::copy_file(test::mesh("ico1.off"), dir_ / "d" / name);
    const auto r = bench_in(dir_ / "d", name, {"--plot", "p.svg"});
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(test::listing(dir_ / "d"), (std::vector<std::string>{name, "p.svg"})) << r.output;
    const std::string svg = test::slurp(dir_ / "d" / "p.svg");
    EXPECT_TRUE(is_svg(svg)) << r.output;
    const std::string shown = name[0] == 'o' ? name : "new\\x0aline.off";
    EXPECT_NE(svg.find(shown + ": 2 steps"), std::string::npos) << "title not " << shown;
    fs::remove_all(dir_ / "d");
  }
}

TEST_F(Hostile, BenchErrorPlotKeepsThePreviousPlotWhenGnuplotFails) {
  // A gnuplot earlier on PATH that draws half a plot where it is told (a file it is named, or
  // its stdout), then fails: exits 1, drawing nothing and exiting 0, or killed.
  fs::create_directories(dir_ / "bin");
  fs::copy_file(test::mesh("ico1.off"), dir_ / "in.off");
  const std::string draw_half =
      "while IFS= read -r line; do case \"$line\" in\n"
      "  \"set output '\"*) out=${line#\"set output '\"}; out=${out%\"'\"}\n"
      "    printf '<svg half' > \"$out\";;\n"
      "  'set output') printf '<svg half';;\n"
      "esac; done\n";
  const std::vector<std::pair<std::string, std::string>> endings = {
      {"exit 1", draw_half + "exit 1\n"},
      {"nothing drawn, exit 0", "cat > /dev/null; exit 0\n"},
      {"killed", draw_half + "kill -9 $$\n"},
  };
  const fs::path gnuplot = dir_ / "bin" / "gnuplot";
  for (const auto& [what, body] : endings) {
    test::spit(gnuplot, "#!/bin/sh\n" + body);
    fs::permissions(gnuplot, fs::perms::owner_all);
    test::spit(dir_ / "p.svg", "previous plot");
    const auto r = bench_in(dir_, "in.off", {"--plot", "p.svg"},
                            "PATH=" + test::quoted((dir_ / "bin").string()) + ":\"$PATH\" ");
    EXPECT_EQ(r.exit_code, 1) << what << ": " << r.output;
    EXPECT_NE(r.output.find("--plot 'p.svg' not drawn"), std::string::npos) << what << r.output;
    EXPECT_EQ(r.output.find("plot written to"), std::string::npos) << what << ": " << r.output;
    EXPECT_EQ(test::slurp(dir_ / "p.svg"), "previous plot") << what << ": the plot was cut";
    EXPECT_EQ(test::listing(dir_), (std::vector<std::string>{"bin", "in.off", "p.svg"})) << what;
  }
}

}  // namespace
}  // namespace shellcontract
