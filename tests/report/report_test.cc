// The report's parts on a synthetic run with exact truth: what it gathers from OUT, the compact
// display model, the page's self-containment and the pieces (base64, ticks, escaping).
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "report/synthetic_output.h"
#include "support/test_data.h"
#include "varsfm/report/base64.h"
#include "varsfm/report/display_model.h"
#include "varsfm/report/html_report.h"
#include "varsfm/report/html_text.h"
#include "varsfm/report/report.h"
#include "varsfm/report/report_charts.h"
#include "varsfm/report/report_sections.h"
#include "varsfm/report/svg_chart.h"
#include "varsfm/report/vertex_clustering.h"
#include "varsfm/util/error.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

using testing::TempDir;
using testing::WriteSyntheticOutput;

std::string ReadText(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(Base64, MatchesRfc4648TestVectors) {
  const auto encode = [](const std::string& s) {
    return Base64Encode(reinterpret_cast<const uint8_t*>(s.data()), s.size());
  };
  EXPECT_EQ(encode(""), "");
  EXPECT_EQ(encode("f"), "Zg==");
  EXPECT_EQ(encode("fo"), "Zm8=");
  EXPECT_EQ(encode("foo"), "Zm9v");
  EXPECT_EQ(encode("foob"), "Zm9vYg==");
  EXPECT_EQ(encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(encode("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64Encode(std::vector<uint8_t>{0xfb, 0xff}), "+/8=");
}

TEST(SvgChart, NiceTicksCoverTheRangeAtRoundSteps) {
  EXPECT_EQ(NiceTicks(0, 1), (std::vector<double>{0, 0.2, 0.4, 0.6000000000000001, 0.8, 1}));
  const std::vector<double> ticks = NiceTicks(918.9, 1428.0);
  ASSERT_GE(ticks.size(), 2u);
  EXPECT_LE(ticks.front(), 918.9);
  EXPECT_GE(ticks.back(), 1428.0);
  EXPECT_DOUBLE_EQ(ticks[1] - ticks[0], 100.0);
}

// Slanted image names reach down to where the x axis' title would be: the title is left out
// when every name is written, and kept when only indices are (too many images for names).
TEST(SvgChart, ImageNamesStandForTheXAxisTitle) {
  const ChartFrame frame{.width = 620, .height = 300, .title = "t", .x_label = "image"};
  PerImageSeries few;
  for (int i = 0; i < 12; ++i) {
    few.names.push_back(fmt::format("photo_{:04d}.jpg", i));
    few.values.push_back(i);
  }
  const std::string named = PerImageChartSvg(frame, few);
  EXPECT_NE(named.find("rotate(-40)"), std::string::npos);  // the slanted names
  EXPECT_EQ(named.find(">image<"), std::string::npos);
  PerImageSeries many;
  for (int i = 0; i < 200; ++i) {
    many.names.push_back(fmt::format("photo_{:04d}.jpg", i));
    many.values.push_back(i);
  }
  const std::string indexed = PerImageChartSvg(frame, many);
  EXPECT_EQ(indexed.find("rotate(-40)"), std::string::npos);
  EXPECT_NE(indexed.find(">image<"), std::string::npos);
}

TEST(SvgChart, StageTimesShowMillisecondsBelowATenthOfASecond) {
  const std::string svg = StageTimesSvg({{"registration", 0.012}, {"global BA", 1.25}}, 600);
  EXPECT_NE(svg.find("registration 12 ms"), std::string::npos);
  EXPECT_NE(svg.find("global BA 1.2 s"), std::string::npos);
}

TEST(HtmlText, JsonCannotCloseItsScriptElement) {
  const std::string json = JsonForScript({{"name", "</script><b>"}});
  EXPECT_EQ(json.find('<'), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(json)["name"], "</script><b>");
  EXPECT_EQ(EscapeHtml("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
}

TEST(ReportData, GathersTheModelWorkspaceAndPhotos) {
  TempDir tmp("report_data");
  const Reconstruction model = WriteSyntheticOutput(tmp.path());
  const ReportData data = CollectReportData(tmp.path(), {});
  EXPECT_EQ(data.sparse_dir, tmp.path() / "sparse");
  ASSERT_EQ(data.images.size(), 6u);
  size_t registered = 0, seen = 0;
  for (const ReportImage& image : data.images) {
    EXPECT_EQ(image.name, model.image(image.image_id).name);
    EXPECT_FALSE(image.thumbnail.empty()) << image.name;
    EXPECT_EQ(image.thumbnail_width, 160);  // 320 x 240 photos halved
    EXPECT_EQ(image.thumbnail_height, 120);
    if (!image.registered) continue;
    ++registered;
    seen += image.num_points3D;
    const Camera& truth = model.CameraOf(image.image_id);
    EXPECT_DOUBLE_EQ(image.camera.focal(), truth.focal());
    EXPECT_LT(image.rms_error_px, 1e-6);  // exact synthetic observations
    EXPECT_EQ(image.num_points3D, model.image(image.image_id).NumPoints3D());
  }
  EXPECT_EQ(registered, 5u);
  EXPECT_EQ(seen, model.NumObservations());
  EXPECT_EQ(data.num_observations, model.NumObservations());
  EXPECT_EQ(data.observation_errors_px.size(), model.NumObservations());
  EXPECT_EQ(data.track_lengths.size(), model.points3D().size());
  EXPECT_EQ(data.view_points.size(), model.points3D().size());  // under max_view_points
  // Pairs (1,2) (1,3) (2,3) (2,4) (3,4) (3,5) (4,5) (4,6) (5,6).
  EXPECT_EQ(data.pairs.size(), 9u);
  const ReportImage& last = data.images.back();
  EXPECT_FALSE(last.registered);
  EXPECT_EQ(last.best_pair_inliers, 5u);
  EXPECT_EQ(last.num_verified_pairs, 0u);
  EXPECT_NE(last.failure.find("no pair with 15+ verified inliers (best 5)"), std::string::npos)
      << last.failure;
  EXPECT_GT(data.glb.size(), 0u);
  EXPECT_GT(data.glb_file_bytes, 0u);
}

TEST(ReportData, ReadingTheWorkspaceLeavesNoLogBesideIt) {
  TempDir tmp("report_wal");
  WriteSyntheticOutput(tmp.path());
  const std::filesystem::path database = tmp.path() / "workspace.db";
  ASSERT_TRUE(std::filesystem::exists(database));
  ASSERT_FALSE(std::filesystem::exists(tmp.path() / "workspace.db-wal"));
  const ReportData data = CollectReportData(tmp.path(), {});
  EXPECT_EQ(data.images.size(), 6u);
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / "workspace.db-wal"));
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / "workspace.db-shm"));
}

// A file of the photo folder that extract could not read is listed as not extracted; it is no
// missing photo of the model, so the warning about thumbnails does not name it.
TEST(ReportData, AnUnreadablePhotoIsListedAsNotExtractedWithoutAThumbnailWarning) {
  TempDir tmp("report_data_unreadable");
  WriteSyntheticOutput(tmp.path());
  std::ofstream(tmp.path() / "images" / "zz_broken.jpg") << "not a photo";
  // Files extraction skipped and named already: not named again by the report.
  std::ofstream(tmp.path() / "images" / "IMG_0002.MOV") << "a video";
  std::ofstream(tmp.path() / "images" / "IMG_0003.gif") << "a GIF";
  std::ostringstream log;
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>(
      "capture", std::make_shared<spdlog::sinks::ostream_sink_st>(log)));
  const ReportData data = CollectReportData(tmp.path(), {});
  spdlog::set_default_logger(previous);
  ASSERT_EQ(data.images.size(), 7u);
  EXPECT_EQ(data.images.back().name, "zz_broken.jpg");
  EXPECT_NE(data.images.back().failure.find("not extracted"), std::string::npos)
      << data.images.back().failure;
  EXPECT_TRUE(data.images.back().thumbnail.empty());
  EXPECT_EQ(log.str().find("thumbnails"), std::string::npos) << log.str();
  EXPECT_EQ(log.str().find("skipping"), std::string::npos) << log.str();

  // A photo of the model that has gone is named.
  std::filesystem::remove(tmp.path() / "images" / data.images.front().name);
  spdlog::set_default_logger(std::make_shared<spdlog::logger>(
      "capture", std::make_shared<spdlog::sinks::ostream_sink_st>(log)));
  CollectReportData(tmp.path(), {});
  spdlog::set_default_logger(previous);
  EXPECT_NE(log.str().find("1 of 6 photos not found or unreadable"), std::string::npos)
      << log.str();
}

TEST(ReportData, AnImageInAnotherModelIsSaidToBeThere) {
  TempDir tmp("report_data_models");
  WriteSyntheticOutput(tmp.path());
  nlohmann::json summary = nlohmann::json::parse(ReadText(tmp.path() / "summary.json"));
  summary["models"] = {{{"path", "sparse/0"}}, {{"path", "sparse/1"}}};
  summary["images"].back()["model"] = 1;
  std::ofstream(tmp.path() / "summary.json") << summary.dump();
  const ReportData data = CollectReportData(tmp.path(), {});
  EXPECT_EQ(data.num_models, 2u);
  EXPECT_NE(data.images.back().failure.find("sparse/1"), std::string::npos)
      << data.images.back().failure;
}

TEST(ReportData, DecimatesThePointsShownAndReadsSparseZero) {
  TempDir tmp("report_data_decimate");
  const Reconstruction model = WriteSyntheticOutput(tmp.path(), {.model_in_subfolder = true});
  ReportDataOptions options;
  options.max_view_points = 50;
  const ReportData data = CollectReportData(tmp.path(), options);
  EXPECT_EQ(data.sparse_dir, tmp.path() / "sparse" / "0");
  EXPECT_LE(data.view_points.size(), 50u);
  EXPECT_GE(data.view_points.size(), 25u);  // every k-th point: at least half the budget
  EXPECT_EQ(data.num_points3D, model.points3D().size());
}

TEST(ReportData, AFolderWithoutModelIsOneLineError) {
  TempDir tmp("report_data_empty");
  try {
    CollectReportData(tmp.path(), {});
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no sparse model"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}

// Reads accessor `index` of a GLB's binary chunk as `T`, `components` per element.
template <typename T>
std::vector<T> Accessor(const nlohmann::json& gltf, const uint8_t* bin, int index, int components) {
  const nlohmann::json& accessor = gltf["accessors"][index];
  const nlohmann::json& view = gltf["bufferViews"][accessor["bufferView"].get<int>()];
  const size_t stride = view.value("byteStride", sizeof(T) * components);
  std::vector<T> values;
  for (size_t i = 0; i < accessor["count"].get<size_t>(); ++i)
    for (int k = 0; k < components; ++k) {
      T v;
      std::memcpy(&v, bin + view["byteOffset"].get<size_t>() + i * stride + k * sizeof(T),
                  sizeof(T));
      values.push_back(v);
    }
  return values;
}

TEST(DisplayModel, QuantisedCopyKeepsEveryTriangleWithinOneStep) {
  TempDir tmp("display_model");
  const TexturedMesh box = testing::RedBox();
  WriteGlb(tmp.path() / "box.glb", box);
  const std::string file = ReadText(tmp.path() / "box.glb");
  const std::vector<uint8_t> glb =
      CompactGlbForDisplay(std::vector<uint8_t>(file.begin(), file.end()));
  uint32_t json_length;
  std::memcpy(&json_length, glb.data() + 12, 4);
  const nlohmann::json gltf =
      nlohmann::json::parse(glb.begin() + 20, glb.begin() + 20 + json_length);
  const uint8_t* bin = glb.data() + 20 + json_length + 8;
  const nlohmann::json& primitive = gltf["meshes"][0]["primitives"][0];
  const auto q = Accessor<uint16_t>(gltf, bin, primitive["attributes"]["POSITION"], 3);
  const auto uv = Accessor<uint16_t>(gltf, bin, primitive["attributes"]["TEXCOORD_0"], 2);
  const auto indices = Accessor<uint16_t>(gltf, bin, primitive["indices"], 1);
  const nlohmann::json& node = gltf["nodes"][0];
  EXPECT_FALSE(node.contains("rotation"));  // the sparse model's frame
  ASSERT_EQ(indices.size(), 3 * box.faces.size());
  for (size_t f = 0; f < box.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const size_t v = indices[3 * f + k];
      for (int c = 0; c < 3; ++c) {
        const double x = node["translation"][c].get<double>() +
                         node["scale"][c].get<double>() * q[3 * v + c] / 65535.0;
        EXPECT_NEAR(x, box.vertices[box.faces[f][k]][c], 2.0 / 65535);
      }
      const Eigen::Vector2f& t = box.texcoords[box.face_texcoords[f][k]];
      EXPECT_NEAR(uv[2 * v] / 65535.0, t.x(), 1e-4);
      EXPECT_NEAR(uv[2 * v + 1] / 65535.0, t.y(), 1e-4);
    }
  // The 60 x 100 page as a JPEG resampled to 32 x 64, powers of two.
  const nlohmann::json& image = gltf["images"][0];
  EXPECT_EQ(image["mimeType"], "image/jpeg");
  const nlohmann::json& view = gltf["bufferViews"][image["bufferView"].get<int>()];
  const uint8_t* jpeg = bin + view["byteOffset"].get<size_t>();
  const cv::Mat page =
      DecodeImage("page.jpg", std::vector<uint8_t>(jpeg, jpeg + view["byteLength"].get<size_t>()),
                  ColorMode::kColor);
  EXPECT_EQ(page.cols, 32);
  EXPECT_EQ(page.rows, 64);
  const cv::Vec3b red = page.at<cv::Vec3b>(32, 16);
  EXPECT_GT(red[2], 200);
  EXPECT_LT(red[1], 50);
}

TEST(VertexClustering, LeavesAboutTheFacesAskedForOnTheSurface) {
  // A 300 x 300 grid of squares on the plane z = 0: 180 000 triangles, texture coordinates
  // running across it.
  ClusteredPart grid;
  const int n = 300;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      grid.positions.insert(grid.positions.end(), {i / float(n), j / float(n), 0.f});
      grid.uvs.insert(grid.uvs.end(), {i / float(n), j / float(n)});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      grid.indices.insert(grid.indices.end(), {a, b, c, a, c, d});
    }
  const std::vector<ClusteredPart> out = ClusterVertices({grid}, 20000);
  ASSERT_EQ(out.size(), 1u);
  const size_t faces = out[0].indices.size() / 3;
  EXPECT_LE(faces, 20000u);
  EXPECT_GE(faces, 10000u);
  ASSERT_EQ(out[0].uvs.size() / 2, out[0].positions.size() / 3);
  for (size_t v = 0; v < out[0].positions.size() / 3; ++v) {
    // One chart: a vertex's texture coordinate stays where its position is.
    EXPECT_NEAR(out[0].uvs[2 * v], out[0].positions[3 * v], 0.02);
    EXPECT_NEAR(out[0].uvs[2 * v + 1], out[0].positions[3 * v + 1], 0.02);
    EXPECT_EQ(out[0].positions[3 * v + 2], 0.f);
  }
  EXPECT_EQ(ClusterVertices({grid}, 200000)[0].indices, grid.indices);  // under the budget
}

TEST(DisplayModel, NotAGlbIsOneLineError) {
  EXPECT_THROW(CompactGlbForDisplay({'n', 'o', 't', ' ', 'g', 'l', 'b'}), Error);
}

// Two registered photos of one field of view at different sizes (a phone's and a resized copy):
// their focal lengths in pixels differ by x2, their zoom does not.
ReportData TwoSizesOfOneView(int small_width, int small_height, double small_focal) {
  ReportData data;
  for (const Camera& camera : {Camera::FromFocal(640, 480, 600),
                               Camera::FromFocal(small_width, small_height, small_focal)}) {
    ReportImage image;
    image.image_id = static_cast<image_t>(data.images.size() + 1);
    image.name = fmt::format("{}.jpg", image.image_id);
    image.width = camera.width, image.height = camera.height;
    image.registered = true;
    image.camera = camera;
    data.images.push_back(image);
  }
  return data;
}

TEST(Report, PhotosOfSeveralSizesCompareFocalLengthsByFieldOfView) {
  const ReportData mixed = TwoSizesOfOneView(320, 240, 300);
  EXPECT_FALSE(FocalLengthsInPixels(mixed));
  EXPECT_DOUBLE_EQ(FocalRange(mixed).first, 600.0 / 640);
  EXPECT_DOUBLE_EQ(FocalRange(mixed).second, 600.0 / 640);
  const std::vector<std::string> colors = FocalColors(mixed);
  EXPECT_EQ(colors[0], colors[1]);
  const std::string table = ImagesSection(mixed);
  const size_t first = table.find("\u00d71.000");
  ASSERT_NE(first, std::string::npos);
  EXPECT_NE(table.find("\u00d71.000", first + 1), std::string::npos) << "both images at x1";
  EXPECT_EQ(table.find("\u00d72.000"), std::string::npos);
  const ReportCharts charts = DrawReportCharts(mixed);
  EXPECT_NE(charts.focal.find("longer image side"), std::string::npos);
  EXPECT_NE(charts.focal_colorbar.find(">0.928<"), std::string::npos) << "the scale's low end";

  // One size: pixels, as before; the longer focal length reads x2.
  const ReportData one_size = TwoSizesOfOneView(640, 480, 1200);
  EXPECT_TRUE(FocalLengthsInPixels(one_size));
  EXPECT_DOUBLE_EQ(FocalRange(one_size).first, 600);
  EXPECT_NE(ImagesSection(one_size).find("\u00d72.000"), std::string::npos);
  EXPECT_NE(DrawReportCharts(one_size).focal.find("focal length (px)"), std::string::npos);
}

TEST(Report, PageIsSelfContained) {
  TempDir tmp("report_page");
  WriteSyntheticOutput(tmp.path());
  const ReportSummary result = WriteReport({.output = tmp.path()});
  ASSERT_TRUE(result.has_3d_view) << "three.js (libjs-three) is a build dependency";
  EXPECT_EQ(result.file, tmp.path() / "report.html");
  EXPECT_EQ(std::filesystem::file_size(result.file), result.bytes);
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / ".report.html.tmp"));
  const std::string html = ReadText(result.file);
  // Nothing is fetched: no element refers to a file or a server.
  for (const char* attribute : {"src=\"http", "href=\"http", "src=\"file", "src=\"/", "src=\"."})
    EXPECT_EQ(html.find(attribute), std::string::npos) << attribute;
  EXPECT_NE(html.find("id=\"varsfm-scene\""), std::string::npos);
  EXPECT_NE(html.find("id=\"varsfm-glb\" data-encoding=\"deflate\""), std::string::npos);
  EXPECT_NE(html.find("THREE.OrbitControls"), std::string::npos);
  EXPECT_NE(html.find("id=\"thumb-1\""), std::string::npos);
  EXPECT_NE(html.find("Focal length per image"), std::string::npos);
  EXPECT_NE(html.find("no pair with 15+ verified inliers (best 5)"), std::string::npos);
}

TEST(Report, WithoutThreeJsThePageSaysWhatToInstall) {
  TempDir tmp("report_no_three");
  WriteSyntheticOutput(tmp.path(), {.with_glb = false});
  std::filesystem::create_directories(tmp.path() / "no_three");
  const ReportSummary result =
      WriteReport({.output = tmp.path(), .three_js_dir = tmp.path() / "no_three"});
  EXPECT_FALSE(result.has_3d_view);
  const std::string html = ReadText(result.file);
  EXPECT_NE(html.find("The 3D view needs three.js"), std::string::npos);
  EXPECT_NE(html.find("data-viewer=\"absent\""), std::string::npos);
  EXPECT_EQ(html.find("id=\"varsfm-scene\""), std::string::npos);
  EXPECT_NE(html.find("Focal length per image"), std::string::npos);  // the rest is there
}

// A run with --holdout records how the textured model renders the photos; the report shows
// the held-out and source means and a row per image, and has no such section without them.
TEST(Report, HeldOutRendersAreShownWhenTheRunScoredThem) {
  TempDir tmp("report_renders");
  WriteSyntheticOutput(tmp.path(), {.with_glb = false});
  EXPECT_EQ(ReadText(WriteReport({.output = tmp.path()}).file).find("id=\"renders\""),
            std::string::npos);
  nlohmann::json summary = nlohmann::json::parse(ReadText(tmp.path() / "summary.json"));
  summary["renders"] = {
      {"held_out",
       {{"images", 1}, {"mean_psnr_db", 27.125}, {"mean_ssim", 0.9}, {"mean_coverage", 0.8}}},
      {"source",
       {{"images", 1}, {"mean_psnr_db", 30.5}, {"mean_ssim", 0.95}, {"mean_coverage", 0.9}}},
      {"images",
       {{{"name", "a.png"},
         {"held_out", true},
         {"psnr_db", 27.125},
         {"ssim", 0.9},
         {"coverage", 0.8}},
        {{"name", "b.png"},
         {"held_out", false},
         {"psnr_db", 30.5},
         {"ssim", 0.95},
         {"coverage", 0.9}}}}};
  std::ofstream(tmp.path() / "summary.json") << summary.dump();
  const std::string html = ReadText(WriteReport({.output = tmp.path()}).file);
  EXPECT_NE(html.find("id=\"renders\""), std::string::npos);
  EXPECT_NE(html.find("27.12 dB"), std::string::npos) << "the held-out mean";
  EXPECT_NE(html.find("Held-out views (1)"), std::string::npos);
  EXPECT_NE(html.find("<td>a.png</td><td>held out</td><td>27.12</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>b.png</td><td>source</td><td>30.50</td>"), std::string::npos);
}

// The dense cloud's card says how many views had a depth map and how many were redundant, where
// dense_summary.json records them, and names the file alone where it does not.
TEST(Report, DenseCardSaysHowManyViewsHadADepthMap) {
  TempDir tmp("report_dense");
  WriteSyntheticOutput(tmp.path(), {.with_glb = false});
  std::ofstream(tmp.path() / "dense.ply")
      << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n0 0 0\n1 1 1\n";
  const auto dense_card = [&] {
    const std::string html = ReadText(WriteReport({.output = tmp.path()}).file);
    const size_t at = html.find("Dense points");
    return at == std::string::npos ? std::string() : html.substr(at, 200);
  };
  EXPECT_NE(dense_card().find("dense.ply</div>"), std::string::npos);
  std::ofstream(tmp.path() / "dense_summary.json")
      << R"({"depth_maps": 435, "redundant_views": 565})";
  EXPECT_NE(dense_card().find("dense.ply, 435 depth maps (565 views redundant)"),
            std::string::npos);
  std::ofstream(tmp.path() / "dense_summary.json") << R"({"depth_maps": 11, "redundant_views": 0})";
  EXPECT_NE(dense_card().find("dense.ply, 11 depth maps</div>"), std::string::npos);
  std::ofstream(tmp.path() / "dense_summary.json") << "not json";
  EXPECT_NE(dense_card().find("dense.ply</div>"), std::string::npos);
}

TEST(Report, OptionsAreChecked) {
  EXPECT_THROW(ReportOptions{}.Check(), OptionError);
  ReportOptions options{.output = "x"};
  EXPECT_NO_THROW(options.Check());
  options.data.thumbnail_width = 4;
  EXPECT_THROW(options.Check(), OptionError);
}

}  // namespace
}  // namespace varsfm
