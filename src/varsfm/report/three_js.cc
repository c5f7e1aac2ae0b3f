#include "varsfm/report/three_js.h"

#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace varsfm {
namespace {

std::optional<std::string> ReadScript(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  std::string script = text.str();
  if (script.empty()) return std::nullopt;
  // "</script" ends a script element whatever the JavaScript around it; "<\/" is the same text
  // inside the string or regular-expression literal where it can legitimately occur.
  for (size_t at = 0; (at = script.find("</", at)) != std::string::npos; at += 3) {
    std::string next = script.substr(at + 2, 6);
    for (char& c : next) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (next == "script") script.insert(at + 1, "\\");
  }
  return script;
}

}  // namespace

std::optional<ThreeJs> LoadThreeJs(const std::filesystem::path& dir) {
  ThreeJs three;
  three.dir = dir;
  if (three.dir.empty()) {
    const char* env = std::getenv("VARSFM_THREE_JS_DIR");
    three.dir = env != nullptr && *env != '\0' ? env : kDebianThreeJsDir;
  }
  auto core = ReadScript(three.dir / "build" / "three.min.js");
  auto orbit = ReadScript(three.dir / "examples" / "js" / "controls" / "OrbitControls.js");
  auto gltf = ReadScript(three.dir / "examples" / "js" / "loaders" / "GLTFLoader.js");
  if (!core || !orbit || !gltf) return std::nullopt;
  // `REVISION = "111"` (three.js) or `REVISION="111"` (three.min.js). Searched by hand:
  // std::regex recurses per character and would overflow the stack on a megabyte of script.
  const size_t key = core->find("REVISION");
  if (key != std::string::npos) {
    size_t at = core->find_first_of("\"'", key);
    const size_t end = at == std::string::npos ? at : core->find_first_of("\"'", at + 1);
    if (end != std::string::npos && end - at < 16)
      three.revision = core->substr(at + 1, end - at - 1);
  }
  three.core = std::move(*core);
  three.orbit_controls = std::move(*orbit);
  three.gltf_loader = std::move(*gltf);
  return three;
}

}  // namespace varsfm
