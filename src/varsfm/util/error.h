#pragma once
// The one exception type varsfm throws for bad input or a run that cannot proceed. Its message
// is a single line meant for the user; the command-line tool prints it and exits non-zero.
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace varsfm {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// Throws varsfm::Error with a fmt-formatted message.
template <typename... Args>
[[noreturn]] void Fail(fmt::format_string<Args...> format, Args&&... args) {
  throw Error(fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace varsfm
