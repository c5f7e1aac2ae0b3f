#include "varsfm/image/heif_codec.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <string>

#include <libheif/heif.h>
#include <opencv2/imgproc.hpp>

#include "varsfm/image/exif.h"

namespace varsfm {
namespace {

struct ContextDeleter {
  void operator()(heif_context* c) const { heif_context_free(c); }
};
struct HandleDeleter {
  void operator()(heif_image_handle* h) const { heif_image_handle_release(h); }
};
struct ImageDeleter {
  void operator()(heif_image* i) const { heif_image_release(i); }
};
using ContextPtr = std::unique_ptr<heif_context, ContextDeleter>;
using HandlePtr = std::unique_ptr<heif_image_handle, HandleDeleter>;
using ImagePtr = std::unique_ptr<heif_image, ImageDeleter>;

// The primary image's handle of the HEIF `data` (which the context reads without copying: it
// must outlive both); null when it cannot be read.
HandlePtr PrimaryImage(const uint8_t* data, size_t size, ContextPtr* context) {
  context->reset(heif_context_alloc());
  if (!*context ||
      heif_context_read_from_memory_without_copy(context->get(), data, size, nullptr).code !=
          heif_error_Ok)
    return nullptr;
  heif_image_handle* handle = nullptr;
  if (heif_context_get_primary_image_handle(context->get(), &handle).code != heif_error_Ok)
    return nullptr;
  return HandlePtr(handle);
}

}  // namespace

bool IsHeifPhotoName(const std::filesystem::path& path) {
  static constexpr std::array<const char*, 3> kExtensions = {".heic", ".heif", ".avif"};
  const std::string ext = LowerCaseExtension(path);
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

bool LooksLikeHeif(const uint8_t* data, size_t size) {
  if (data == nullptr || size < 12) return false;
  const heif_filetype_result type =
      heif_check_filetype(data, static_cast<int>(std::min<size_t>(size, 1 << 16)));
  return type == heif_filetype_yes_supported || type == heif_filetype_yes_unsupported;
}

cv::Mat DecodeHeif(const std::filesystem::path& path, const uint8_t* data, size_t size,
                   ColorMode mode) {
  ContextPtr context;
  const HandlePtr handle = PrimaryImage(data, size, &context);
  if (!handle) return {};
  const uint64_t width =
      static_cast<uint64_t>(std::max(heif_image_handle_get_width(handle.get()), 0));
  const uint64_t height =
      static_cast<uint64_t>(std::max(heif_image_handle_get_height(handle.get()), 0));
  RequireDecodablePixelCount(path, width, height);
  // Interleaved 8-bit RGB whatever the stored bit depth or chroma (libheif converts; a 10-bit
  // photo is scaled to 8 bits), the transformations applied (the default decoding options).
  heif_image* decoded = nullptr;
  if (heif_decode_image(handle.get(), &decoded, heif_colorspace_RGB, heif_chroma_interleaved_RGB,
                        nullptr)
          .code != heif_error_Ok)
    return {};
  const ImagePtr image(decoded);
  int stride = 0;
  const uint8_t* rgb =
      heif_image_get_plane_readonly(image.get(), heif_channel_interleaved, &stride);
  const int w = heif_image_get_width(image.get(), heif_channel_interleaved);
  const int h = heif_image_get_height(image.get(), heif_channel_interleaved);
  if (rgb == nullptr || w <= 0 || h <= 0) return {};
  const cv::Mat view(h, w, CV_8UC3, const_cast<uint8_t*>(rgb), static_cast<size_t>(stride));
  cv::Mat pixels;
  cv::cvtColor(view, pixels, mode == ColorMode::kGray ? cv::COLOR_RGB2GRAY : cv::COLOR_RGB2BGR);
  return pixels;
}

std::vector<uint8_t> HeifExif(const uint8_t* data, size_t size) {
  ContextPtr context;
  const HandlePtr handle = PrimaryImage(data, size, &context);
  if (!handle) return {};
  heif_item_id id = 0;
  if (heif_image_handle_get_list_of_metadata_block_IDs(handle.get(), "Exif", &id, 1) != 1)
    return {};
  const size_t block_size = heif_image_handle_get_metadata_size(handle.get(), id);
  std::vector<uint8_t> block(block_size);
  if (block_size < 4 ||
      heif_image_handle_get_metadata(handle.get(), id, block.data()).code != heif_error_Ok)
    return {};
  // The block starts with the big-endian offset from its 5th byte to the TIFF header (ISO/IEC
  // 23008-12, A.2.1); what lies between is usually the "Exif\0\0" header itself.
  const uint32_t offset = (uint32_t{block[0]} << 24) | (uint32_t{block[1]} << 16) |
                          (uint32_t{block[2]} << 8) | uint32_t{block[3]};
  if (offset > block_size - 4) return {};
  std::vector<uint8_t> exif(kExifHeader, kExifHeader + sizeof(kExifHeader));
  exif.insert(exif.end(), block.begin() + 4 + offset, block.end());
  return exif;
}

}  // namespace varsfm
