#include "varsfm/report/html_report.h"

#include "varsfm/report/base64.h"
#include "varsfm/report/deflate.h"
#include "varsfm/report/html_text.h"
#include "varsfm/report/report_charts.h"
#include "varsfm/report/report_sections.h"
#include "varsfm/report/viewer_scene.h"
#include "varsfm/report/viewer_script.h"

namespace varsfm {
namespace {

constexpr const char* kStyle = R"CSS(
:root { --ink: #1d2026; --muted: #5f6672; --line: #d9dce1; --warn: #b3261e; }
body { font: 14px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; color: var(--ink);
       margin: 0 auto; padding: 12px 24px 40px; max-width: 1400px; background: #f7f8fa; }
h1 { font-size: 22px; margin: 4px 0; } h2 { font-size: 17px; margin: 22px 0 8px; }
h3 { font-size: 14px; margin: 12px 0 4px; color: var(--muted); }
header p { margin: 0; color: var(--muted); }
section { background: #fff; border: 1px solid var(--line); border-radius: 6px;
          padding: 4px 16px 12px; margin-top: 14px; }
.cards { display: flex; flex-wrap: wrap; gap: 8px; }
.card { border: 1px solid var(--line); border-radius: 5px; padding: 6px 10px; min-width: 130px; }
.card .label { font-size: 12px; color: var(--muted); }
.card .value { font-size: 18px; font-weight: 600; }
.card .note { font-size: 12px; color: var(--muted); }
.warn { color: var(--warn); }
.overview { display: grid; grid-template-columns: minmax(0, 1fr) 640px; gap: 16px;
            align-items: start; }
#viewer { position: relative; height: 520px; background: #3a3f47; border-radius: 5px;
          overflow: hidden; }
#viewer-canvas { width: 100%; height: 100%; display: block; }
#viewer.unavailable { display: flex; align-items: center; justify-content: center; }
#viewer-message { color: #e8e8e8; padding: 0 24px; position: absolute; top: 8px; margin: 0; }
#viewer.unavailable #viewer-message { position: static; }
#viewer-message code { color: #fde725; }
#viewer-toggles { position: absolute; left: 8px; bottom: 6px; color: #e8e8e8; font-size: 12px; }
#viewer-toggles label { margin-right: 10px; }
#viewer-legend { position: absolute; right: 8px; bottom: 4px; background: rgba(255,255,255,.85);
                 border-radius: 4px; padding: 2px 6px; }
#camera-info { position: absolute; top: 8px; right: 8px; background: rgba(255,255,255,.94);
               border-radius: 5px; padding: 8px; font-size: 12px; max-width: 260px; }
#camera-info img { display: block; width: 240px; margin: 4px 0; }
#camera-info th { text-align: left; font-weight: normal; color: var(--muted); padding-right: 6px; }
.hint { font-size: 12px; color: var(--muted); margin: 4px 0; }
.grid { display: flex; flex-wrap: wrap; gap: 8px 24px; }
svg.chart text { font-size: 11px; fill: var(--ink); }
svg.chart text.title { font-size: 13px; font-weight: 600; }
svg.chart text.tick { fill: var(--muted); }
svg.chart .grid { stroke: #e6e8eb; }
svg.chart .reference { stroke: #888; stroke-dasharray: 4 3; }
svg.chart .line { fill: none; stroke-width: 1.5; }
svg.chart .missing { fill: var(--warn); font-size: 14px; cursor: default; }
svg.chart .mark[data-image] { cursor: pointer; }
svg.chart .mark.selected { stroke: #000; stroke-width: 2; }
svg .matrix-bg { fill: #eef0f3; }
svg.colorbar text { font-size: 11px; fill: var(--ink); }
table.images { border-collapse: collapse; width: 100%; font-size: 13px; }
table.images th, table.images td { border-bottom: 1px solid var(--line); padding: 3px 6px;
                                   text-align: right; }
table.images td:nth-child(3), table.images th:nth-child(3) { text-align: left; }
table.images img { display: block; max-width: 160px; height: auto; }
table.images tr[data-image] { cursor: pointer; }
table.renders { width: auto; margin-top: 8px; }
table.renders td:first-child, table.renders th:first-child { text-align: left; }
table.renders td:nth-child(3), table.renders th:nth-child(3) { text-align: right; }
table.images tr.selected { background: #fff6c8; }
.swatch { display: inline-block; width: 10px; height: 10px; border-radius: 2px;
          margin-right: 5px; }
ul.failed { margin: 4px 0 10px; }
#page-errors { background: #fde2e1; color: var(--warn); padding: 6px 10px; border-radius: 4px; }
@media (max-width: 1100px) { .overview { grid-template-columns: 1fr; } }
)CSS";

// Before anything else runs: every script error is counted in <html data-errors> and shown, so
// a reader (and the browser test) sees when the page did not work.
constexpr const char* kErrorScript = R"JS(
window.varsfmErrors = [];
function varsfmError(text) {
  window.varsfmErrors.push(String(text));
  document.documentElement.setAttribute('data-errors', String(window.varsfmErrors.length));
  var box = document.getElementById('page-errors');
  if (box) { box.hidden = false; box.textContent = 'Errors: ' + window.varsfmErrors.join('; '); }
}
window.addEventListener('error', function (e) { varsfmError(e.message || 'error'); });
window.addEventListener('unhandledrejection', function (e) { varsfmError(e.reason); });
(function () {
  var original = console.error;
  console.error = function () {
    varsfmError(Array.prototype.join.call(arguments, ' '));
    original.apply(console, arguments);
  };
})();
)JS";

std::string Script(const std::string& code) { return "<script>" + code + "</script>\n"; }

}  // namespace

std::string ReportHtml(const ReportData& data, const std::optional<ThreeJs>& three) {
  const ReportCharts charts = DrawReportCharts(data);
  const std::string name = data.output.filename().empty()
                               ? data.output.parent_path().filename().string()
                               : data.output.filename().string();
  std::string html =
      "<!DOCTYPE html>\n<html lang=\"en\" data-errors=\"0\" data-viewer=\"" +
      std::string(three ? "pending" : "absent") +
      "\">\n<head>\n<meta charset=\"utf-8\">\n<title>varsfm report: " + EscapeHtml(name) +
      "</title>\n<style>" + kStyle + "</style>\n" + Script(kErrorScript) + "</head>\n<body>\n";
  html += "<header><h1>varsfm report: " + EscapeHtml(name) + "</h1><p>" +
          EscapeHtml(data.output.string()) + "</p></header>\n<p id=\"page-errors\" hidden></p>\n";
  html += SummarySection(data, charts) + "\n";
  html += OverviewSection(data, charts, three) + "\n";
  html += FiguresSection(charts) + "\n";
  html += RendersSection(data) + "\n";
  html += ImagesSection(data) + "\n";
  if (three) {
    html += "<script type=\"application/json\" id=\"varsfm-scene\">" +
            JsonForScript(ViewerSceneJson(data)) + "</script>\n";
    // zlib-compressed (the browser's DecompressionStream("deflate") reads it): the quantised
    // geometry shrinks by a third (docs/measurements.md).
    if (!data.glb.empty())
      html +=
          "<script type=\"application/octet-stream\" id=\"varsfm-glb\" "
          "data-encoding=\"deflate\">" +
          Base64Encode(Deflate(data.glb)) + "</script>\n";
    html += Script(three->core) + Script(three->orbit_controls) + Script(three->gltf_loader);
    html += Script(ViewerScript());
  }
  return html + "</body>\n</html>\n";
}

}  // namespace varsfm
