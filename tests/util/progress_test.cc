#include "varsfm/util/progress.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <memory>
#include <sstream>
#include <thread>

namespace varsfm {
namespace {

// Routes spdlog's default logger into a string for the test's lifetime (stderr is no terminal
// under ctest, so Progress writes log lines).
class CapturedLog {
 public:
  explicit CapturedLog(spdlog::level::level_enum level) : previous_(spdlog::default_logger()) {
    auto logger = std::make_shared<spdlog::logger>(
        "captured", std::make_shared<spdlog::sinks::ostream_sink_mt>(stream_));
    logger->set_level(level);
    spdlog::set_default_logger(logger);
    spdlog::set_level(level);
  }
  ~CapturedLog() {
    spdlog::set_default_logger(previous_);
    spdlog::set_level(spdlog::level::info);
  }
  std::string text() const { return stream_.str(); }

 private:
  std::ostringstream stream_;
  std::shared_ptr<spdlog::logger> previous_;
};

TEST(Progress, LogsRateAndTimeLeftAboutEveryTenthOfTheWork) {
  CapturedLog log(spdlog::level::info);
  {
    Progress progress("work", 20);
    for (int i = 0; i < 20; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(30));  // a rate to show
      progress.Tick();
    }
  }
  const std::string text = log.text();
  size_t lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 10u) << text;
  EXPECT_NE(text.find("work: 2/20 ("), std::string::npos) << text;
  EXPECT_NE(text.find("/s, "), std::string::npos) << text;
  EXPECT_NE(text.find(" left)"), std::string::npos) << text;
  EXPECT_NE(text.find("work: 20/20"), std::string::npos) << text;
}

// Work done within the first instants shows no rate: it would be noise ("7.23e+05/s").
TEST(Progress, NoRateOverTheFirstInstants) {
  EXPECT_EQ(FormatRateAndEta(1, 2, 0.001), "");
  EXPECT_EQ(FormatRateAndEta(0, 2, 10.0), "");
  EXPECT_EQ(FormatRateAndEta(1, 2, 1.0), "1/s, 0:01 left");
  EXPECT_EQ(FormatRateAndEta(2, 2, 1.0), "2/s, 0:01");
}

TEST(Progress, QuietAboveInfo) {
  CapturedLog log(spdlog::level::warn);
  {
    Progress progress("work", 5);
    for (int i = 0; i < 5; ++i) progress.Tick();
  }
  EXPECT_TRUE(log.text().empty()) << log.text();
}

}  // namespace
}  // namespace varsfm
