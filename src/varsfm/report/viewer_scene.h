#pragma once
// What the report's 3D view draws, as the JSON the page's viewer script reads: every registered
// camera (centre, the four corners of its frustum, colour on the focal-length scale and its
// figures), the displayed points (base64 float32 coordinates and uint8 colours) and a framing
// (target, eye, up) that looks at the scene from behind the cameras with the photos' up.
#include <nlohmann/json.hpp>

#include "varsfm/report/report_data.h"

namespace varsfm {

nlohmann::json ViewerSceneJson(const ReportData& data);

}  // namespace varsfm
