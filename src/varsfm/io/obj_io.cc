#include "varsfm/io/obj_io.h"

#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "varsfm/image/image_file.h"
#include "varsfm/io/text_line.h"
#include "varsfm/util/atomic_file.h"
#include "varsfm/util/error.h"

namespace varsfm {

namespace fs = std::filesystem;

void WriteTexturedObj(const fs::path& dir, const TexturedMesh& mesh, const std::string& name) {
  std::vector<std::string> names = {name + ".obj", name + ".mtl"};
  for (size_t p = 0; p < mesh.pages.size(); ++p) names.push_back(fmt::format("{}_{}.png", name, p));
  WriteFilesAtomically(dir, names, [&](const fs::path& tmp) {
    {
      std::ofstream mtl(tmp / (name + ".mtl"));
      mtl << "# varsfm texture atlas\n";
      for (size_t p = 0; p < mesh.pages.size(); ++p) {
        // Unlit photo colours: ambient and diffuse white, no specular.
        mtl << fmt::format(
            "newmtl page_{}\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd {}_{}.png\n\n", p, name,
            p);
        WriteImage(tmp / names[2 + p], mesh.pages[p]);
      }
      if (!mtl) Fail("{}: cannot write", (dir / names[1]).string());
    }
    std::ofstream obj(tmp / names[0]);
    obj << "# varsfm textured mesh\nmtllib " << names[1] << "\n";
    for (const Eigen::Vector3d& v : mesh.vertices)
      obj << fmt::format("v {:.9g} {:.9g} {:.9g}\n", v.x(), v.y(), v.z());
    for (const Eigen::Vector2f& t : mesh.texcoords)
      obj << fmt::format("vt {:.8g} {:.8g}\n", t.x(), 1.0f - t.y());
    for (size_t p = 0; p < mesh.pages.size(); ++p) {
      obj << "usemtl page_" << p << "\n";
      for (size_t f = 0; f < mesh.faces.size(); ++f) {
        if (mesh.face_page[f] != static_cast<int>(p)) continue;
        const Eigen::Vector3i& v = mesh.faces[f];
        const Eigen::Vector3i& t = mesh.face_texcoords[f];
        obj << fmt::format("f {}/{} {}/{} {}/{}\n", v[0] + 1, t[0] + 1, v[1] + 1, t[1] + 1,
                           v[2] + 1, t[2] + 1);
      }
    }
    if (!obj.flush()) Fail("{}: cannot write", (dir / names[0]).string());
  });
}

namespace {

// Material name -> texture file, from an MTL file.
std::map<std::string, fs::path> ReadMtl(const fs::path& file) {
  std::ifstream in(file);
  if (!in) Fail("{}: cannot open material file", file.string());
  std::map<std::string, fs::path> textures;
  std::string line, current;
  while (ReadTextLine(in, &line)) {
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "newmtl") {
      s >> current;
    } else if (key == "map_Kd") {
      std::string rest;
      std::getline(s >> std::ws, rest);
      textures[current] = file.parent_path() / rest;
    }
  }
  return textures;
}

// "v/vt/vn", "v/vt" or "v" -> (v, vt), 0-based; OBJ's negative indices count from the end.
std::pair<int, int> ParseCorner(const std::string& token, size_t num_v, size_t num_vt) {
  int v = 0, vt = 0;
  const size_t slash = token.find('/');
  v = std::stoi(token.substr(0, slash));
  if (slash != std::string::npos && slash + 1 < token.size() && token[slash + 1] != '/')
    vt = std::stoi(token.substr(slash + 1));
  v = v < 0 ? static_cast<int>(num_v) + v : v - 1;
  vt = vt < 0 ? static_cast<int>(num_vt) + vt : vt - 1;
  return {v, vt};
}

}  // namespace

TexturedMesh ReadTexturedObj(const fs::path& obj_file) {
  std::ifstream in(obj_file);
  if (!in) Fail("{}: cannot open textured model", obj_file.string());
  TexturedMesh mesh;
  std::map<std::string, fs::path> textures;
  std::map<std::string, int> page_of_material;
  int page = -1;
  std::string line;
  size_t line_number = 0;
  try {
    while (ReadTextLine(in, &line)) {
      ++line_number;
      std::istringstream s(line);
      std::string key;
      s >> key;
      if (key == "v") {
        Eigen::Vector3d v;
        if (!(s >> v.x() >> v.y() >> v.z()))
          Fail("{}:{}: malformed vertex", obj_file.string(), line_number);
        mesh.vertices.push_back(v);
      } else if (key == "vt") {
        float u = 0, v = 0;
        s >> u >> v;
        mesh.texcoords.emplace_back(u, 1.0f - v);
      } else if (key == "mtllib") {
        std::string rest;
        std::getline(s >> std::ws, rest);
        textures = ReadMtl(obj_file.parent_path() / rest);
      } else if (key == "usemtl") {
        std::string material;
        s >> material;
        const auto it = page_of_material.find(material);
        if (it != page_of_material.end()) {
          page = it->second;
          continue;
        }
        const auto texture = textures.find(material);
        if (texture == textures.end())
          Fail("{}:{}: material {} has no texture", obj_file.string(), line_number, material);
        cv::Mat image = ReadImagePixels(texture->second, ColorMode::kColor);
        page = static_cast<int>(mesh.pages.size());
        page_of_material[material] = page;
        mesh.pages.push_back(image);
      } else if (key == "f") {
        std::vector<std::pair<int, int>> corners;
        std::string token;
        while (s >> token)
          corners.push_back(ParseCorner(token, mesh.vertices.size(), mesh.texcoords.size()));
        for (const auto& [v, vt] : corners) {
          if (v < 0 || v >= static_cast<int>(mesh.vertices.size()) || vt < 0 ||
              vt >= static_cast<int>(mesh.texcoords.size()))
            Fail("{}:{}: face index out of range or without texture coordinates", obj_file.string(),
                 line_number);
        }
        if (page < 0) Fail("{}:{}: face before any usemtl", obj_file.string(), line_number);
        for (size_t j = 2; j < corners.size(); ++j) {
          mesh.faces.emplace_back(corners[0].first, corners[j - 1].first, corners[j].first);
          mesh.face_texcoords.emplace_back(corners[0].second, corners[j - 1].second,
                                           corners[j].second);
          mesh.face_page.push_back(page);
        }
      }
    }
  } catch (const std::logic_error& e) {  // std::stoi on a malformed index
    Fail("{}:{}: malformed line", obj_file.string(), line_number);
  }
  if (mesh.faces.empty()) Fail("{}: textured model has no faces", obj_file.string());
  return mesh;
}

}  // namespace varsfm
