#pragma once
// Logging goes through spdlog's default logger (stderr). The command-line tool sets the level.
#include <spdlog/spdlog.h>

namespace varsfm {
using spdlog::debug;
using spdlog::error;
using spdlog::info;
using spdlog::warn;
}  // namespace varsfm
