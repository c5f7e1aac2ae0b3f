#pragma once
// The page's own script for the 3D view (three.js): cameras as frustums coloured by focal
// length with their photos, the sparse points and the textured model, orbit controls, and a
// click on a camera (or on an image's mark in a chart or the table) showing its photo and
// figures. It reads the scene from <script id="varsfm-scene"> (viewer_scene.h) and the model
// from <script id="varsfm-glb"> (base64 glTF binary), and expects three.js, OrbitControls and
// GLTFLoader loaded before it.
namespace varsfm {

const char* ViewerScript();

}  // namespace varsfm
