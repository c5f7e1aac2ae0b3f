#pragma once
// OUT/report.html: one file that shows what a run did and opens offline in any browser (see
// html_report.h): the summary, the 3D view of cameras, points and textured model, each image's
// intrinsics in capture order, the fit's figures and the pair-match matrix.
#include <cstddef>
#include <filesystem>

#include "varsfm/report/report_data.h"
#include "varsfm/util/option_check.h"

namespace varsfm {

struct ReportOptions {
  std::filesystem::path output;  // OUT: read, and report.html written into it
  ReportDataOptions data;
  // three.js's folder (three_js.h); empty: $VARSFM_THREE_JS_DIR, else Debian's libjs-three.
  std::filesystem::path three_js_dir;

  void Check() const;  // throws OptionError (util/option_check.h) for a bad value
};

struct ReportSummary {
  std::filesystem::path file;  // OUT/report.html
  size_t bytes = 0;
  bool has_3d_view = false;  // three.js was found and inlined
};

// Writes OUT/report.html (through a temporary file renamed into place, so an existing report is
// replaced only by a complete one). Throws varsfm::Error as CollectReportData does, or when the
// file cannot be written.
ReportSummary WriteReport(const ReportOptions& options,
                          OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
