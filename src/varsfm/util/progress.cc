#include "varsfm/util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "varsfm/util/log.h"

namespace varsfm {

namespace {

// A terminal bar is redrawn at most this often: parallel loops tick thousands of times a second.
constexpr auto kRedrawInterval = std::chrono::milliseconds(100);
constexpr double kMinRateSeconds = 0.05;

std::string FormatDuration(double seconds) {
  const auto s = static_cast<long>(seconds + 0.5);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

}  // namespace

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)),
      total_(total),
      tty_(isatty(fileno(stderr)) != 0),
      enabled_(spdlog::should_log(spdlog::level::info)),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { Finish(); }

void Progress::Tick(size_t n, const std::string& status) {
  const size_t done = done_.fetch_add(n) + n;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!status.empty()) status_ = status;
  Draw(done, status_);
}

void Progress::SetStatus(const std::string& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  status_ = status;
  Draw(done_.load(), status_);
}

void Progress::Finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  if (enabled_ && tty_) {
    Draw(done_.load(), status_, /*force=*/true);  // the last state, whatever was skipped
    std::fputc('\n', stderr);
  }
  finished_ = true;
}

std::string Progress::RateAndEta(size_t done) const {
  return FormatRateAndEta(
      done, total_,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
}

void Progress::Draw(size_t done, const std::string& status, bool force) {
  if (finished_ || !enabled_) return;
  const std::string rate = RateAndEta(done);
  if (tty_) {
    const auto now = std::chrono::steady_clock::now();
    if (!force && done < total_ && now - last_draw_ < kRedrawInterval) return;
    last_draw_ = now;
    constexpr int kWidth = 30;
    const double fraction = total_ ? std::min(1.0, static_cast<double>(done) / total_) : 1.0;
    const int filled = static_cast<int>(fraction * kWidth);
    std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu %s %s\033[K", label_.c_str(), filled,
                 "##############################", kWidth - filled, "", done, total_, rate.c_str(),
                 status.c_str());
    std::fflush(stderr);
    return;
  }
  const size_t decile = total_ ? done * 10 / total_ : 10;
  if (decile > last_logged_decile_ || done == total_) {
    last_logged_decile_ = decile;
    info("{}: {}/{}{} {}", label_, done, total_, rate.empty() ? "" : " (" + rate + ")", status);
  }
}

std::string FormatRateAndEta(size_t done, size_t total, double elapsed_seconds) {
  if (done == 0 || elapsed_seconds < kMinRateSeconds) return "";
  const double rate = done / elapsed_seconds;
  if (done >= total) return fmt::format("{:.3g}/s, {}", rate, FormatDuration(elapsed_seconds));
  return fmt::format("{:.3g}/s, {} left", rate, FormatDuration((total - done) / rate));
}

}  // namespace varsfm
