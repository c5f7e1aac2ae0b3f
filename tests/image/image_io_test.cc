#include "varsfm/image/image_io.h"

#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/test_data.h"
#include "varsfm/image/image_list.h"
#include "varsfm/image/jpeg_check.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

namespace fs = std::filesystem;

cv::Mat RandomImage(int width, int height) {
  cv::Mat image(height, width, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

std::vector<uint8_t> ReadBytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

void WriteBytes(const fs::path& path, const uint8_t* data, size_t size) {
  std::ofstream file(path, std::ios::binary);
  file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

void Touch(const fs::path& path) { std::ofstream(path) << "x"; }

TEST(ListImages, SortedRecursiveRelativeNamesOfImageFilesOnly) {
  testing::TempDir dir("list_images");
  fs::create_directories(dir.path() / "sub" / "deeper");
  for (const char* name : {"b.jpg", "a.PNG", "e.jpeg", "notes.txt", "model.ply", "sub/c.tif",
                           "sub/deeper/d.bmp", "sub/f.TIFF", "noext"}) {
    Touch(dir.path() / name);
  }
  const std::vector<std::string> expected = {
      "a.PNG", "b.jpg", "e.jpeg", "sub/c.tif", "sub/deeper/d.bmp", "sub/f.TIFF"};
  EXPECT_EQ(ListImages(dir.path()), expected);
}

// A phone's HEIC and AVIF photos and a camera's raw files are photos; GIF is not read.
TEST(ListImages, HeifAndRawPhotosAreListed) {
  testing::TempDir dir("list_heif_raw");
  for (const char* name :
       {"IMG_0001.HEIC", "IMG_0002.heif", "c.avif", "d.gif", "e.DNG", "f.cr2", "g.NEF"})
    Touch(dir.path() / name);
  const std::vector<std::string> expected = {"IMG_0001.HEIC", "IMG_0002.heif", "c.avif",
                                             "e.DNG",         "f.cr2",         "g.NEF"};
  EXPECT_EQ(ListImages(dir.path()), expected);
}

// Hidden files and folders are not the user's photos: macOS's "._" metadata beside each copied
// photo, a file manager's thumbnails.
TEST(ListImages, HiddenFilesAndFoldersAreSkipped) {
  testing::TempDir dir("list_images_hidden");
  fs::create_directories(dir.path() / ".thumbnails" / "normal");
  fs::create_directories(dir.path() / "sub");
  for (const char* name : {"a.jpg", "._a.jpg", ".hidden.png", ".thumbnails/a.jpg",
                           ".thumbnails/normal/b.png", "sub/c.jpg", "sub/._c.jpg"}) {
    Touch(dir.path() / name);
  }
  const std::vector<std::string> expected = {"a.jpg", "sub/c.jpg"};
  EXPECT_EQ(ListImages(dir.path()), expected);
}

TEST(ListImages, MissingFolderOrFileIsAnError) {
  testing::TempDir dir("list_images_missing");
  EXPECT_THROW(ListImages(dir.path() / "absent"), Error);
  Touch(dir.path() / "a.jpg");
  EXPECT_THROW(ListImages(dir.path() / "a.jpg"), Error);
}

// A link is listed under its own name; a second name for a photo of the set (a link to it, a
// folder linked twice) is skipped, as are broken links, link loops and a folder linked into
// itself, never an error.
TEST(ListImages, LinksToPhotosOfTheSetLoopsAndBrokenLinksAreSkipped) {
  testing::TempDir dir("list_images_links");
  const fs::path images = dir.path() / "images";
  fs::create_directories(images / "sub");
  fs::create_directories(dir.path() / "elsewhere");
  for (const char* name : {"b.jpg", "sub/c.jpg"}) Touch(images / name);
  Touch(dir.path() / "elsewhere" / "x.jpg");
  fs::create_symlink("b.jpg", images / "a_link.jpg");                // same photo as b.jpg
  fs::create_symlink("../elsewhere/x.jpg", images / "outside.jpg");  // a photo of its own
  fs::create_symlink("absent.jpg", images / "broken.jpg");
  fs::create_symlink("loop2.jpg", images / "loop1.jpg");
  fs::create_symlink("loop1.jpg", images / "loop2.jpg");
  fs::create_symlink(".", images / "self");        // a folder containing itself
  fs::create_symlink("sub", images / "sub_link");  // a second name for sub/
  const std::vector<std::string> expected = {"b.jpg", "outside.jpg", "sub/c.jpg"};
  EXPECT_EQ(ListImages(images), expected);
}

TEST(ReadPhoto, ReadsEveryFormatInGreyAndColour) {
  testing::TempDir dir("read_formats");
  const cv::Mat original = RandomImage(64, 48);
  for (const char* name : {"a.jpg", "a.png", "a.tif", "a.bmp", "a.webp", "a.jp2", "a.ppm"}) {
    SCOPED_TRACE(name);
    WriteImage(dir.path() / name, original);
    EXPECT_TRUE(HasImageExtension(dir.path() / name));
    const Photo color = ReadPhoto(dir.path() / name, ColorMode::kColor);
    EXPECT_EQ(color.width(), 64);
    EXPECT_EQ(color.height(), 48);
    EXPECT_EQ(color.pixels.type(), CV_8UC3);
    EXPECT_FALSE(color.exif_focal_px.has_value());
    const Photo gray = ReadPhoto(dir.path() / name, ColorMode::kGray);
    EXPECT_EQ(gray.pixels.type(), CV_8UC1);
    EXPECT_EQ(gray.pixels.size(), color.pixels.size());
  }
  // Lossless formats come back exactly.
  const Photo png = ReadPhoto(dir.path() / "a.png", ColorMode::kColor);
  EXPECT_EQ(cv::norm(png.pixels, original, cv::NORM_INF), 0.0);
}

TEST(ReadPhoto, TextWithAnImageExtensionIsAnErrorNamingTheFile) {
  testing::TempDir dir("read_text");
  const fs::path path = dir.path() / "not_an_image.jpg";
  std::ofstream(path) << "this is text, not a JPEG\n";
  try {
    ReadPhoto(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not_an_image.jpg"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line";
  }
  EXPECT_THROW(ReadPhoto(dir.path() / "absent.png"), Error);
  WriteBytes(dir.path() / "empty.png", nullptr, 0);
  EXPECT_THROW(ReadPhoto(dir.path() / "empty.png"), Error);
}

TEST(ReadPhoto, TruncatedJpegIsAnError) {
  testing::TempDir dir("read_truncated");
  const fs::path full = dir.path() / "full.jpg";
  WriteImage(full, RandomImage(200, 150));
  const std::vector<uint8_t> bytes = ReadBytes(full);
  EXPECT_TRUE(IsCompleteJpeg(bytes.data(), bytes.size()));
  EXPECT_NO_THROW(ReadPhoto(full));

  // libjpeg would decode the first half and grey-fill the rest without an error.
  const fs::path half = dir.path() / "half.jpg";
  WriteBytes(half, bytes.data(), bytes.size() / 2);
  EXPECT_FALSE(IsCompleteJpeg(bytes.data(), bytes.size() / 2));
  EXPECT_THROW(ReadPhoto(half), Error);
  // Cut just before the end-of-image marker.
  EXPECT_FALSE(IsCompleteJpeg(bytes.data(), bytes.size() - 2));
  // Headers only.
  EXPECT_FALSE(IsCompleteJpeg(bytes.data(), 20));
}

TEST(ReadPhoto, TruncatedRealPhotographIsAnError) {
  VARSFM_REQUIRE_SHARED_DATA(photo, "bundler/kermit/kermit000.jpg");
  const std::vector<uint8_t> bytes = ReadBytes(photo);
  EXPECT_TRUE(IsCompleteJpeg(bytes.data(), bytes.size()));
  for (const size_t cut : {bytes.size() / 4, bytes.size() / 2, bytes.size() - 100}) {
    EXPECT_FALSE(IsCompleteJpeg(bytes.data(), cut)) << "cut at " << cut;
  }
}

}  // namespace
}  // namespace varsfm
