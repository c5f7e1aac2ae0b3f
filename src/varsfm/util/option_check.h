#pragma once
// Validation of option values. Every stage's options struct has a Check() (as COLMAP's and
// Ceres' options do) that the stage calls once where it starts, before it reads or writes
// anything, so a bad value fails at once with one line naming the option and what it accepts:
// "--ratio: expected a number in (0, 1], got nan". Options are named by their command-line flag
// where they have one, else by their field name. NaN and infinities are rejected for every
// floating-point option.
#include <cmath>
#include <concepts>
#include <string_view>

#include <fmt/format.h>

#include "varsfm/util/error.h"

namespace varsfm {

// Who calls a stage's options' Check(): the stage where it starts, or a caller that has done so
// already (`run` checks every stage's options before the first stage starts), so that each
// Check() runs once.
enum class OptionsCheck { kByStage, kDoneByCaller };

// A bad option value: a usage error (the command-line tool exits 2 for it, 1 for other errors).
class OptionError : public Error {
 public:
  using Error::Error;
};

// Throws OptionError "NAME: expected EXPECTED, got VALUE".
template <typename T>
[[noreturn]] void FailOption(std::string_view name, std::string_view expected, const T& value) {
  throw OptionError(fmt::format("{}: expected {}, got {}", name, expected, value));
}

namespace internal {

template <typename T>
constexpr std::string_view KindOf() {
  return std::integral<T> ? "an integer" : "a number";
}

template <typename T>
bool IsFinite(T value) {
  if constexpr (std::floating_point<T>) return std::isfinite(value);
  return true;
}

}  // namespace internal

// value >= min.
template <typename T, typename U>
void CheckAtLeast(std::string_view name, T value, U min) {
  if (!internal::IsFinite(value) || !(value >= static_cast<T>(min)))
    FailOption(name, fmt::format("{} >= {}", internal::KindOf<T>(), min), value);
}

// value > min.
template <typename T, typename U>
void CheckGreaterThan(std::string_view name, T value, U min) {
  if (!internal::IsFinite(value) || !(value > static_cast<T>(min)))
    FailOption(name, fmt::format("{} > {}", internal::KindOf<T>(), min), value);
}

// lo <= value <= hi.
template <typename T, typename U>
void CheckInRange(std::string_view name, T value, U lo, U hi) {
  if (!internal::IsFinite(value) || !(value >= static_cast<T>(lo) && value <= static_cast<T>(hi)))
    FailOption(name, fmt::format("{} in [{}, {}]", internal::KindOf<T>(), lo, hi), value);
}

// lo < value <= hi.
template <typename T, typename U>
void CheckInHalfOpenRange(std::string_view name, T value, U lo, U hi) {
  if (!internal::IsFinite(value) || !(value > static_cast<T>(lo) && value <= static_cast<T>(hi)))
    FailOption(name, fmt::format("{} in ({}, {}]", internal::KindOf<T>(), lo, hi), value);
}

// The ranges most options have, named for what they mean. The message is the general check's
// ("a number > 0").

// value > 0: a length, a threshold, a tolerance, a weight that must act.
template <typename T>
void CheckPositive(std::string_view name, T value) {
  CheckGreaterThan(name, value, 0);
}

// value >= 0: a count or weight where 0 turns the step off.
template <typename T>
void CheckNonNegative(std::string_view name, T value) {
  CheckAtLeast(name, value, 0);
}

// 0 <= value <= 1: a fraction, a ratio or a probability.
template <typename T>
void CheckFraction(std::string_view name, T value) {
  CheckInRange(name, value, 0, 1);
}

// Any finite value.
template <std::floating_point T>
void CheckFinite(std::string_view name, T value) {
  if (!std::isfinite(value)) FailOption(name, "a finite number", value);
}

}  // namespace varsfm
