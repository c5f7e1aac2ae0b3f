#pragma once
// Logging goes through spdlog's default logger (stderr). The command-line tool sets the level.
#include <spdlog/spdlog.h>

#include "varsfm/util/enum_names.h"

namespace varsfm {
using spdlog::debug;
using spdlog::error;
using spdlog::info;
using spdlog::warn;

// The names `--log-level` takes.
inline constexpr EnumName<spdlog::level::level_enum> kLogLevelNames[] = {
    {spdlog::level::trace, "trace"}, {spdlog::level::debug, "debug"}, {spdlog::level::info, "info"},
    {spdlog::level::warn, "warn"},   {spdlog::level::err, "error"},   {spdlog::level::off, "off"}};
}  // namespace varsfm
