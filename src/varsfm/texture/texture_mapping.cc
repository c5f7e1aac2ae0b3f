#include "varsfm/texture/texture_mapping.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <opencv2/core.hpp>

#include "varsfm/texture/atlas.h"
#include "varsfm/texture/atlas_fill.h"
#include "varsfm/texture/chart_colour.h"
#include "varsfm/texture/colour_levelling.h"
#include "varsfm/texture/face_adjacency.h"
#include "varsfm/texture/rasterizer.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"
#include "varsfm/util/progress.h"
#include "varsfm/util/timer.h"

namespace varsfm {
namespace {

struct Chart {
  int view = -1;
  std::vector<int> faces;
  cv::Rect source;  // pixels of the photo copied into the atlas
};

// Connected components of edge-adjacent faces with the same (valid) label.
std::vector<Chart> GrowCharts(const std::vector<int>& labels,
                              const std::vector<std::array<int, 3>>& neighbours) {
  std::vector<Chart> charts;
  std::vector<char> done(labels.size(), 0);
  std::vector<int> stack;
  for (size_t seed = 0; seed < labels.size(); ++seed) {
    if (done[seed] || labels[seed] < 0) continue;
    Chart chart;
    chart.view = labels[seed];
    stack.assign(1, static_cast<int>(seed));
    done[seed] = 1;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      chart.faces.push_back(f);
      for (const int g : neighbours[f]) {
        if (g >= 0 && !done[g] && labels[g] == chart.view) {
          done[g] = 1;
          stack.push_back(g);
        }
      }
    }
    charts.push_back(std::move(chart));
  }
  return charts;
}

// The pixels of each chart's photo that go into the atlas: the bounding box of its faces'
// projections plus `pad`. Returns the texels inside the faces, summed over the charts.
double SetChartSources(const TriangleMesh& mesh, const std::vector<TextureView>& views,
                       const std::vector<std::vector<ProjectedVertex>>& projected, int pad,
                       std::vector<Chart>* charts) {
  double face_texels = 0;
  for (Chart& chart : *charts) {
    const Camera& camera = views[chart.view].camera;
    const std::vector<ProjectedVertex>& pixels = projected[chart.view];
    double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
    for (const int f : chart.faces) {
      const Eigen::Vector2d& a = pixels[mesh.faces[f][0]].pixel;
      const Eigen::Vector2d e1 = pixels[mesh.faces[f][1]].pixel - a;
      const Eigen::Vector2d e2 = pixels[mesh.faces[f][2]].pixel - a;
      face_texels += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x());
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d& p = pixels[mesh.faces[f][k]].pixel;
        min_x = std::min(min_x, p.x());
        min_y = std::min(min_y, p.y());
        max_x = std::max(max_x, p.x());
        max_y = std::max(max_y, p.y());
      }
    }
    // Faces cut by the image border reach outside the photo: the rectangle may too, by at most
    // a quarter of the image (the rest of such a face samples the rectangle's edge).
    const int mx = camera.width / 4, my = camera.height / 4;
    const int x0 = std::max(-mx, static_cast<int>(std::floor(min_x)) - pad);
    const int y0 = std::max(-my, static_cast<int>(std::floor(min_y)) - pad);
    const int x1 = std::min(camera.width + mx, static_cast<int>(std::ceil(max_x)) + pad);
    const int y1 = std::min(camera.height + my, static_cast<int>(std::ceil(max_y)) + pad);
    chart.source = cv::Rect(x0, y0, std::max(1, x1 - x0), std::max(1, y1 - y0));
  }
  return face_texels;
}

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

// Applies the view's gain and the levelling corrections to a chart's texels (chart_colour.h).
void CorrectChart(const TriangleMesh& mesh, const Chart& chart,
                  const std::vector<ProjectedVertex>& pixels,
                  const std::vector<std::array<Eigen::Vector3f, 3>>& corrections,
                  const Eigen::Vector3f& gain, double reach, cv::Mat* target) {
  std::vector<std::array<Eigen::Vector2d, 3>> face_pixels(chart.faces.size());
  std::vector<std::array<Eigen::Vector3f, 3>> face_corrections(chart.faces.size());
  const Eigen::Vector2d corner(chart.source.x, chart.source.y);
  for (size_t i = 0; i < chart.faces.size(); ++i) {
    for (int k = 0; k < 3; ++k)
      face_pixels[i][k] = pixels[mesh.faces[chart.faces[i]][k]].pixel - corner;
    face_corrections[i] = corrections[chart.faces[i]];
  }
  CorrectChartColours(face_pixels, face_corrections, gain, reach, target);
}

}  // namespace

TexturedMesh TextureMesh(const TriangleMesh& mesh, const std::vector<TextureView>& views,
                         const std::function<cv::Mat(size_t)>& load_image,
                         const TextureOptions& options, TextureStats* stats) {
  if (mesh.faces.empty() || mesh.vertices.empty()) Fail("texture: the mesh has no faces");
  if (views.empty()) Fail("texture: no registered images to texture from");
  TextureStats local;
  TextureStats& st = stats ? *stats : local;
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
  std::vector<Chart> charts = GrowCharts(selection.labels, FaceNeighbours(mesh.faces));
  st.num_charts = charts.size();
  st.seconds_selection = timer.Seconds();
  timer.Restart();
  const std::vector<std::array<Eigen::Vector3f, 3>> corrections =
      LevelColours(mesh.vertices, mesh.faces, selection.labels, views, selection.small_photos,
                   selection.small_scale, selection.gains, options.levelling);
  selection.small_photos.clear();  // only the levelling samples them
  st.seconds_levelling = timer.Seconds();
  timer.Restart();

  // Vertex pixels in every view that textures a chart (full resolution, with distortion).
  std::vector<std::vector<ProjectedVertex>> projected(views.size());
  for (const Chart& chart : charts) {
    if (projected[chart.view].empty())
      projected[chart.view] = ProjectVertices(mesh.vertices, views[chart.view].camera,
                                              views[chart.view].cam_from_world);
  }

  const int pad = std::max(0, options.padding);
  st.face_texels = SetChartSources(mesh, views, projected, pad, &charts);
  std::vector<AtlasRect> rects;
  for (const Chart& chart : charts) rects.push_back({chart.source.width, chart.source.height});
  const UnseenPalette palette = BuildUnseenPalette(mesh, selection.labels, options.unseen_color);
  if (!palette.faces.empty()) {
    const int rows = static_cast<int>((palette.colours.size() + palette.cells_per_row - 1) /
                                      palette.cells_per_row);
    rects.push_back({3 * palette.cells_per_row, 3 * rows});
  }
  const AtlasLayout layout = PackRectangles(rects, options.max_page_size);

  TexturedMesh out;
  out.vertices = mesh.vertices;
  out.faces = mesh.faces;
  out.face_texcoords.resize(mesh.faces.size());
  out.face_page.resize(mesh.faces.size(), 0);
  std::vector<cv::Mat> filled;  // per page: texels holding chart colour
  for (const AtlasRect& page : layout.pages) {
    out.pages.emplace_back(page.height, page.width, CV_8UC3, cv::Scalar::all(0));
    filled.emplace_back(page.height, page.width, CV_8UC1, cv::Scalar::all(0));
    st.atlas_pixels += static_cast<size_t>(page.width) * page.height;
  }
  st.num_pages = out.pages.size();

  // Copy the charts view by view, so only one photo is in memory at a time.
  std::vector<std::vector<size_t>> charts_of_view(views.size());
  for (size_t c = 0; c < charts.size(); ++c) charts_of_view[charts[c].view].push_back(c);
  std::unordered_map<int, int> texcoord_of_vertex;  // within one chart
  Progress progress("texture: atlas", views.size());
  for (size_t v = 0; v < views.size(); ++v) {
    progress.Tick();
    if (charts_of_view[v].empty()) continue;
    const cv::Mat photo = load_image(v);
    if (photo.cols != views[v].camera.width || photo.rows != views[v].camera.height ||
        photo.type() != CV_8UC3)
      Fail("texture: photo {} is {}x{} (type {}) but its camera is {}x{}", v, photo.cols,
           photo.rows, photo.type(), views[v].camera.width, views[v].camera.height);
    for (const size_t c : charts_of_view[v]) {
      const Chart& chart = charts[c];
      const AtlasPlacement& place = layout.placements[c];
      cv::Mat& page = out.pages[place.page];
      const cv::Rect region(place.x, place.y, chart.source.width, chart.source.height);
      filled[place.page](region).setTo(255);
      cv::Mat target = page(region);
      const cv::Rect inside = chart.source & cv::Rect(0, 0, photo.cols, photo.rows);
      if (inside == chart.source) {
        photo(chart.source).copyTo(target);
      } else if (inside.area() > 0) {  // repeat the photo's border pixels outside it
        cv::copyMakeBorder(photo(inside), target, inside.y - chart.source.y,
                           chart.source.br().y - inside.br().y, inside.x - chart.source.x,
                           chart.source.br().x - inside.br().x,
                           cv::BORDER_REPLICATE | cv::BORDER_ISOLATED);
      }
      CorrectChart(mesh, chart, projected[v], corrections, selection.gains[v], pad + 1.0, &target);
      const Eigen::Vector2d shift(place.x - chart.source.x, place.y - chart.source.y);
      const Eigen::Vector2d inv_size(1.0 / page.cols, 1.0 / page.rows);
      texcoord_of_vertex.clear();
      for (const int f : chart.faces) {
        out.face_page[f] = place.page;
        for (int k = 0; k < 3; ++k) {
          const int vertex = mesh.faces[f][k];
          const auto [it, inserted] =
              texcoord_of_vertex.try_emplace(vertex, static_cast<int>(out.texcoords.size()));
          if (inserted) {
            const Eigen::Vector2d uv = (projected[v][vertex].pixel + shift).cwiseProduct(inv_size);
            out.texcoords.push_back(uv.cast<float>());
          }
          out.face_texcoords[f][k] = it->second;
        }
      }
    }
  }
  if (!palette.faces.empty()) {
    const AtlasPlacement& place = layout.placements.back();
    cv::Mat& page = out.pages[place.page];
    const int first_texcoord = static_cast<int>(out.texcoords.size());
    for (size_t i = 0; i < palette.colours.size(); ++i) {
      const cv::Vec3b& colour = palette.colours[i];
      const int per_row = palette.cells_per_row;
      const cv::Rect cell(place.x + 3 * static_cast<int>(i % per_row),
                          place.y + 3 * static_cast<int>(i / per_row), 3, 3);
      page(cell).setTo(cv::Scalar(colour[0], colour[1], colour[2]));
      filled[place.page](cell).setTo(255);
      out.texcoords.emplace_back((cell.x + 1.5f) / page.cols, (cell.y + 1.5f) / page.rows);
    }
    for (size_t i = 0; i < palette.faces.size(); ++i) {
      out.face_page[palette.faces[i]] = place.page;
      out.face_texcoords[palette.faces[i]].setConstant(first_texcoord + palette.cell_of_face[i]);
    }
  }
  if (options.bleed_rings > 0) {
    for (size_t p = 0; p < out.pages.size(); ++p)
      BleedAtlasBackground(&out.pages[p], filled[p], options.bleed_rings);
  }
  st.seconds_atlas = timer.Seconds();
  return out;
}

void TextureOptions::Check() const {
  selection.Check();
  levelling.Check();
  CheckInRange("--padding", padding, 0, 64);
  CheckAtLeast("bleed_rings", bleed_rings, 0);
  CheckAtLeast("max_page_size", max_page_size, 64);
  CheckInRange("min_mean_coverage", min_mean_coverage, 0, 1);
}

}  // namespace varsfm
