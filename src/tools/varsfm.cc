// varsfm command-line tool: a thin layer over the library. Each subcommand parses its options
// and calls one function of src/varsfm/pipeline; a varsfm::Error becomes one line on stderr and
// exit code 1, a usage error exit code 2 (CLI11's own codes for parse errors).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace {

void SetLogLevel(const std::string& level) {
  spdlog::set_level(spdlog::level::from_str(level));
  spdlog::set_pattern("[%H:%M:%S] %^%l%$ %v");
}

}  // namespace

int main(int argc, char** argv) {
  SetLogLevel("info");
  CLI::App app{"varsfm: structure from motion for cameras with varying intrinsics"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "varsfm 0.1.0");
  app.add_option_function<std::string>("--log-level", SetLogLevel,
                                       "trace|debug|info|warn|error|off (before the subcommand)");

  // ---- Subcommands: each registers its options and a callback into the pipeline. ----

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const varsfm::Error& e) {
    std::fprintf(stderr, "varsfm: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "varsfm: unexpected error: %s\n", e.what());
    return 1;
  }
  return 0;
}
