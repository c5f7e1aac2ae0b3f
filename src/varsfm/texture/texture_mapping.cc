#include "varsfm/texture/texture_mapping.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "varsfm/camera/image_size.h"
#include "varsfm/geometry/rasterizer.h"
#include "varsfm/texture/atlas.h"
#include "varsfm/texture/atlas_fill.h"
#include "varsfm/texture/chart_colour.h"
#include "varsfm/texture/colour_levelling.h"
#include "varsfm/texture/face_adjacency.h"
#include "varsfm/texture/texture_charts.h"
#include "varsfm/util/error.h"
#include "varsfm/util/log.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

// Unseen faces: their colour (mean vertex colour, or the neutral one) quantised to 5 bits per
// channel picks a 3x3 palette cell, whose centre texel every such face samples. At most 32768
// cells, however large the mesh.
struct UnseenPalette {
  std::vector<int> faces;
  std::vector<int> cell_of_face;  // per entry of `faces`
  std::vector<cv::Vec3b> colours;
  int cells_per_row = 1;
};

UnseenPalette BuildUnseenPalette(const TriangleMesh& mesh, const std::vector<int>& labels,
                                 const cv::Vec3b& unseen_color) {
  UnseenPalette palette;
  std::unordered_map<int, int> cell_of_key;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    if (labels[f] >= 0) continue;
    cv::Vec3b colour = unseen_color;
    if (!mesh.colors.empty()) {
      Eigen::Vector3i sum = Eigen::Vector3i::Zero();
      for (int k = 0; k < 3; ++k) sum += mesh.colors[mesh.faces[f][k]].cast<int>();
      // Mesh colours are RGB, atlas pages BGR.
      colour = cv::Vec3b(static_cast<uchar>(sum[2] / 3), static_cast<uchar>(sum[1] / 3),
                         static_cast<uchar>(sum[0] / 3));
    }
    const int key = (colour[0] >> 3) << 10 | (colour[1] >> 3) << 5 | (colour[2] >> 3);
    const auto [it, inserted] =
        cell_of_key.try_emplace(key, static_cast<int>(palette.colours.size()));
    if (inserted) palette.colours.push_back(colour);
    palette.faces.push_back(static_cast<int>(f));
    palette.cell_of_face.push_back(it->second);
  }
  palette.cells_per_row =
      std::max(1, static_cast<int>(std::ceil(std::sqrt(palette.colours.size()))));
  return palette;
}

// Paints the palette's 3 x 3 cells at its place in the atlas (turned: cell i at column i / per
// row, row i % per row) and points every unseen face at its cell's centre.
void WritePalette(const UnseenPalette& palette, const AtlasPlacement& place, int id,
                  TexturedMesh* out, std::vector<cv::Mat>* owner) {
  cv::Mat& page = out->pages[place.page];
  const int first_texcoord = static_cast<int>(out->texcoords.size());
  for (size_t i = 0; i < palette.colours.size(); ++i) {
    const cv::Vec3b& colour = palette.colours[i];
    int along = 3 * static_cast<int>(i % palette.cells_per_row);
    int across = 3 * static_cast<int>(i / palette.cells_per_row);
    if (place.rotated) std::swap(along, across);
    const cv::Rect cell(place.x + along, place.y + across, 3, 3);
    page(cell).setTo(cv::Scalar(colour[0], colour[1], colour[2]));
    (*owner)[place.page](cell).setTo(id);
    out->texcoords.emplace_back((cell.x + 1.5f) / page.cols, (cell.y + 1.5f) / page.rows);
  }
  for (size_t i = 0; i < palette.faces.size(); ++i) {
    out->face_page[palette.faces[i]] = place.page;
    out->face_texcoords[palette.faces[i]].setConstant(first_texcoord + palette.cell_of_face[i]);
  }
}

// What goes into a chart's texels: its photo's pixels times the photo's gain plus the levelling
// corrections (chart_colour.h), out to `reach` texels from its faces.
struct ChartTexels {
  const TriangleMesh& mesh;
  const Chart& chart;
  const std::vector<ProjectedVertex>& pixels;  // the vertices in the chart's photo
  const std::vector<std::array<Eigen::Vector3f, 3>>& corrections;
  const Eigen::Vector3f& gain;
  double reach;
};

// Copies a chart's masked texels from its photo into its place in the atlas, marks them as
// chart `id`'s in `owner` and sets its faces' texture coordinates. Turning by 90 degrees permutes
// texels, so the atlas holds the photo's own pixels either way.
void CopyChart(const cv::Mat& photo, const ChartTexels& t, const AtlasPlacement& place, int id,
               TexturedMesh* out, std::vector<cv::Mat>* owner) {
  const Chart& chart = t.chart;
  cv::Mat texels(chart.source.size(), CV_8UC3, cv::Scalar::all(0));
  const cv::Rect inside = chart.source & cv::Rect(0, 0, photo.cols, photo.rows);
  if (inside == chart.source) {
    photo(chart.source).copyTo(texels);
  } else if (inside.area() > 0) {  // repeat the photo's border pixels outside it
    cv::copyMakeBorder(photo(inside), texels, inside.y - chart.source.y,
                       chart.source.br().y - inside.br().y, inside.x - chart.source.x,
                       chart.source.br().x - inside.br().x,
                       cv::BORDER_REPLICATE | cv::BORDER_ISOLATED);
  }
  std::vector<std::array<Eigen::Vector2d, 3>> face_pixels(chart.faces.size());
  std::vector<std::array<Eigen::Vector3f, 3>> face_corrections(chart.faces.size());
  const Eigen::Vector2d corner(chart.source.x, chart.source.y);
  for (size_t i = 0; i < chart.faces.size(); ++i) {
    for (int k = 0; k < 3; ++k)
      face_pixels[i][k] = t.pixels[t.mesh.faces[chart.faces[i]][k]].pixel - corner;
    face_corrections[i] = t.corrections[chart.faces[i]];
  }
  CorrectChartColours(face_pixels, face_corrections, t.gain, t.reach, &texels);

  cv::Mat placed = texels;
  if (place.rotated) cv::rotate(texels, placed, cv::ROTATE_90_CLOCKWISE);
  const cv::Mat mask = PlacedMask(chart.mask, place);
  cv::Mat& page = out->pages[place.page];
  const cv::Rect region(place.x, place.y, placed.cols, placed.rows);
  placed.copyTo(page(region), mask);
  (*owner)[place.page](region).setTo(id, mask);

  const Eigen::Vector2d inv_size(1.0 / page.cols, 1.0 / page.rows);
  const Eigen::Vector2d origin(place.x, place.y);
  std::unordered_map<int, int> texcoord_of_vertex;
  for (const int f : chart.faces) {
    out->face_page[f] = place.page;
    for (int k = 0; k < 3; ++k) {
      const int vertex = t.mesh.faces[f][k];
      const auto [it, inserted] =
          texcoord_of_vertex.try_emplace(vertex, static_cast<int>(out->texcoords.size()));
      if (inserted) {
        const Eigen::Vector2d local = t.pixels[vertex].pixel - corner;
        const Eigen::Vector2d turned =
            place.rotated ? Eigen::Vector2d(chart.source.height - local.y(), local.x()) : local;
        out->texcoords.push_back(((turned + origin).cwiseProduct(inv_size)).cast<float>());
      }
      out->face_texcoords[f][k] = it->second;
    }
  }
}

// The views with the cameras of their photos' copies at most max_size on the longer side (0:
// as they are).
std::vector<PosedCamera> CappedViews(const std::vector<PosedCamera>& views, int max_size) {
  std::vector<PosedCamera> capped = views;
  if (max_size <= 0) return capped;
  for (PosedCamera& view : capped) {
    const ScaledSize size = SizeWithin(view.camera, max_size);
    if (size.scale < 1) view.camera = view.camera.Resized(size.width, size.height);
  }
  return capped;
}

}  // namespace

TexturedMesh TextureMesh(const TriangleMesh& mesh, const std::vector<PosedCamera>& full_views,
                         const std::function<cv::Mat(size_t)>& load_full_image,
                         const TextureMappingOptions& options, TextureMappingStats* stats) {
  if (mesh.faces.empty() || mesh.vertices.empty()) Fail("texture: the mesh has no faces");
  if (full_views.empty()) Fail("texture: no registered images to texture from");
  const std::vector<PosedCamera> views = CappedViews(full_views, options.max_image_size);
  const auto load_image = [&](size_t v) {
    const cv::Mat photo = load_full_image(v);
    const cv::Size size(views[v].camera.width, views[v].camera.height);
    if (photo.empty() || photo.size() == size) return photo;
    cv::Mat resized;
    cv::resize(photo, resized, size, 0, 0, cv::INTER_AREA);
    return resized;
  };
  TextureMappingStats local;
  TextureMappingStats& st = stats ? *stats : local;
  st = {};
  st.num_faces = mesh.faces.size();
  Timer timer;

  ViewSelection selection =
      SelectViews(mesh.vertices, mesh.faces, views, load_image, options.selection);
  st.num_textured_faces = selection.num_visible_faces;
  st.num_rejected_observations = selection.num_rejected_observations;
  for (const double c : selection.coverage) st.mean_coverage += c / views.size();
  if (st.mean_coverage < options.min_mean_coverage)
    Fail(
        "texture: the mesh covers {:.2f} % of the photos on average (at least {:.2f} % expected): "
        "it is not the surface the photos show",
        100 * st.mean_coverage, 100 * options.min_mean_coverage);
  const std::vector<std::array<int, 3>>& neighbours = selection.neighbours;
  std::vector<Chart> charts = GrowCharts(selection.labels, neighbours);
  st.seconds_selection = timer.Seconds();
  timer.Restart();
  const std::vector<std::array<Eigen::Vector3f, 3>> corrections =
      LevelColours(mesh.vertices, mesh.faces, selection.labels, views, selection.small_photos,
                   selection.small_scale, selection.gains, options.levelling);
  selection.small_photos.clear();  // only the levelling samples them
  st.seconds_levelling = timer.Seconds();
  timer.Restart();

  // The vertices' pixels in a view (full resolution, with distortion) are held for one view at
  // a time, while its charts are cut and masked and again while they are copied: every view's
  // at once grew with the views times the vertices (docs/measurements.md).
  const auto project = [&](size_t v) {
    return ProjectVertices(mesh.vertices, views[v].camera, views[v].cam_from_world);
  };
  const int gutter = std::max(0, options.padding);
  {
    // Each chart cut into compact pieces, masked; the pieces in the charts' order.
    std::vector<std::vector<size_t>> grown_of_view(views.size());
    for (size_t c = 0; c < charts.size(); ++c) grown_of_view[charts[c].view].push_back(c);
    std::vector<std::vector<Chart>> pieces(charts.size());
    for (size_t v = 0; v < views.size(); ++v) {
      if (grown_of_view[v].empty()) continue;
      const std::vector<ProjectedVertex> pixels = project(v);
      const cv::Size photo_size(views[v].camera.width, views[v].camera.height);
      for (const size_t c : grown_of_view[v]) {
        pieces[c] = CutChart(charts[c], mesh.faces, pixels, options.chart_tile);
        for (Chart& piece : pieces[c])
          st.face_texels += SetChartMask(mesh.faces, pixels, photo_size, gutter, &piece);
      }
    }
    charts.clear();
    for (std::vector<Chart>& list : pieces)
      for (Chart& piece : list) charts.push_back(std::move(piece));
  }
  st.num_charts = charts.size();
  std::vector<cv::Mat> masks;
  for (const Chart& chart : charts) {
    masks.push_back(chart.mask);
    st.chart_texels += cv::countNonZero(chart.mask);
  }
  const UnseenPalette palette = BuildUnseenPalette(mesh, selection.labels, options.unseen_color);
  if (!palette.faces.empty()) {
    const int rows = static_cast<int>((palette.colours.size() + palette.cells_per_row - 1) /
                                      palette.cells_per_row);
    masks.emplace_back(3 * rows, 3 * palette.cells_per_row, CV_8UC1, cv::Scalar::all(255));
  }
  const AtlasLayout layout = PackCharts(masks, options.max_page_size);

  TexturedMesh out;
  out.vertices = mesh.vertices;
  out.faces = mesh.faces;
  out.face_texcoords.resize(mesh.faces.size());
  out.face_page.resize(mesh.faces.size(), 0);
  std::vector<cv::Mat> owner;  // per page: the chart of every texel (-1: none)
  for (const AtlasPage& page : layout.pages) {
    out.pages.emplace_back(page.height, page.width, CV_8UC3, cv::Scalar::all(0));
    owner.emplace_back(page.height, page.width, CV_32SC1, cv::Scalar::all(-1));
    st.atlas_pixels += static_cast<size_t>(page.width) * page.height;
  }
  st.num_pages = out.pages.size();

  // Copy the charts view by view, so only one photo is in memory at a time.
  std::vector<std::vector<size_t>> charts_of_view(views.size());
  for (size_t c = 0; c < charts.size(); ++c) charts_of_view[charts[c].view].push_back(c);
  Progress progress("texture: atlas", views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    progress.Tick();
    if (charts_of_view[v].empty()) continue;
    const cv::Mat photo = load_image(v);
    if (photo.cols != views[v].camera.width || photo.rows != views[v].camera.height ||
        photo.type() != CV_8UC3)
      Fail("texture: photo {} is {}x{} (type {}) but its camera is {}x{}", v, photo.cols,
           photo.rows, photo.type(), views[v].camera.width, views[v].camera.height);
    const std::vector<ProjectedVertex> pixels = project(v);
    for (const size_t c : charts_of_view[v]) {
      const ChartTexels texels{mesh,        charts[c],          pixels,
                               corrections, selection.gains[v], gutter + 1.5};
      CopyChart(photo, texels, layout.placements[c], static_cast<int>(c), &out, &owner);
    }
  }
  if (!palette.faces.empty())
    WritePalette(palette, layout.placements.back(), static_cast<int>(charts.size()), &out, &owner);
  std::vector<int> chart_of_face(mesh.faces.size(), -1);
  for (size_t c = 0; c < charts.size(); ++c)
    for (const int f : charts[c].faces) chart_of_face[f] = static_cast<int>(c);
  info("texture: blending the seams between {} charts", charts.size());
  BlendSeams(neighbours, selection.labels, chart_of_face, owner, options.seams, &out);
  if (options.bleed_rings > 0) {
    for (size_t p = 0; p < out.pages.size(); ++p)
      BleedAtlasBackground(&out.pages[p], owner[p] >= 0, options.bleed_rings);
  }
  st.seconds_atlas = timer.Seconds();
  return out;
}

void TextureMappingOptions::Check() const {
  selection.Check();
  levelling.Check();
  seams.Check();
  CheckInRange("--padding", padding, 0, 64);
  CheckNonNegative("bleed_rings", bleed_rings);
  CheckAtLeast("chart_tile", chart_tile, 8);
  CheckAtLeast("max_page_size", max_page_size, 64);
  if (max_image_size != 0) CheckAtLeast("--texture-max-image-size", max_image_size, 64);
  CheckFraction("min_mean_coverage", min_mean_coverage);
}

}  // namespace varsfm
