#include "varsfm/image/exif.h"

#include <libexif/exif-data.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace varsfm {
namespace {

struct ExifDataDeleter {
  void operator()(ExifData* data) const { exif_data_unref(data); }
};
using ExifDataPtr = std::unique_ptr<ExifData, ExifDataDeleter>;

// The focal-length tags live in the Exif sub-IFD; looking only there avoids picking up the
// thumbnail's IFD1 entries.
ExifEntry* FindExifEntry(ExifData* data, ExifTag tag) {
  return exif_content_get_entry(data->ifd[EXIF_IFD_EXIF], tag);
}

std::optional<double> ReadNumber(ExifData* data, ExifTag tag) {
  ExifEntry* entry = FindExifEntry(data, tag);
  if (entry == nullptr || entry->components < 1 || entry->data == nullptr) return std::nullopt;
  const ExifByteOrder order = exif_data_get_byte_order(data);
  double value = 0;
  switch (entry->format) {
    case EXIF_FORMAT_RATIONAL: {
      const ExifRational r = exif_get_rational(entry->data, order);
      if (r.denominator == 0) return std::nullopt;
      value = static_cast<double>(r.numerator) / r.denominator;
      break;
    }
    case EXIF_FORMAT_SRATIONAL: {
      const ExifSRational r = exif_get_srational(entry->data, order);
      if (r.denominator == 0) return std::nullopt;
      value = static_cast<double>(r.numerator) / r.denominator;
      break;
    }
    case EXIF_FORMAT_SHORT:
      value = exif_get_short(entry->data, order);
      break;
    case EXIF_FORMAT_LONG:
      value = exif_get_long(entry->data, order);
      break;
    default:
      return std::nullopt;
  }
  if (!std::isfinite(value) || value <= 0) return std::nullopt;
  return value;
}

// Millimetres per FocalPlaneResolutionUnit (EXIF 2.3: 2 = inch, the default, 3 = cm; TIFF/EP
// adds 4 = mm and 5 = micrometre, which some cameras write).
// Compared as a double: a corrupt tag may hold any rational, and converting one beyond int's
// range is undefined.
std::optional<double> ResolutionUnitMm(ExifData* data) {
  const double unit = ReadNumber(data, EXIF_TAG_FOCAL_PLANE_RESOLUTION_UNIT).value_or(2);
  if (unit == 2) return 25.4;
  if (unit == 3) return 10.0;
  if (unit == 4) return 1.0;
  if (unit == 5) return 0.001;
  return std::nullopt;
}

// Rejects nonsense (a field of view wider than ~175 or narrower than ~0.5 degrees): such values
// come from broken or placeholder tags and would mislead the calibration.
std::optional<double> PlausibleFocal(double focal_px, int width, int height) {
  const double max_size = std::max(width, height);
  if (!(focal_px >= 0.05 * max_size && focal_px <= 100.0 * max_size)) return std::nullopt;
  return focal_px;
}

}  // namespace

int ExifOrientation(const uint8_t* data, size_t size) {
  if (data == nullptr || size == 0) return 1;
  // Not exif_data_new_from_data: its "follow the specification" option fills in missing
  // mandatory tags with defaults; only a tag the file really has may turn the image.
  ExifDataPtr exif(exif_data_new());
  if (!exif) return 1;
  exif_data_unset_option(exif.get(), EXIF_DATA_OPTION_FOLLOW_SPECIFICATION);
  exif_data_load_data(exif.get(), data, static_cast<unsigned int>(size));
  ExifEntry* entry = exif_content_get_entry(exif->ifd[EXIF_IFD_0], EXIF_TAG_ORIENTATION);
  if (entry == nullptr || entry->components < 1 || entry->data == nullptr ||
      entry->format != EXIF_FORMAT_SHORT) {
    return 1;
  }
  const int orientation = exif_get_short(entry->data, exif_data_get_byte_order(exif.get()));
  return orientation >= 1 && orientation <= 8 ? orientation : 1;
}

std::optional<double> FocalPixelsFrom35mmEquivalent(double f35_mm, int width, int height) {
  if (!(f35_mm > 0) || width <= 0 || height <= 0) return std::nullopt;
  return PlausibleFocal(f35_mm * std::hypot(width, height) / std::hypot(36.0, 24.0), width, height);
}

std::optional<double> ExifFocalLengthPixels(const uint8_t* data, size_t size, int width,
                                            int height) {
  if (data == nullptr || size == 0 || width <= 0 || height <= 0) return std::nullopt;
  ExifDataPtr exif(exif_data_new_from_data(data, static_cast<unsigned int>(size)));
  if (!exif) return std::nullopt;

  const double max_size = std::max(width, height);
  std::optional<double> focal_px;
  if (const auto f35 = ReadNumber(exif.get(), EXIF_TAG_FOCAL_LENGTH_IN_35MM_FILM)) {
    return FocalPixelsFrom35mmEquivalent(*f35, width, height);
  } else if (const auto f_mm = ReadNumber(exif.get(), EXIF_TAG_FOCAL_LENGTH)) {
    const auto x_resolution = ReadNumber(exif.get(), EXIF_TAG_FOCAL_PLANE_X_RESOLUTION);
    const auto unit_mm = ResolutionUnitMm(exif.get());
    if (x_resolution && unit_mm) {
      // The resolution refers to the sensor's full image; a resized copy scales it. Comparing
      // the larger sides keeps this independent of the orientation.
      double resize = 1.0;
      const auto pixel_x = ReadNumber(exif.get(), EXIF_TAG_PIXEL_X_DIMENSION);
      const auto pixel_y = ReadNumber(exif.get(), EXIF_TAG_PIXEL_Y_DIMENSION);
      if (pixel_x && pixel_y) resize = max_size / std::max(*pixel_x, *pixel_y);
      focal_px = *f_mm * (*x_resolution / *unit_mm) * resize;
    }
  }
  return focal_px ? PlausibleFocal(*focal_px, width, height) : std::nullopt;
}

}  // namespace varsfm
