#pragma once
// three.js for the report's 3D view, read from where a package installed it and inlined in the
// page (the report must open offline, with nothing beside it). varsfm ships no copy of it.
// Expected layout (Debian's libjs-three, or the npm package `three` up to r147, which still
// has examples/js): build/three.min.js, examples/js/controls/OrbitControls.js and
// examples/js/loaders/GLTFLoader.js, the last two as classic scripts that extend THREE.
#include <filesystem>
#include <optional>
#include <string>

namespace varsfm {

struct ThreeJs {
  std::filesystem::path dir;
  std::string revision;  // THREE.REVISION, e.g. "111"
  std::string core;
  std::string orbit_controls;
  std::string gltf_loader;
};

// Debian's libjs-three.
inline const char* kDebianThreeJsDir = "/usr/share/javascript/three";

// The scripts from `dir`; empty `dir`: $VARSFM_THREE_JS_DIR when set, else kDebianThreeJsDir.
// Nothing when a file is missing. Each script has "</script" written as "<\/script" (the same
// text to JavaScript), so that it can sit inside a <script> element.
std::optional<ThreeJs> LoadThreeJs(const std::filesystem::path& dir = {});

}  // namespace varsfm
