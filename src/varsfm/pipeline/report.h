#pragma once
// `varsfm report OUT`: (re)builds OUT/report.html from what a run left in OUT
// (report/report.h). `varsfm run` calls it after its last stage.
#include "varsfm/report/report.h"

namespace varsfm {

// Writes the report and logs where it is and its size. Throws varsfm::Error (one line) as
// WriteReport does.
ReportSummary RunReport(const ReportOptions& options, OptionsCheck check = OptionsCheck::kByStage);

}  // namespace varsfm
