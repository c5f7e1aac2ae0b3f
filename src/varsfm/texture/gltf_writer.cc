#include "varsfm/texture/gltf_writer.h"

#include <cstring>
#include <map>

#include <tiny_gltf.h>

#include "varsfm/image/png_codec.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"

namespace varsfm {
namespace {

// Appends raw bytes to the buffer, 4-byte aligned as glTF accessors require, and returns the
// new buffer view's index.
int AddBufferView(tinygltf::Model* model, const void* data, size_t bytes, int target) {
  std::vector<unsigned char>& buffer = model->buffers[0].data;
  while (buffer.size() % 4) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), p, p + bytes);
  model->bufferViews.push_back(view);
  return static_cast<int>(model->bufferViews.size()) - 1;
}

// An accessor of `count` elements of `type` (scalar, VEC2, ...) whose components are
// `component_type`, over `values` in a new buffer view for `target`.
template <typename T>
tinygltf::Accessor AccessorOver(tinygltf::Model* model, const std::vector<T>& values, int target,
                                int component_type, int type, size_t count) {
  tinygltf::Accessor accessor;
  accessor.bufferView = AddBufferView(model, values.data(), values.size() * sizeof(T), target);
  accessor.componentType = component_type;
  accessor.count = count;
  accessor.type = type;
  return accessor;
}

}  // namespace

void WriteGlb(const std::filesystem::path& file, const TexturedMesh& mesh) {
  if (mesh.faces.empty()) Fail("{}: no faces to write", file.string());
  // glTF attributes are per vertex: one glTF vertex per (position, texcoord) pair used.
  std::map<std::pair<int, int>, uint32_t> vertex_of_pair;
  std::vector<float> positions, texcoords;
  std::vector<std::vector<uint32_t>> indices(mesh.pages.size());
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const std::pair<int, int> key(mesh.faces[f][k], mesh.face_texcoords[f][k]);
      auto [it, inserted] =
          vertex_of_pair.try_emplace(key, static_cast<uint32_t>(positions.size() / 3));
      if (inserted) {
        const Eigen::Vector3f p = mesh.vertices[key.first].cast<float>();
        positions.insert(positions.end(), {p.x(), p.y(), p.z()});
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
        const Eigen::Vector2f& t = mesh.texcoords[key.second];
        texcoords.insert(texcoords.end(), {t.x(), t.y()});
      }
      indices[mesh.face_page[f]].push_back(it->second);
    }
  }

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "varsfm";
  model.buffers.resize(1);
  const size_t num_vertices = positions.size() / 3;

  tinygltf::Accessor position =
      AccessorOver(&model, positions, TINYGLTF_TARGET_ARRAY_BUFFER, TINYGLTF_COMPONENT_TYPE_FLOAT,
                   TINYGLTF_TYPE_VEC3, num_vertices);
  position.minValues = {lo.x(), lo.y(), lo.z()};  // required for POSITION by the spec
  position.maxValues = {hi.x(), hi.y(), hi.z()};
  model.accessors.push_back(position);
  model.accessors.push_back(AccessorOver(&model, texcoords, TINYGLTF_TARGET_ARRAY_BUFFER,
                                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2,
                                         num_vertices));

  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);

  tinygltf::Mesh gltf_mesh;
  for (size_t p = 0; p < mesh.pages.size(); ++p) {
    if (indices[p].empty()) continue;
    std::vector<uint8_t> png;
    if (!EncodePng(mesh.pages[p], &png)) Fail("{}: cannot encode atlas", file.string());
    tinygltf::Image image;
    image.mimeType = "image/png";
    image.bufferView = AddBufferView(&model, png.data(), png.size(), 0);
    model.images.push_back(image);
    tinygltf::Texture texture;
    texture.source = static_cast<int>(model.images.size()) - 1;
    texture.sampler = 0;
    model.textures.push_back(texture);

    tinygltf::Material material;
    material.name = "page_" + std::to_string(p);
    material.pbrMetallicRoughness.baseColorTexture.index =
        static_cast<int>(model.textures.size()) - 1;
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    material.pbrMetallicRoughness.roughnessFactor = 1.0;
    material.doubleSided = true;  // reconstructed meshes are not consistently oriented
    material.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
    model.materials.push_back(material);

    model.accessors.push_back(AccessorOver(&model, indices[p], TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                                           TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                                           TINYGLTF_TYPE_SCALAR, indices[p].size()));

    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = 0;
    primitive.attributes["TEXCOORD_0"] = 1;
    primitive.indices = static_cast<int>(model.accessors.size()) - 1;
    primitive.material = static_cast<int>(model.materials.size()) - 1;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    gltf_mesh.primitives.push_back(primitive);
  }
  model.extensionsUsed.push_back("KHR_materials_unlit");
  model.meshes.push_back(gltf_mesh);
  tinygltf::Node node;
  node.mesh = 0;
  // The model's frame is the vision convention (y down, z forward, as the first camera of a
  // reconstruction usually is); glTF is y up. A half turn about x on the node shows the model
  // upright in viewers while the vertex data stays in the sparse model's coordinates.
  node.rotation = {1.0, 0.0, 0.0, 0.0};  // quaternion (x, y, z, w)
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  WriteFileViaTemporary(file, [&](const std::filesystem::path& tmp) {
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToFile(&model, tmp.string(), /*embedImages=*/true,
                                     /*embedBuffers=*/true, /*prettyPrint=*/false,
                                     /*writeBinary=*/true))
      Fail("{}: cannot write", file.string());
  });
}

}  // namespace varsfm
