#pragma once
// Progress reporting: a redrawn bar with the rate and the estimated time left when stderr is a
// terminal, otherwise plain log lines at roughly every 10 %. Nothing is shown when the log level
// is above info (--quiet, --log-level warn). Thread-safe Tick(), so parallel loops can report
// as they finish items.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace varsfm {

class Progress {
 public:
  Progress(std::string label, size_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Marks `n` more items done; `status` (optional) is shown after the counter.
  void Tick(size_t n = 1, const std::string& status = "");
  // Replaces the status text without advancing.
  void SetStatus(const std::string& status);
  void Finish();

 private:
  // `force`: draw even within the terminal's redraw interval.
  void Draw(size_t done, const std::string& status, bool force = false);
  // "12.3/s, 0:42 left" once a rate can be estimated, else "".
  std::string RateAndEta(size_t done) const;

  std::string label_;
  size_t total_;
  std::atomic<size_t> done_{0};
  std::mutex mutex_;
  bool tty_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  bool finished_ = false;
  size_t last_logged_decile_ = 0;
  std::string status_;
};

// "R/s, T left" (or "R/s, T" once done = total) after `elapsed_seconds`; "" before any work is
// done and over the first instants, where a rate is noise (a first item that had nothing to do
// gave "7.23e+05/s").
std::string FormatRateAndEta(size_t done, size_t total, double elapsed_seconds);

}  // namespace varsfm
