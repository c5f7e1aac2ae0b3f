#include "varsfm/pipeline/report.h"

#include "varsfm/util/log.h"
#include "varsfm/util/path_lock.h"
#include "varsfm/util/timer.h"

namespace varsfm {

ReportSummary RunReport(const ReportOptions& options, OptionsCheck check) {
  const OutputFolderLock output_lock(options.output);
  Timer timer;
  const ReportSummary result = WriteReport(options, check);
  info("report: wrote {} ({:.1f} MB{}) in {:.2f} s", result.file.string(), result.bytes / 1e6,
       result.has_3d_view ? "" : ", no 3D view: three.js not found", timer.Seconds());
  return result;
}

}  // namespace varsfm
