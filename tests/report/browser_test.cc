// The report in a real browser: headless Chromium (software WebGL, SwiftShader) opens the page
// made by `varsfm report` for a synthetic run; the page must reach data-viewer="ready" with no
// script error, and its screenshot must show the 3D view drawn, the red textured model
// included. Skipped with a message when chromium is not installed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>

#include <fmt/format.h>

#include "report/synthetic_output.h"
#include "support/test_data.h"
#include "varsfm/image/image_file.h"
#include "varsfm/report/three_js.h"

namespace varsfm {
namespace {

using testing::RunCommand;
using testing::ShellQuote;
using testing::TempDir;
using testing::VarsfmBinary;
using testing::WriteSyntheticOutput;

// The browser: $VARSFM_CHROMIUM, else the first of Debian's chromium and its usual names.
std::string FindChromium() {
  if (const char* env = std::getenv("VARSFM_CHROMIUM"); env != nullptr && *env != '\0') return env;
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    std::string path;
    if (RunCommand(fmt::format("command -v {}", name), &path) == 0 && !path.empty())
      return path.substr(0, path.find('\n'));
  }
  return "";
}

#define REQUIRE_CHROMIUM(variable)                                                      \
  const std::string variable = FindChromium();                                          \
  if (variable.empty())                                                                 \
  GTEST_SKIP() << "chromium is not installed (scripts/install_deps.sh --with-colmap); " \
                  "skipping the browser test"

constexpr int kWidth = 1400, kHeight = 1300;

// Runs headless Chromium on `page` with `action` (--dump-dom, or --screenshot=FILE); returns
// its stdout. Software WebGL; a profile of its own so that tests can run side by side; the
// virtual time budget lets the page's scripts and its first frames run to the end.
std::string Chromium(const std::string& chromium, const std::filesystem::path& page,
                     const std::filesystem::path& profile, const std::string& action,
                     const std::string& fragment = "") {
  const std::string command = fmt::format(
      "{} --headless --no-sandbox --disable-dev-shm-usage --use-gl=angle --use-angle=swiftshader "
      "--enable-unsafe-swiftshader --hide-scrollbars --no-first-run --user-data-dir={} "
      "--window-size={},{} --virtual-time-budget=20000 {} {} 2>/dev/null",
      ShellQuote(chromium), ShellQuote(profile), kWidth, kHeight, action,
      ShellQuote("file://" + page.string() + fragment));
  std::string out;
  EXPECT_EQ(RunCommand(command, &out), 0) << command;
  return out;
}

// The value of attribute `name` on the page's <html> element in Chromium's DOM dump.
std::string HtmlAttribute(const std::string& dom, const std::string& name) {
  const size_t html = dom.find("<html");
  const size_t at = dom.find(" " + name + "=\"", html);
  if (html == std::string::npos || at == std::string::npos || at > dom.find('>', html)) return "";
  const size_t begin = at + name.size() + 3;
  return dom.substr(begin, dom.find('"', begin) - begin);
}

TEST(ReportInBrowser, ViewerDrawsTheCamerasPointsAndTexturedModel) {
  REQUIRE_CHROMIUM(chromium);
  if (!LoadThreeJs()) GTEST_SKIP() << "three.js (libjs-three) is not installed; skipping";
  TempDir tmp("report_browser");
  const auto out = tmp.path() / "out";
  WriteSyntheticOutput(out);
  std::string log;
  ASSERT_EQ(
      RunCommand(fmt::format("{} report {}", ShellQuote(VarsfmBinary()), ShellQuote(out)), &log), 0)
      << log;

  const std::string dom =
      Chromium(chromium, out / "report.html", tmp.path() / "profile", "--dump-dom");
  EXPECT_EQ(HtmlAttribute(dom, "data-viewer"), "ready");
  EXPECT_EQ(HtmlAttribute(dom, "data-errors"), "0")
      << dom.substr(std::min(dom.size(), dom.find("id=\"page-errors\"")), 400);
  std::istringstream rect(HtmlAttribute(dom, "data-canvas"));
  int left = 0, top = 0, width = 0, height = 0;
  rect >> left >> top >> width >> height;
  ASSERT_GT(width, 100);
  ASSERT_GT(height, 100);
  ASSERT_LE(left + width, kWidth);
  ASSERT_LE(top + height, kHeight);

  // A camera selected (as a click on it does, here through the page's #camera= link): its
  // photo and figures are shown.
  const std::string selected =
      Chromium(chromium, out / "report.html", tmp.path() / "profile", "--dump-dom", "#camera=2");
  const size_t info = selected.find("id=\"camera-info\"");
  ASSERT_NE(info, std::string::npos);
  const std::string panel = selected.substr(info, selected.find("</div>", info) - info);
  EXPECT_EQ(panel.find("hidden"), std::string::npos) << panel;
  EXPECT_NE(panel.find("<b>photo_02.png</b>"), std::string::npos) << panel;
  EXPECT_NE(panel.find("data:image/jpeg;base64,"), std::string::npos);

  const auto png = tmp.path() / "shot.png";
  Chromium(chromium, out / "report.html", tmp.path() / "profile",
           "--screenshot=" + ShellQuote(png));
  const cv::Mat shot = ReadImagePixels(png, ColorMode::kColor);
  ASSERT_EQ(shot.cols, kWidth);
  size_t drawn = 0, red = 0;
  for (int y = top; y < top + height; ++y)
    for (int x = left; x < left + width; ++x) {
      const cv::Vec3b bgr = shot.at<cv::Vec3b>(y, x);
      // Anything off the view's background (#3a3f47) is drawn; the model's texture is red.
      drawn += std::abs(bgr[2] - 0x3a) + std::abs(bgr[1] - 0x3f) + std::abs(bgr[0] - 0x47) > 40;
      red += bgr[2] > 170 && bgr[1] < 90 && bgr[0] < 90;
    }
  const double area = static_cast<double>(width) * height;
  EXPECT_GT(drawn / area, 0.05) << drawn << " drawn pixels";
  EXPECT_GT(red / area, 0.01) << red << " red pixels: the textured model is not drawn";
}

TEST(ReportInBrowser, WithoutThreeJsThePageStillWorks) {
  REQUIRE_CHROMIUM(chromium);
  TempDir tmp("report_browser_no_three");
  const auto out = tmp.path() / "out";
  WriteSyntheticOutput(out, {.with_glb = false});
  std::filesystem::create_directories(tmp.path() / "none");
  std::string log;
  ASSERT_EQ(RunCommand(fmt::format("{} report {} --three-js {}", ShellQuote(VarsfmBinary()),
                                   ShellQuote(out), ShellQuote(tmp.path() / "none")),
                       &log),
            0)
      << log;
  const std::string dom =
      Chromium(chromium, out / "report.html", tmp.path() / "profile", "--dump-dom");
  EXPECT_EQ(HtmlAttribute(dom, "data-viewer"), "absent");
  EXPECT_EQ(HtmlAttribute(dom, "data-errors"), "0");
  EXPECT_NE(dom.find("The 3D view needs three.js"), std::string::npos);
  EXPECT_NE(dom.find("Focal length per image"), std::string::npos);
}

}  // namespace
}  // namespace varsfm
