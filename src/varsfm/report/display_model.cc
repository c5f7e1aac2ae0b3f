#include "varsfm/report/display_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "varsfm/image/image_file.h"
#include "varsfm/image/jpeg_codec.h"
#include "varsfm/report/vertex_clustering.h"
#include "varsfm/util/error.h"
#include "varsfm/util/little_endian.h"
#include "varsfm/util/option_check.h"

namespace varsfm {
namespace {

using nlohmann::json;

// glTF 2.0 constants (Khronos specification, sections 3.6.2 and 4.4).
constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A;
constexpr uint32_t kChunkBin = 0x004E4942;
constexpr int kUnsignedByte = 5121, kUnsignedShort = 5123, kUnsignedInt = 5125, kFloat = 5126;

uint32_t ReadU32(const std::vector<uint8_t>& bytes, size_t at) {
  return GetLittleEndian<uint32_t>(reinterpret_cast<const char*>(bytes.data() + at));
}

// The JSON and binary chunks of a GLB file.
struct Glb {
  json gltf;
  const uint8_t* bin = nullptr;
  size_t bin_size = 0;
};

Glb ParseGlb(const std::vector<uint8_t>& bytes) {
  if (bytes.size() < 20 || ReadU32(bytes, 0) != kGlbMagic || ReadU32(bytes, 4) != 2)
    Fail("model.glb: not a binary glTF 2.0 file");
  Glb glb;
  size_t at = 12;
  while (at + 8 <= bytes.size()) {
    const size_t length = ReadU32(bytes, at);
    const uint32_t type = ReadU32(bytes, at + 4);
    if (at + 8 + length > bytes.size()) Fail("model.glb: truncated chunk");
    if (type == kChunkJson) {
      glb.gltf = json::parse(bytes.begin() + at + 8, bytes.begin() + at + 8 + length, nullptr,
                             /*allow_exceptions=*/false);
    } else if (type == kChunkBin) {
      glb.bin = bytes.data() + at + 8;
      glb.bin_size = length;
    }
    at += 8 + length;
  }
  if (!glb.gltf.is_object()) Fail("model.glb: no JSON chunk");
  return glb;
}

// The bytes of buffer view `index` (buffer 0, the binary chunk), and its stride.
std::pair<const uint8_t*, size_t> View(const Glb& glb, size_t index, size_t* stride) {
  const json& view = glb.gltf.at("bufferViews").at(index);
  const size_t offset = view.value("byteOffset", size_t{0}), length = view.at("byteLength");
  if (view.value("buffer", 0) != 0 || offset + length > glb.bin_size)
    Fail("model.glb: buffer view {} is outside the binary chunk", index);
  if (stride != nullptr) *stride = view.value("byteStride", size_t{0});
  return {glb.bin + offset, length};
}

// Accessor `index` as floats (`components` per element); 32-bit float data only.
std::vector<float> ReadFloats(const Glb& glb, size_t index, int components) {
  const json& accessor = glb.gltf.at("accessors").at(index);
  if (accessor.at("componentType") != kFloat) Fail("model.glb: accessor {} is not float", index);
  size_t stride = 0;
  const auto [data, size] = View(glb, accessor.at("bufferView"), &stride);
  const size_t count = accessor.at("count"), offset = accessor.value("byteOffset", size_t{0});
  if (stride == 0) stride = 4 * components;
  if (count > 0 && offset + (count - 1) * stride + 4 * components > size)
    Fail("model.glb: accessor {} overruns its buffer view", index);
  std::vector<float> values(count * components);
  for (size_t i = 0; i < count; ++i)
    std::memcpy(&values[i * components], data + offset + i * stride, 4 * components);
  return values;
}

std::vector<uint32_t> ReadIndices(const Glb& glb, size_t index) {
  const json& accessor = glb.gltf.at("accessors").at(index);
  const int type = accessor.at("componentType");
  const size_t width = type == kUnsignedByte ? 1 : type == kUnsignedShort ? 2 : 4;
  if (type != kUnsignedByte && type != kUnsignedShort && type != kUnsignedInt)
    Fail("model.glb: accessor {} is not an index type", index);
  const auto [data, size] = View(glb, accessor.at("bufferView"), nullptr);
  const size_t count = accessor.at("count"), offset = accessor.value("byteOffset", size_t{0});
  if (offset + count * width > size) Fail("model.glb: accessor {} overruns its view", index);
  std::vector<uint32_t> indices(count);
  for (size_t i = 0; i < count; ++i) {
    const auto* p = reinterpret_cast<const char*>(data + offset + i * width);
    indices[i] = width == 1   ? static_cast<uint8_t>(*p)
                 : width == 2 ? GetLittleEndian<uint16_t>(p)
                              : GetLittleEndian<uint32_t>(p);
  }
  return indices;
}

// Largest power of two <= min(size, limit), at least 1.
int PowerOfTwoAtMost(int size, int limit) {
  int p = 1;
  while (p * 2 <= std::min(size, limit)) p *= 2;
  return p;
}

// Writes the output: appends `data` as a 4-byte aligned buffer view.
class GlbBuilder {
 public:
  size_t AddView(const void* data, size_t size, int target, size_t stride = 0) {
    while (bin_.size() % 4) bin_.push_back(0);
    json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", size}};
    if (target != 0) view["target"] = target;
    if (stride != 0) view["byteStride"] = stride;
    const auto* p = static_cast<const uint8_t*>(data);
    bin_.insert(bin_.end(), p, p + size);
    gltf["bufferViews"].push_back(view);
    return gltf["bufferViews"].size() - 1;
  }
  size_t AddAccessor(json accessor) {
    gltf["accessors"].push_back(std::move(accessor));
    return gltf["accessors"].size() - 1;
  }
  std::vector<uint8_t> Finish() {
    while (bin_.size() % 4) bin_.push_back(0);
    gltf["buffers"] = json::array({{{"byteLength", bin_.size()}}});
    std::string text = gltf.dump();
    while (text.size() % 4) text += ' ';
    std::vector<uint8_t> out;
    const auto put = [&out](uint32_t v) { AppendLittleEndian(&out, v); };
    put(kGlbMagic);
    put(2);
    put(static_cast<uint32_t>(12 + 8 + text.size() + 8 + bin_.size()));
    put(static_cast<uint32_t>(text.size()));
    put(kChunkJson);
    out.insert(out.end(), text.begin(), text.end());
    put(static_cast<uint32_t>(bin_.size()));
    put(kChunkBin);
    out.insert(out.end(), bin_.begin(), bin_.end());
    return out;
  }
  json gltf = {{"asset", {{"version", "2.0"}, {"generator", "varsfm report"}}},
               {"bufferViews", json::array()},
               {"accessors", json::array()}};

 private:
  std::vector<uint8_t> bin_;
};

// Image `index` re-encoded as a JPEG page; returns the new texture's index.
size_t AddTexture(const Glb& glb, size_t index, const DisplayModelOptions& options,
                  GlbBuilder* out) {
  const auto [data, size] = View(glb, glb.gltf.at("images").at(index).at("bufferView"), nullptr);
  const cv::Mat page =
      DecodeImage("model.glb", std::vector<uint8_t>(data, data + size), ColorMode::kColor);
  cv::Mat small;
  cv::resize(page, small,
             cv::Size(PowerOfTwoAtMost(page.cols, options.max_texture_size),
                      PowerOfTwoAtMost(page.rows, options.max_texture_size)),
             0, 0, cv::INTER_AREA);
  std::vector<uint8_t> jpeg;
  if (!EncodeJpeg(small, options.jpeg_quality, &jpeg)) Fail("model.glb: cannot encode a page");
  const size_t view = out->AddView(jpeg.data(), jpeg.size(), 0);
  out->gltf["images"].push_back({{"bufferView", view}, {"mimeType", "image/jpeg"}});
  out->gltf["textures"].push_back({{"source", out->gltf["images"].size() - 1}, {"sampler", 0}});
  return out->gltf["textures"].size() - 1;
}

// Adds one triangle primitive: positions quantised within [low, high], texture coordinates
// quantised when they lie in [0, 1], indices 16-bit when they fit.
json AddPrimitive(const std::vector<float>& positions, const std::vector<float>& uvs,
                  const std::vector<uint32_t>& indices, const std::array<float, 3>& low,
                  const std::array<float, 3>& high, GlbBuilder* out) {
  const size_t n = positions.size() / 3;
  // VEC3 of uint16 padded to 8 bytes: vertex attributes must be 4-byte aligned.
  std::vector<uint16_t> q(n * 4, 0);
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const float span = std::max(high[k] - low[k], 1e-12f);
      q[4 * i + k] =
          static_cast<uint16_t>(std::lround((positions[3 * i + k] - low[k]) / span * 65535.0));
    }
  std::array<uint16_t, 3> qmin = {65535, 65535, 65535}, qmax = {0, 0, 0};
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      qmin[k] = std::min(qmin[k], q[4 * i + k]);
      qmax[k] = std::max(qmax[k], q[4 * i + k]);
    }
  json attributes;
  attributes["POSITION"] =
      out->AddAccessor({{"bufferView", out->AddView(q.data(), q.size() * 2, 34962, 8)},
                        {"componentType", kUnsignedShort},
                        {"normalized", true},
                        {"count", n},
                        {"type", "VEC3"},
                        {"min", {qmin[0], qmin[1], qmin[2]}},
                        {"max", {qmax[0], qmax[1], qmax[2]}}});
  if (!uvs.empty()) {
    const bool unit = std::all_of(uvs.begin(), uvs.end(), [](float t) { return t >= 0 && t <= 1; });
    if (unit) {
      std::vector<uint16_t> t(uvs.size());
      for (size_t i = 0; i < uvs.size(); ++i)
        t[i] = static_cast<uint16_t>(std::lround(uvs[i] * 65535.0));
      attributes["TEXCOORD_0"] =
          out->AddAccessor({{"bufferView", out->AddView(t.data(), t.size() * 2, 34962)},
                            {"componentType", kUnsignedShort},
                            {"normalized", true},
                            {"count", n},
                            {"type", "VEC2"}});
    } else {
      attributes["TEXCOORD_0"] =
          out->AddAccessor({{"bufferView", out->AddView(uvs.data(), uvs.size() * 4, 34962)},
                            {"componentType", kFloat},
                            {"count", n},
                            {"type", "VEC2"}});
    }
  }
  size_t index_view;
  int index_type = kUnsignedInt;
  if (n <= 65535) {
    std::vector<uint16_t> narrow(indices.begin(), indices.end());
    index_view = out->AddView(narrow.data(), narrow.size() * 2, 34963);
    index_type = kUnsignedShort;
  } else {
    index_view = out->AddView(indices.data(), indices.size() * 4, 34963);
  }
  const size_t index_accessor = out->AddAccessor({{"bufferView", index_view},
                                                  {"componentType", index_type},
                                                  {"count", indices.size()},
                                                  {"type", "SCALAR"}});
  return {{"attributes", attributes}, {"indices", index_accessor}, {"mode", 4}};
}

}  // namespace

void DisplayModelOptions::Check() const {
  CheckAtLeast("model.max_faces", max_faces, 1);
  CheckAtLeast("model.max_texture_size", max_texture_size, 1);
  CheckInRange("model.jpeg_quality", jpeg_quality, 1, 100);
}

std::vector<uint8_t> CompactGlbForDisplay(const std::vector<uint8_t>& bytes,
                                          const DisplayModelOptions& options) {
  const Glb glb = ParseGlb(bytes);
  try {
    std::vector<ClusteredPart> parts;
    std::vector<std::optional<size_t>> images;  // per part: the atlas page
    for (const json& mesh : glb.gltf.value("meshes", json::array())) {
      for (const json& p : mesh.at("primitives")) {
        if (p.value("mode", 4) != 4) Fail("model.glb: a primitive is not made of triangles");
        ClusteredPart part;
        part.positions = ReadFloats(glb, p.at("attributes").at("POSITION"), 3);
        if (p.at("attributes").contains("TEXCOORD_0"))
          part.uvs = ReadFloats(glb, p["attributes"]["TEXCOORD_0"], 2);
        if (p.contains("indices")) {
          part.indices = ReadIndices(glb, p["indices"]);
        } else {
          part.indices.resize(part.positions.size() / 3);
          for (size_t i = 0; i < part.indices.size(); ++i) part.indices[i] = i;
        }
        const size_t n = part.positions.size() / 3;
        if (std::any_of(part.indices.begin(), part.indices.end(),
                        [n](uint32_t i) { return i >= n; }))
          Fail("model.glb: an index is out of range");
        std::optional<size_t> image;
        if (p.contains("material")) {
          const json& material = glb.gltf.at("materials").at(p["material"].get<size_t>());
          const json texture = material.value("pbrMetallicRoughness", json::object())
                                   .value("baseColorTexture", json::object());
          if (texture.contains("index"))
            image = glb.gltf.at("textures").at(texture["index"].get<size_t>()).at("source");
        }
        parts.push_back(std::move(part));
        images.push_back(image);
      }
    }
    if (parts.empty()) Fail("model.glb: no mesh");
    parts = ClusterVertices(parts, options.max_faces);
    std::array<float, 3> low, high;
    low.fill(std::numeric_limits<float>::max());
    high.fill(-std::numeric_limits<float>::max());
    for (const ClusteredPart& part : parts)
      for (size_t i = 0; i < part.positions.size(); ++i) {
        low[i % 3] = std::min(low[i % 3], part.positions[i]);
        high[i % 3] = std::max(high[i % 3], part.positions[i]);
      }

    GlbBuilder out;
    out.gltf["samplers"] = {
        {{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}};
    out.gltf["extensionsUsed"] = {"KHR_materials_unlit", "KHR_mesh_quantization"};
    out.gltf["extensionsRequired"] = {"KHR_mesh_quantization"};
    std::map<size_t, size_t> texture_of_image;
    json gltf_primitives = json::array();
    for (size_t i = 0; i < parts.size(); ++i) {
      json primitive =
          AddPrimitive(parts[i].positions, parts[i].uvs, parts[i].indices, low, high, &out);
      json material = {{"doubleSided", true},
                       {"extensions", {{"KHR_materials_unlit", json::object()}}},
                       {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}};
      if (images[i]) {
        if (!texture_of_image.count(*images[i]))
          texture_of_image[*images[i]] = AddTexture(glb, *images[i], options, &out);
        material["pbrMetallicRoughness"]["baseColorTexture"] = {
            {"index", texture_of_image[*images[i]]}};
      }
      out.gltf["materials"].push_back(material);
      primitive["material"] = out.gltf["materials"].size() - 1;
      gltf_primitives.push_back(primitive);
    }
    out.gltf["meshes"] = {{{"primitives", gltf_primitives}}};
    // Dequantisation: x = low + (high - low) * q / 65535 (normalised: the GPU divides).
    out.gltf["nodes"] = {{{"mesh", 0},
                          {"translation", {low[0], low[1], low[2]}},
                          {"scale",
                           {std::max(high[0] - low[0], 1e-12f), std::max(high[1] - low[1], 1e-12f),
                            std::max(high[2] - low[2], 1e-12f)}}}};
    out.gltf["scenes"] = {{{"nodes", {0}}}};
    out.gltf["scene"] = 0;
    return out.Finish();
  } catch (const json::exception& e) {
    Fail("model.glb: unexpected glTF structure ({})", e.what());
  }
}

}  // namespace varsfm
