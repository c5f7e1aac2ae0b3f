#pragma once
// The report page: one HTML file with everything inline (styles, SVG charts, thumbnails, the
// scene data, three.js and the textured model in base64), so it opens offline from anywhere.
#include <optional>
#include <string>

#include "varsfm/report/report_data.h"
#include "varsfm/report/three_js.h"

namespace varsfm {

// `three`: the scripts to inline for the 3D view; nothing: the page says what to install.
std::string ReportHtml(const ReportData& data, const std::optional<ThreeJs>& three);

}  // namespace varsfm
