#pragma once
// Test helper for the options Check() tests: a bad value of one option, and the check that a
// Check() refuses it with OptionError whose message starts with the option's name.
#include <functional>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "varsfm/util/option_check.h"

namespace varsfm::testing {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

template <typename Options>
struct BadValue {
  std::string option;  // the name the message must start with
  std::function<void(Options&)> spoil;
};

// Runs `check`; a bad value must make it throw OptionError starting "<option>: expected ".
// Returns the message ("" when nothing was thrown) for further expectations.
inline std::string ExpectRejected(const std::function<void()>& check, const std::string& option) {
  try {
    check();
    ADD_FAILURE() << option << ": a bad value was accepted";
  } catch (const OptionError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(option + ": expected ", 0), 0u) << message;
    return message;
  }
  return "";
}

}  // namespace varsfm::testing
