#include "support/heif_writer.h"

#include <memory>

#include <gtest/gtest.h>
#include <libheif/heif.h>

namespace varsfm::testing {

std::vector<uint8_t> EncodeHeic(const cv::Mat& bgr, int quality, int orientation,
                                const std::vector<uint8_t>& exif) {
  const auto check = [](heif_error e) {
    if (e.code != heif_error_Ok) ADD_FAILURE() << "libheif: " << e.message;
    return e.code == heif_error_Ok;
  };
  std::unique_ptr<heif_context, void (*)(heif_context*)> context(heif_context_alloc(),
                                                                 heif_context_free);
  heif_image* raw = nullptr;
  if (!check(heif_image_create(bgr.cols, bgr.rows, heif_colorspace_RGB, heif_chroma_interleaved_RGB,
                               &raw)))
    return {};
  std::unique_ptr<heif_image, void (*)(const heif_image*)> image(raw, heif_image_release);
  if (!check(heif_image_add_plane(image.get(), heif_channel_interleaved, bgr.cols, bgr.rows, 8)))
    return {};
  int stride = 0;
  uint8_t* plane = heif_image_get_plane(image.get(), heif_channel_interleaved, &stride);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b& p = bgr.at<cv::Vec3b>(y, x);
      uint8_t* q = plane + static_cast<size_t>(y) * stride + 3 * x;
      q[0] = p[2], q[1] = p[1], q[2] = p[0];
    }
  heif_encoder* raw_encoder = nullptr;
  if (!check(
          heif_context_get_encoder_for_format(context.get(), heif_compression_HEVC, &raw_encoder)))
    return {};
  std::unique_ptr<heif_encoder, void (*)(heif_encoder*)> encoder(raw_encoder, heif_encoder_release);
  heif_encoder_set_lossy_quality(encoder.get(), quality);
  std::unique_ptr<heif_encoding_options, void (*)(heif_encoding_options*)> options(
      heif_encoding_options_alloc(), heif_encoding_options_free);
  options->image_orientation = static_cast<heif_orientation>(orientation);
  heif_image_handle* handle = nullptr;
  if (!check(heif_context_encode_image(context.get(), image.get(), encoder.get(), options.get(),
                                       &handle)))
    return {};
  bool ok = true;
  if (!exif.empty())
    ok = check(heif_context_add_exif_metadata(context.get(), handle, exif.data(),
                                              static_cast<int>(exif.size())));
  heif_image_handle_release(handle);
  if (!ok) return {};
  std::vector<uint8_t> file;
  heif_writer writer{1, [](heif_context*, const void* data, size_t size, void* out) {
                       const auto* bytes = static_cast<const uint8_t*>(data);
                       static_cast<std::vector<uint8_t>*>(out)->insert(
                           static_cast<std::vector<uint8_t>*>(out)->end(), bytes, bytes + size);
                       return heif_error{heif_error_Ok, heif_suberror_Unspecified, ""};
                     }};
  if (!check(heif_context_write(context.get(), &writer, &file))) return {};
  return file;
}

}  // namespace varsfm::testing
