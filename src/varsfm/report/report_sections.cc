#include "varsfm/report/report_sections.h"

#include <cmath>

#include <fmt/format.h>

#include "varsfm/report/html_text.h"

namespace varsfm {
namespace {

// 1234567 -> "1 234 567" (narrow no-break spaces, as in SI style).
std::string Count(size_t n) {
  std::string digits = std::to_string(n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += "\u202f";
    out += digits[i];
  }
  return out;
}

std::string Card(const std::string& label, const std::string& value, const std::string& note = "") {
  return fmt::format(
      "<div class=\"card\"><div class=\"label\">{}</div><div class=\"value\">{}"
      "</div>{}</div>",
      label, value, note.empty() ? "" : "<div class=\"note\">" + note + "</div>");
}

// The dense cloud's file, and how many views had a depth map and how many were redundant
// (dense_summary.json), where the run recorded them.
std::string DenseNote(const ReportData& data) {
  const auto count = [&](const char* key) -> size_t {
    const nlohmann::json& d = data.dense_summary;
    return d.contains(key) && d[key].is_number_unsigned() ? d[key].get<size_t>() : 0;
  };
  std::string note = "dense.ply";
  if (const size_t maps = count("depth_maps"); maps > 0) {
    note += ", " + Count(maps) + " depth maps";
    if (const size_t redundant = count("redundant_views"); redundant > 0)
      note += " (" + Count(redundant) + " views redundant)";
  }
  return note;
}

std::string ImageName(const ReportData& data, image_t id) {
  const ReportImage* image = data.FindImage(id);
  return image != nullptr ? EscapeHtml(image->name) : fmt::format("image {}", id);
}

// The initial pair and the outcome of its two-view self-calibration.
std::string InitialPairCard(const ReportData& data) {
  const nlohmann::json& s = data.summary;
  if (!s.contains("initial_pair") || !s["initial_pair"].is_array() ||
      s["initial_pair"].size() != 2 || !s["initial_pair"][0].is_number_unsigned() ||
      !s["initial_pair"][1].is_number_unsigned())
    return "";
  const std::string pair = ImageName(data, s["initial_pair"][0].get<image_t>()) + " &amp; " +
                           ImageName(data, s["initial_pair"][1].get<image_t>());
  std::string note = "self-calibration: well-posed";
  if (s.value("initial_calibration_degenerate", false)) {
    note = "<span class=\"warn\">self-calibration degenerate</span>";
    if (s.contains("initial_focal_prior_scale"))
      note += fmt::format(": prior focal length \u00d7{:.2f}, chosen by a third view",
                          s["initial_focal_prior_scale"].get<double>());
  }
  return Card("Initial pair", pair, note);
}

// The PSNR after each photo's exposure (pipeline/render.h) with `suffix`; empty in the summary of
// a run made before it was measured, and where the figure is null (an exact match).
std::string ExposurePsnr(const nlohmann::json& object, const char* key, const char* suffix) {
  if (!object.contains(key) || !object[key].is_number()) return "";
  return fmt::format("{:.2f}{}", object[key].get<double>(), suffix);
}

// "28.44 dB", its SSIM and coverage as a card's value and note; `means` is one of the renders'
// "held_out" / "source" objects.
std::string RenderMeansCard(const std::string& label, const nlohmann::json& means,
                            const std::string& what) {
  const int images = means.value("images", 0);
  if (images == 0) return "";
  return Card(fmt::format("{} ({})", label, images),
              fmt::format("{:.2f} dB", means.value("mean_psnr_db", 0.0)),
              ExposurePsnr(means, "mean_psnr_exposure_db", " dB after each photo's exposure; ") +
                  fmt::format("SSIM {:.3f}, covers {:.1f} % of the photos; {}",
                              means.value("mean_ssim", 0.0),
                              100 * means.value("mean_coverage", 0.0), what));
}

double Rms(const std::vector<double>& errors) {
  double sum = 0;
  for (const double e : errors) sum += e * e;
  return errors.empty() ? 0 : std::sqrt(sum / errors.size());
}

}  // namespace

std::string SummarySection(const ReportData& data, const ReportCharts& charts) {
  size_t registered = 0;
  for (const ReportImage& image : data.images) registered += image.registered;
  const double mean_track =
      data.num_points3D > 0 ? static_cast<double>(data.num_observations) / data.num_points3D : 0;
  std::string model = data.sparse_dir.lexically_relative(data.output).generic_string();
  std::string html = "<section id=\"summary\"><h2>Summary</h2><div class=\"cards\">";
  html += Card("Images registered", fmt::format("{} / {}", registered, data.images.size()),
               registered < data.images.size()
                   ? "<span class=\"warn\">" + std::to_string(data.images.size() - registered) +
                         " not registered (see the table)</span>"
                   : "all images in one model");
  html += Card("Model", EscapeHtml(model),
               data.num_models > 1
                   ? fmt::format("<span class=\"warn\">{} models in sparse/: this page shows "
                                 "this one</span>",
                                 data.num_models)
                   : "COLMAP format");
  html +=
      Card("3D points", Count(data.num_points3D), Count(data.num_observations) + " observations");
  html += Card("RMS reprojection error", fmt::format("{:.3f} px", Rms(data.observation_errors_px)));
  html += Card("Mean track length", fmt::format("{:.2f}", mean_track), "images per point");
  html += InitialPairCard(data);
  if (data.dense_points) html += Card("Dense points", Count(*data.dense_points), DenseNote(data));
  if (data.mesh_faces)
    html += Card("Mesh", Count(*data.mesh_faces) + " faces",
                 Count(data.mesh_vertices.value_or(0)) + " vertices, mesh.ply");
  if (data.glb_file_bytes > 0)
    html += Card("Textured model", fmt::format("{:.1f} MB", data.glb_file_bytes / 1e6),
                 fmt::format("model.glb (shown here: {:.1f} MB)", data.glb.size() / 1e6));
  if (data.summary.contains("matching_strategy") && data.summary["matching_strategy"].is_string())
    html += Card("Matching", EscapeHtml(data.summary["matching_strategy"].get<std::string>()),
                 Count(data.pairs.size()) + " verified pairs");
  html += "</div>";
  if (!charts.stage_times.empty()) html += "<h3>Time per stage</h3>" + charts.stage_times;
  if (!charts.mapping_times.empty()) html += "<h3>Inside the map stage</h3>" + charts.mapping_times;
  return html + "</section>";
}

std::string OverviewSection(const ReportData& data, const ReportCharts& charts,
                            const std::optional<ThreeJs>& three) {
  std::string viewer;
  if (three) {
    viewer = fmt::format(
        "<div id=\"viewer\"><canvas id=\"viewer-canvas\"></canvas>"
        "<p id=\"viewer-message\"></p><div id=\"camera-info\" hidden></div>"
        "<div id=\"viewer-toggles\"><label><input type=\"checkbox\" name=\"model\" checked> "
        "textured model</label><label><input type=\"checkbox\" name=\"points\" checked> "
        "points</label><label><input type=\"checkbox\" name=\"cameras\" checked> cameras"
        "</label></div><div id=\"viewer-legend\">{}</div></div>"
        "<p class=\"hint\">Drag to orbit, scroll to zoom, right-drag to pan; click a camera's "
        "photo (or an image in a chart or the table) for its figures. three.js r{} ({}).</p>",
        charts.focal_colorbar, EscapeHtml(three->revision), EscapeHtml(three->dir.string()));
  } else {
    viewer =
        "<div id=\"viewer\" class=\"unavailable\"><p id=\"viewer-message\">The 3D view needs "
        "three.js, which was not found when this report was made: install Debian's "
        "<code>libjs-three</code> (<code>scripts/install_deps.sh</code>) and run "
        "<code>varsfm report " +
        EscapeHtml(data.output.string()) + "</code> again.</p></div>";
  }
  return "<section id=\"overview\"><h2>The model and the cameras' focal lengths</h2>"
         "<div class=\"overview\"><div>" +
         viewer + "</div><div>" + charts.focal +
         "<p class=\"hint\">Every image has its own intrinsics. The right axis gives each focal "
         "length relative to the shortest; colours are those of the cameras in the 3D view. " +
         (FocalLengthsInPixels(data)
              ? std::string()
              : std::string("The photos have several sizes, so each focal length is given over "
                            "its photo's longer side, which compares fields of view. ")) +
         "\u00d7 marks an image not in the model.</p></div></div></section>";
}

std::string FiguresSection(const ReportCharts& charts) {
  std::string html =
      "<section id=\"intrinsics\"><h2>Distortion and principal point</h2>"
      "<div class=\"grid\">" +
      charts.k1 + charts.k2 + charts.principal_u + charts.principal_v + "</div></section>";
  html += "<section id=\"fit\"><h2>How well the model fits the photos</h2><div class=\"grid\">" +
          charts.error_per_image + charts.points_per_image + charts.error_histogram +
          charts.track_histogram + "</div></section>";
  if (!charts.match_matrix.empty()) {
    html += "<section id=\"matches\"><h2>Verified matches between image pairs</h2>" +
            charts.match_matrix +
            "<p class=\"hint\">Cell (i, j): inliers of the verified two-view geometry of images i "
            "and j (colour on a log scale; faint: too few for the mapper to use).</p></section>";
  }
  return html;
}

std::string RendersSection(const ReportData& data) {
  if (!data.summary.contains("renders") || !data.summary["renders"].is_object()) return "";
  const nlohmann::json& renders = data.summary["renders"];
  std::string html =
      "<section id=\"renders\"><h2>The textured model seen from the photos' cameras</h2>"
      "<div class=\"cards\">";
  if (renders.contains("held_out"))
    html +=
        RenderMeansCard("Held-out views", renders["held_out"], "kept out of densify and texture");
  if (renders.contains("source"))
    html += RenderMeansCard("Source views", renders["source"], "the texture comes from them");
  html += "</div>";
  std::string rows;
  for (const nlohmann::json& image : renders.value("images", nlohmann::json::array())) {
    if (!image.is_object()) continue;
    rows += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{:.2f}</td><td>{}</td><td>{:.3f}</td><td>{:.1f}</td>"
        "</tr>",
        EscapeHtml(image.value("name", std::string())),
        image.value("held_out", false) ? "held out" : "source", image.value("psnr_db", 0.0),
        ExposurePsnr(image, "psnr_exposure_db", ""), image.value("ssim", 0.0),
        100 * image.value("coverage", 0.0));
  }
  if (!rows.empty())
    html +=
        "<table class=\"images renders\"><thead><tr><th>image</th><th>view</th><th>PSNR (dB)</th>"
        "<th>PSNR after its exposure (dB)</th><th>SSIM</th><th>coverage (%)</th></tr></thead>"
        "<tbody>" +
        rows + "</tbody></table>";
  return html +
         "<p class=\"hint\">Each registered camera renders the textured model, compared with its "
         "photo over the pixels the model covers. Held-out photos took part in structure from "
         "motion only, so their figures say how the model looks from a new viewpoint; source "
         "views flatter, their texture was cut from those very photos.</p></section>";
}

std::string ImagesSection(const ReportData& data) {
  const std::vector<std::string> colors = FocalColors(data);
  const double shortest = FocalRange(data).first;
  const bool in_pixels = FocalLengthsInPixels(data);
  std::string rows;
  std::string failed;
  for (size_t i = 0; i < data.images.size(); ++i) {
    const ReportImage& image = data.images[i];
    const std::string name = EscapeHtml(image.name);
    const std::string thumb =
        image.thumbnail.empty()
            ? ""
            : fmt::format(
                  "<img{} alt=\"{}\" width=\"{}\" height=\"{}\" "
                  "src=\"data:image/jpeg;base64,{}\">",
                  image.registered ? fmt::format(" id=\"thumb-{}\"", image.image_id) : "", name,
                  image.thumbnail_width, image.thumbnail_height, image.thumbnail);
    const std::string data_image =
        image.registered ? fmt::format(" data-image=\"{}\"", image.image_id) : "";
    std::string figures;
    if (image.registered) {
      const Camera& c = image.camera;
      figures = fmt::format(
          "<td><span class=\"swatch\" style=\"background:{}\"></span>{:.1f}</td>"
          "<td>\u00d7{:.3f}</td><td>{:.4f}</td><td>{:.4f}</td><td>{:.1f}, {:.1f}</td>"
          "<td>{}</td><td>{:.3f}</td>",
          colors[i], c.focal(), shortest > 0 ? ComparableFocal(c, in_pixels) / shortest : 1.0,
          c.params[Camera::kK1], c.params[Camera::kK2], c.params[Camera::kU0],
          c.params[Camera::kV0], image.num_points3D, image.rms_error_px);
    } else {
      figures = "<td colspan=\"7\" class=\"warn\">" + EscapeHtml(image.failure) + "</td>";
      failed += "<li><b>" + name + "</b>: " + EscapeHtml(image.failure) + "</li>";
    }
    rows += fmt::format(
        "<tr{}><td>{}</td><td>{}</td><td>{}</td><td>{}x{}</td>{}<td>{}</td><td>{}</td></tr>",
        data_image, i + 1, thumb, name, image.width, image.height, figures,
        Count(image.num_keypoints), image.num_verified_pairs);
  }
  std::string html = "<section id=\"images\"><h2>Images</h2>";
  if (!failed.empty()) html += "<h3>Not registered</h3><ul class=\"failed\">" + failed + "</ul>";
  html +=
      "<table class=\"images\"><thead><tr><th>#</th><th>photo</th><th>name</th><th>size</th>"
      "<th>focal (px)</th><th>relative</th><th>k1</th><th>k2</th><th>principal point</th>"
      "<th>3D points</th><th>RMS (px)</th><th>features</th><th>verified pairs</th></tr></thead>"
      "<tbody>" +
      rows + "</tbody></table></section>";
  return html;
}

}  // namespace varsfm
