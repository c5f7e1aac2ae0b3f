// End to end through the command-line tool: a bad option value, an unknown option or a missing
// one is one line on stderr and exit code 2 (a usage error), before any file is touched; other
// failures one line and exit code 1; --help the full help.
#include <algorithm>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/test_data.h"

namespace varsfm {
namespace {

using testing::RunCommand;
using testing::ShellQuote;
using testing::TempDir;
using testing::VarsfmBinary;

struct Outcome {
  int code = 0;
  std::string stderr_text;
};

// Runs `varsfm ARGS` and keeps only what it writes on stderr.
Outcome RunVarsfm(const std::string& args) {
  Outcome outcome;
  outcome.code =
      RunCommand(fmt::format("( {} {} 2>&1 >/dev/null )", ShellQuote(VarsfmBinary()), args),
                 &outcome.stderr_text);
  return outcome;
}

// One line, ending in a newline, that starts with varsfm's error prefix and holds `expected`.
void ExpectOneLineError(const Outcome& outcome, int code, const std::string& expected) {
  EXPECT_EQ(outcome.code, code) << outcome.stderr_text;
  EXPECT_EQ(std::count(outcome.stderr_text.begin(), outcome.stderr_text.end(), '\n'), 1)
      << outcome.stderr_text;
  EXPECT_EQ(outcome.stderr_text.rfind("varsfm: error: ", 0), 0u) << outcome.stderr_text;
  EXPECT_NE(outcome.stderr_text.find(expected), std::string::npos) << outcome.stderr_text;
}

class CommandLineErrors : public ::testing::Test {
 protected:
  CommandLineErrors() : tmp_("cli_errors"), workspace_(ShellQuote(tmp_.path() / "ws.db")) {}
  TempDir tmp_;
  std::string workspace_;  // never created: every error here comes before it is opened
};

TEST_F(CommandLineErrors, NanRatioIsRefused) {
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --ratio nan"), 2,
                     "--ratio: expected a number in (0, 1], got nan");
}

TEST_F(CommandLineErrors, NegativeThreadsAreRefused) {
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --threads -3"), 2,
                     "--threads: expected an integer >= 0, got -3");
}

// A negative or too large unsigned value was wrapped or clamped to the largest one in silence.
TEST_F(CommandLineErrors, NegativeOrOverflowingSeedIsRefused) {
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --seed -1"), 2,
                     "--seed: expected an integer from 0 to 18446744073709551615, got -1");
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --seed 99999999999999999999"),
                     2,
                     "--seed: expected an integer from 0 to 18446744073709551615, got "
                     "99999999999999999999");
  ExpectOneLineError(RunVarsfm("densify --sparse s --images i --output o --seed 1e3"), 2,
                     "--seed: expected an integer from 0 to 18446744073709551615, got 1e3");
}

TEST_F(CommandLineErrors, UnknownLogLevelIsRefused) {
  ExpectOneLineError(RunVarsfm("--log-level bogus match --workspace " + workspace_), 2,
                     "--log-level: expected trace, debug, info, warn, error or off, got bogus");
}

// The main command's options are taken after the subcommand too (`varsfm run IN OUT --quiet`
// was a usage error); an option neither knows still is.
TEST_F(CommandLineErrors, LogOptionsAfterTheSubcommandAreTaken) {
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --quiet"), 1,
                     "does not exist");
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --log-level bogus"), 2,
                     "--log-level: expected trace, debug, info, warn, error or off, got bogus");
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --bogus"), 2,
                     "not expected: --bogus");
}

TEST_F(CommandLineErrors, ZeroOverlapNamesItsRangeReadably) {
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --overlap 0"), 2,
                     "--overlap: expected an integer >= 1, got 0");
}

TEST_F(CommandLineErrors, UnknownStrategyAndStageNameTheirChoices) {
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --strategy bogus"), 2,
                     "--strategy: expected exhaustive, sequential, retrieval or auto, got bogus");
  ExpectOneLineError(RunVarsfm(fmt::format("run {} {} --until everything", ShellQuote(tmp_.path()),
                                           ShellQuote(tmp_.path() / "out"))),
                     2, "--until: expected sparse, dense, mesh or texture, got everything");
}

TEST_F(CommandLineErrors, ParseErrorsAreOneLine) {
  ExpectOneLineError(RunVarsfm("match"), 2, "--workspace is required");
  ExpectOneLineError(RunVarsfm("match --workspace " + workspace_ + " --bogus"), 2, "--bogus");
}

TEST_F(CommandLineErrors, InfiniteDenseThresholdIsRefused) {
  ExpectOneLineError(RunVarsfm("densify --sparse a --images b --output c --min-zncc inf"), 2,
                     "--min-zncc: expected a number in [-1, 1], got inf");
}

TEST_F(CommandLineErrors, MissingPhotoFolderOfMapIsAnError) {
  ExpectOneLineError(RunVarsfm(fmt::format("map --workspace {} --output {} --images {}", workspace_,
                                           ShellQuote(tmp_.path() / "out"),
                                           ShellQuote(tmp_.path() / "nonexistent"))),
                     1, "image folder");
  EXPECT_FALSE(std::filesystem::exists(tmp_.path() / "out"));
}

// `run` checks every stage's options before it creates anything.
TEST_F(CommandLineErrors, RunWithABadOptionCreatesNothing) {
  const auto out = tmp_.path() / "out";
  ExpectOneLineError(
      RunVarsfm(fmt::format("run {} {} --threads -3", ShellQuote(tmp_.path()), ShellQuote(out))), 2,
      "--threads: expected an integer >= 0, got -3");
  EXPECT_FALSE(std::filesystem::exists(out));
}

// An output folder that cannot be created (here: under a file) is named in a one-line error.
TEST_F(CommandLineErrors, OutputThatCannotBeCreatedIsAOneLineError) {
  const auto file = tmp_.path() / "file";
  std::ofstream(file) << "x";
  ExpectOneLineError(
      RunVarsfm(fmt::format("run {} {}", ShellQuote(tmp_.path()), ShellQuote(file / "out"))), 1,
      (file / "out").string() + ": cannot create");
}

TEST_F(CommandLineErrors, APhotoGivenForTheFolderAndAFolderForTheVideoAreNamed) {
  const auto photo = tmp_.path() / "a.jpg";
  std::ofstream(photo) << "x";
  ExpectOneLineError(
      RunVarsfm(fmt::format("run {} {}", ShellQuote(photo), ShellQuote(tmp_.path() / "out"))), 1,
      "is a photo: give the folder of the photos");
  ExpectOneLineError(RunVarsfm(fmt::format("extract --workspace {} --video {}", workspace_,
                                           ShellQuote(tmp_.path()))),
                     1, "is a folder: give a video file");
  EXPECT_FALSE(std::filesystem::exists(tmp_.path() / "out"));
}

TEST_F(CommandLineErrors, HelpIsTheFullHelp) {
  std::string help;
  ASSERT_EQ(RunCommand(ShellQuote(VarsfmBinary()) + " match --help", &help), 0) << help;
  EXPECT_GT(std::count(help.begin(), help.end(), '\n'), 10) << help;
  EXPECT_NE(help.find("--ratio"), std::string::npos) << help;
}

}  // namespace
}  // namespace varsfm
