// The mesh stage on real photographs: bundler/kermit's dense cloud, on which the former default
// (CGAL's Poisson) crashed the process in its surface mesher, must give a mesh that passes the
// check, with its figures in summary.json. The default surface (Delaunay) reads the cloud with the
// visibility beside it (dense.ply.vis) and the sparse model's cameras, and `run` refines it from
// the photos; screened Poisson reads the same cloud through `mesh --method poisson`.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "support/test_data.h"

namespace varsfm {
namespace {

using testing::RunCommand;
using testing::TempDir;
using testing::VarsfmBinary;

// The face count in a binary PLY's header.
long FacesInPly(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  for (std::string line; std::getline(in, line) && line != "end_header";)
    if (line.starts_with("element face ")) return std::stol(line.substr(13));
  return -1;
}

TEST(MeshStage, KermitGivesAMeshOnItsDensePoints) {
  VARSFM_REQUIRE_SHARED_DATA(kermit, "bundler/kermit");
  TempDir tmp("mesh_stage_kermit");
  const auto out = tmp.path() / "out";
  std::string log;
  ASSERT_EQ(RunCommand(fmt::format("{} run {} {} --until mesh", testing::ShellQuote(VarsfmBinary()),
                                   testing::ShellQuote(kermit), testing::ShellQuote(out)),
                       &log),
            0)
      << log;
  ASSERT_TRUE(std::filesystem::exists(out / "mesh.ply"));
  // `run` refines the surface from the photos (mesh/photometric_refinement.h).
  EXPECT_NE(log.find("photometric refinement, 2 iterations"), std::string::npos) << log;
  const nlohmann::json mesh = nlohmann::json::parse(std::ifstream(out / "summary.json"))["mesh"];
  EXPECT_GT(mesh["points"].get<double>(), 100000) << mesh;
  // Merged at the default spacing: the memory cap does not bind on kermit's cloud.
  EXPECT_LT(mesh["surface_points"].get<double>(), mesh["points"].get<double>()) << mesh;
  EXPECT_GT(mesh["surface_points"].get<double>(), 20000) << mesh;
  EXPECT_NEAR(mesh["merge_spacing"].get<double>(), 2.0, 1e-9) << mesh;
  EXPECT_GE(mesh["faces"].get<double>(), 2000) << mesh;
  EXPECT_LT(mesh["relative_distance"].get<double>(), 0.005) << mesh;
  EXPECT_NEAR(mesh["relative_distance"].get<double>(),
              mesh["median_distance"].get<double>() / mesh["extent"].get<double>(), 1e-12);
  // A tenth of the vertices or more measured, none sent far: the mean move is under a hundredth
  // of the cloud's extent.
  EXPECT_GT(mesh["refinement"]["measured_vertices"].get<double>(),
            0.1 * mesh["surface_points"].get<double>())
      << mesh;
  EXPECT_LT(mesh["refinement"]["mean_offset"].get<double>(), 0.01 * mesh["extent"].get<double>())
      << mesh;

  // The other surface on the same points: the mesh check passes (exit 0) and the mesh is not
  // tiny.
  ASSERT_EQ(RunCommand(fmt::format("{} mesh --input {} --output {} --method poisson",
                                   testing::ShellQuote(VarsfmBinary()),
                                   testing::ShellQuote(out / "dense.ply"),
                                   testing::ShellQuote(tmp.path() / "poisson")),
                       &log),
            0)
      << log;
  EXPECT_GE(FacesInPly(tmp.path() / "poisson" / "mesh.ply"), 2000) << log;

  // `mesh` without the photos makes no photometric refinement, and says so.
  EXPECT_NE(log.find("no photometric refinement"), std::string::npos) << log;

  // With a photo missing from --images: one line naming it, before the surface is built.
  const auto partial = tmp.path() / "partial";
  std::filesystem::create_directories(partial);
  for (const auto& entry : std::filesystem::directory_iterator(kermit))
    if (entry.path().filename() != "kermit005.jpg")
      std::filesystem::copy_file(entry.path(), partial / entry.path().filename());
  EXPECT_EQ(RunCommand(fmt::format("{} mesh --input {} --output {} --images {}",
                                   testing::ShellQuote(VarsfmBinary()),
                                   testing::ShellQuote(out / "dense.ply"),
                                   testing::ShellQuote(tmp.path() / "partial_mesh"),
                                   testing::ShellQuote(partial)),
                       &log),
            1)
      << log;
  EXPECT_NE(log.find("registered photos are not in"), std::string::npos) << log;
  EXPECT_NE(log.find("(the first: kermit005.jpg)"), std::string::npos) << log;
  EXPECT_EQ(log.find("surface:"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(tmp.path() / "partial_mesh" / "mesh.ply"));
}

}  // namespace
}  // namespace varsfm
