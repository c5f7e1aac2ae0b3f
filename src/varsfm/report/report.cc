#include "varsfm/report/report.h"

#include "varsfm/report/html_report.h"
#include "varsfm/report/three_js.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

void ReportOptions::Check() const {
  if (output.empty()) FailOption("output", "the output folder of a run", "''");
  data.Check();
}

ReportSummary WriteReport(const ReportOptions& options, OptionsCheck check) {
  if (check == OptionsCheck::kByStage) options.Check();
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
