#include "varsfm/util/progress.h"

#include <unistd.h>

#include <cstdio>

#include "varsfm/util/log.h"

namespace varsfm {

Progress::Progress(std::string label, size_t total)
    : label_(std::move(label)), total_(total), tty_(isatty(fileno(stderr)) != 0) {}

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
  finished_ = true;
  if (tty_) std::fputc('\n', stderr);
}

void Progress::Draw(size_t done, const std::string& status) {
  if (finished_) return;
  if (tty_) {
    constexpr int kWidth = 30;
    const double fraction = total_ ? static_cast<double>(done) / total_ : 1.0;
    const int filled = static_cast<int>(fraction * kWidth);
    std::fprintf(stderr, "\r%s [%.*s%*s] %zu/%zu %s\033[K", label_.c_str(), filled,
                 "##############################", kWidth - filled, "", done, total_,
                 status.c_str());
    std::fflush(stderr);
    return;
  }
  const size_t decile = total_ ? done * 10 / total_ : 10;
  if (decile > last_logged_decile_ || done == total_) {
    last_logged_decile_ = decile;
    info("{}: {}/{} {}", label_, done, total_, status);
  }
}

}  // namespace varsfm
