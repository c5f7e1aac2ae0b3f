#include "varsfm/report/viewer_script.h"

namespace varsfm {
namespace {

// The script's text, a constant (data, not code of this program). Written for three.js r111
// (Debian 12's libjs-three) and later releases that still have the classic-script examples:
// BufferGeometry.setAttribute, THREE.VertexColors, GLTFLoader.parse.
// The page's state goes to <html data-viewer="...">: "loading", then "ready" once a frame with
// everything (the textured model included) has been drawn, or "no-webgl" / "model-error";
// errors go through varsfmError (the page head), which counts them in data-errors.
constexpr const char kViewerScript[] = R"JS(
(function () {
  'use strict';
  var root = document.documentElement;
  function setStatus(status) {
    root.setAttribute('data-viewer', status);
    document.title = document.title.replace(/ \[[^\]]*\]$/, '') + ' [' + status + ']';
  }
  var scene3 = JSON.parse(document.getElementById('varsfm-scene').textContent);
  var box = document.getElementById('viewer');
  var canvas = document.getElementById('viewer-canvas');
  var info = document.getElementById('camera-info');
  setStatus('loading');

  function decodeBase64(text) {
    var raw = atob(text);
    var bytes = new Uint8Array(raw.length);
    for (var i = 0; i < raw.length; ++i) bytes[i] = raw.charCodeAt(i);
    return bytes;
  }

  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true,
                                        preserveDrawingBuffer: true});
  } catch (e) {
    box.classList.add('unavailable');
    document.getElementById('viewer-message').textContent =
        'The 3D view needs WebGL, which this browser does not provide.';
    setStatus('no-webgl');
    return;
  }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  var scene = new THREE.Scene();
  scene.background = new THREE.Color(0x3a3f47);
  var r = scene3.radius;
  var camera = new THREE.PerspectiveCamera(scene3.fov, 1, r * 1e-3, r * 1e3);
  camera.up.fromArray(scene3.up);
  camera.position.fromArray(scene3.eye);
  var controls = new THREE.OrbitControls(camera, canvas);
  controls.target.fromArray(scene3.target);
  controls.update();

  function render() { renderer.render(scene, camera); }
  function resize() {
    var w = canvas.clientWidth, h = canvas.clientHeight;
    renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(1, h);
    camera.updateProjectionMatrix();
    render();
  }
  controls.addEventListener('change', render);
  window.addEventListener('resize', resize);

  var groups = {points: new THREE.Group(), cameras: new THREE.Group(), model: new THREE.Group()};
  Object.keys(groups).forEach(function (k) { scene.add(groups[k]); });

  if (scene3.points.count > 0) {
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(
        new Float32Array(decodeBase64(scene3.points.xyz).buffer), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(
        decodeBase64(scene3.points.rgb), 3, true));
    groups.points.add(new THREE.Points(geometry, new THREE.PointsMaterial(
        {size: 2, sizeAttenuation: false, vertexColors: THREE.VertexColors})));
  }

  // Each camera: its frustum in its focal-length colour and, on the frustum's base, its photo.
  var planes = [], byId = {};
  scene3.cameras.forEach(function (cam) {
    var c = new THREE.Vector3().fromArray(cam.center);
    var k = cam.corners.map(function (a) { return new THREE.Vector3().fromArray(a); });
    var segments = [];
    for (var i = 0; i < 4; ++i) segments.push(c, k[i], k[i], k[(i + 1) % 4]);
    var color = new THREE.Color(cam.color);
    var lines = new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(segments),
                                       new THREE.LineBasicMaterial({color: color}));
    var quad = new THREE.BufferGeometry();
    quad.setAttribute('position', new THREE.Float32BufferAttribute(
        [].concat(cam.corners[0], cam.corners[1], cam.corners[2], cam.corners[3]), 3));
    quad.setAttribute('uv', new THREE.Float32BufferAttribute([0, 1, 1, 1, 1, 0, 0, 0], 2));
    quad.setIndex([0, 1, 2, 0, 2, 3]);
    var material = new THREE.MeshBasicMaterial(
        {color: color, side: THREE.DoubleSide, transparent: true, opacity: 0.3});
    var photo = document.getElementById('thumb-' + cam.id);
    if (photo) {
      var texture = new THREE.Texture(photo);
      texture.minFilter = THREE.LinearFilter;  // no mipmaps: thumbnails are not powers of two
      texture.generateMipmaps = false;
      var show = function () { texture.needsUpdate = true; render(); };
      if (photo.complete && photo.naturalWidth > 0) texture.needsUpdate = true;
      else photo.addEventListener('load', show);
      material = new THREE.MeshBasicMaterial(
          {map: texture, side: THREE.DoubleSide, transparent: true, opacity: 0.85});
    }
    var plane = new THREE.Mesh(quad, material);
    plane.userData.id = cam.id;
    planes.push(plane);
    groups.cameras.add(lines, plane);
    byId[cam.id] = {cam: cam, lines: lines, plane: plane, color: color};
  });

  function figure(label, value) {
    return '<tr><th>' + label + '</th><td>' + value + '</td></tr>';
  }
  var selected = null;
  function select(id) {
    var entry = byId[id];
    if (selected) selected.lines.material.color.copy(selected.color);
    document.querySelectorAll('.selected').forEach(function (e) { e.classList.remove('selected'); });
    if (!entry) { selected = null; info.hidden = true; render(); return; }
    selected = entry;
    entry.lines.material.color.set(0xffffff);
    document.querySelectorAll('[data-image="' + id + '"]').forEach(function (e) {
      e.classList.add('selected');
    });
    var cam = entry.cam, photo = document.getElementById('thumb-' + id);
    var name = document.createElement('b');
    name.textContent = cam.name;
    info.innerHTML = (photo ? '<img alt="" src="' + photo.src + '">' : '') + '<table>' +
        figure('focal', cam.focal.toFixed(1) + ' px (\u00d7' + cam.ratio.toFixed(3) + ')') +
        figure('k1, k2', cam.k1.toFixed(4) + ', ' + cam.k2.toFixed(4)) +
        figure('principal point', cam.pp[0].toFixed(1) + ', ' + cam.pp[1].toFixed(1)) +
        figure('size', cam.size[0] + ' \u00d7 ' + cam.size[1]) +
        figure('3D points', cam.points) + figure('RMS error', cam.rms.toFixed(3) + ' px') +
        '</table>';
    info.insertBefore(name, info.firstChild);
    info.hidden = false;
    render();
  }
  document.querySelectorAll('[data-image]').forEach(function (e) {
    e.addEventListener('click', function () { select(Number(e.getAttribute('data-image'))); });
  });

  // A click (not a drag) on a photo plane selects its camera.
  var raycaster = new THREE.Raycaster(), down = null;
  canvas.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
  canvas.addEventListener('pointerup', function (e) {
    if (!down || Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) > 4) return;
    var rect = canvas.getBoundingClientRect();
    raycaster.setFromCamera(new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1,
                                              -(e.clientY - rect.top) / rect.height * 2 + 1),
                            camera);
    var hits = groups.cameras.visible ? raycaster.intersectObjects(planes) : [];
    select(hits.length ? hits[0].object.userData.id : null);
  });

  // report.html#camera=ID opens with that camera selected (a link to one image).
  var linked = /camera=(\d+)/.exec(window.location.hash);
  if (linked) select(Number(linked[1]));

  document.querySelectorAll('#viewer-toggles input').forEach(function (input) {
    input.addEventListener('change', function () {
      groups[input.name].visible = input.checked;
      render();
    });
  });

  // The canvas's place on the page (CSS pixels), for a test that looks at a screenshot.
  function finish(status) {
    resize();
    requestAnimationFrame(function () {
      render();
      var rect = canvas.getBoundingClientRect();
      root.setAttribute('data-canvas', [rect.left + window.scrollX, rect.top + window.scrollY,
                                        rect.width, rect.height].map(Math.round).join(' '));
      setStatus(status);
    });
  }
  var glb = document.getElementById('varsfm-glb');
  if (!glb) { finish('ready'); return; }
  function failed(error) {
    varsfmError('the textured model could not be read: ' + (error && error.message || error));
    finish('model-error');
  }
  var bytes = decodeBase64(glb.textContent.trim());
  var unpacked;
  if (glb.getAttribute('data-encoding') !== 'deflate') {
    unpacked = Promise.resolve(bytes.buffer);
  } else if (typeof DecompressionStream === 'undefined') {
    unpacked = Promise.reject(new Error('this browser has no DecompressionStream'));
  } else {
    unpacked = new Response(new Blob([bytes]).stream().pipeThrough(
        new DecompressionStream('deflate'))).arrayBuffer();
  }
  unpacked.then(function (buffer) {
    new THREE.GLTFLoader().parse(buffer, '', function (gltf) {
      gltf.scene.traverse(function (o) {
        if (!o.isMesh) return;
        o.material.side = THREE.DoubleSide;  // reconstructed meshes are not consistently oriented
        // The atlas holds the photos' pixel values and the page shows them as they are (the
        // thumbnails and point colours too): no sRGB decoding, which would darken them.
        if (o.material.map) o.material.map.encoding = THREE.LinearEncoding;
        o.material.needsUpdate = true;
      });
      groups.model.add(gltf.scene);
      finish('ready');
    }, failed);
  }, failed);
  resize();
})();
)JS";

}  // namespace

const char* ViewerScript() { return kViewerScript; }

}  // namespace varsfm
