#!/usr/bin/env bash
# Installs every Debian package varsfm needs. Idempotent: does nothing when all are present.
# Usage: scripts/install_deps.sh [--with-colmap]
set -euo pipefail
pkgs=(build-essential cmake pkg-config libeigen3-dev libceres-dev libsuitesparse-dev libopencv-dev
      libsqlite3-dev libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev libtbb-dev
      libgtest-dev libgmock-dev libbenchmark-dev ffmpeg libexif-dev libcgal-dev
      libtinygltf-dev libboost-dev libopenblas0-serial libturbojpeg0-dev libpng-dev libheif-dev libraw-dev
      libgoogle-perftools-dev libavutil-dev
      libopen3d-dev libjs-three)
# libjs-three: three.js r111 with its OrbitControls and GLTFLoader, which `varsfm report` inlines
# into OUT/report.html for the 3D view (varsfm ships no copy; without it the report has no 3D
# view). chromium (tests only): the report's browser test opens it headless.
# libopenblas0-serial becomes the system BLAS/LAPACK (Debian's alternatives): SuiteSparse's
# supernodal Cholesky, the sparse bundle adjustment above 250 images, runs on it (a 200-image
# final global BA: 7.6 s with the reference BLAS/ATLAS, 5.4 s); serial, so still reproducible.
with_tests=0
if [[ "${1:-}" == "--with-colmap" ]]; then pkgs+=(colmap chromium); with_tests=1; fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[varsfm] installing: ${missing[*]}"
  SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
# The tests' Node tools (scripts/node/package.json: the Khronos glTF-Validator), from npm.
if ((with_tests)); then
  if ! command -v npm >/dev/null 2>&1; then
    SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
  fi
  root="$(cd "$(dirname "$0")/.." && pwd)"
  if [[ ! -d "$root/scripts/node/node_modules/gltf-validator" ]]; then
    npm ci --prefix "$root/scripts/node" --no-audit --no-fund --silent
  fi
fi
