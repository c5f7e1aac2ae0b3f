#!/usr/bin/env bash
# Feature extraction of 12 MP phone photos (issue 21): renders NUM views of the project's scene
# at 4032x3024 as JPEGs of quality 95 (bench/render_sequence, with exact ground truth), then
# times `varsfm extract --threads THREADS` on them (two photos in flight on two threads) under
# GNU time, and with --sparse also matches, maps and scores the model against the ground truth.
#   bench/sift_speed.sh [VARSFM_BINARY] [WORK_DIR] [NUM] [THREADS] [--sparse]
# Defaults: build/varsfm, /tmp/varsfm-sift-speed, 8 photos, 2 threads. The rendered photos are
# kept in WORK_DIR/photos and reused. Prints wall and CPU seconds per photo and the features.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
binary="$(realpath "${1:-$root/build/varsfm}")"
work="${2:-/tmp/varsfm-sift-speed}"
num="${3:-8}"
threads="${4:-2}"
sparse="${5:-}"
render="$root/build/bench/render_sequence"
[[ -x "$binary" && -x "$render" ]] || { echo "build varsfm and bench/render_sequence first" >&2; exit 2; }

photos="$work/photos"
if [[ ! -f "$photos/done" ]]; then
  rm -rf "$photos"
  "$render" "$photos" "$num" --width 4032 --height 3024 --jpeg 95 --supersampling 1 --arc 30
  touch "$photos/done"
fi

tag="$(sha256sum "$binary" | cut -c1-12)"
out="$work/$tag"
rm -rf "$out"
mkdir -p "$out/run"
/usr/bin/time -f "%e %U %S" -o "$out/time.txt" \
  "$binary" extract --images "$photos/images" --workspace "$out/run/workspace.db" --threads "$threads" \
  >"$out/extract.log" 2>&1
read -r wall user sys <"$out/time.txt"
features="$(grep -o 'extracted .*features' "$out/extract.log" | tail -1)"
awk -v w="$wall" -v u="$user" -v s="$sys" -v n="$num" -v t="$threads" -v f="$features" 'BEGIN {
  printf "extract: %d photos on %d threads: wall %.1f s (%.2f s a photo), CPU %.1f s (%.2f s a photo); %s\n",
         n, t, w, w / n, u + s, (u + s) / n, f }'

if [[ "$sparse" == "--sparse" ]]; then
  # run finds the features extracted above (same settings) and matches and maps.
  "$binary" run "$photos/images" "$out/run" --until sparse >"$out/run.log" 2>&1
  "$binary" evaluate "$out/run/sparse" --gt "$photos/gt" | tee "$out/evaluate.txt"
fi
