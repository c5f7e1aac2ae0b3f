#include "varsfm/report/report.h"

#include "varsfm/report/html_report.h"
#include "varsfm/report/three_js.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"

namespace varsfm {

void ReportOptions::Check() const {
  if (output.empty()) Fail("report: no output folder given");
  if (data.thumbnail_width < 16 || data.thumbnail_width > 1024)
    Fail("report: thumbnail width {} is outside 16-1024", data.thumbnail_width);
  if (data.thumbnail_quality < 1 || data.thumbnail_quality > 100)
    Fail("report: JPEG quality {} is outside 1-100", data.thumbnail_quality);
  if (data.max_view_points == 0) Fail("report: the 3D view needs at least one point");
}

ReportSummary WriteReport(const ReportOptions& options) {
  options.Check();
  const std::optional<ThreeJs> three = LoadThreeJs(options.three_js_dir);
  if (!three) warn("report: three.js not found (install libjs-three); the report has no 3D view");
  std::string html;
  try {
    html = ReportHtml(CollectReportData(options.output, options.data), three);
  } catch (const nlohmann::json::exception& e) {
    // summary.json parsed, but a value has another type than map and run write.
    Fail("{}: unexpected content ({})", (options.output / "summary.json").string(), e.what());
  }

  ReportSummary result;
  result.file = options.output / "report.html";
  result.bytes = html.size();
  result.has_3d_view = three.has_value();
  WriteFileAtomically(result.file, [&](std::ostream& out) {
    out.write(html.data(), static_cast<std::streamsize>(html.size()));
  });
  return result;
}

}  // namespace varsfm
