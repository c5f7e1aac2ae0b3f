#!/usr/bin/env bash
# Times varsfm's feature extraction + exhaustive matching against COLMAP's (CPU only) on the same
# images in the same run, and compares the verified inlier matches of adjacent image pairs.
#   bench/features_vs_colmap.sh [IMAGE_DIR] [VARSFM_BINARY]
# Defaults: ../shared/data/strecha/fountain-P11/images and build/varsfm. Work files go to a
# temporary folder that is removed at the end. COLMAP is skipped when it is not installed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
images="${1:-$root/../shared/data/strecha/fountain-P11/images}"
varsfm="${2:-$root/build/varsfm}"
[[ -d "$images" ]] || { echo "no image folder $images" >&2; exit 1; }
[[ -x "$varsfm" ]] || { echo "no varsfm binary $varsfm (build it first)" >&2; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Seconds taken by a command (its output goes to a log in $work).
timed() {
  local log="$1"; shift
  local start end
  start=$(date +%s.%N)
  "$@" >"$work/$log" 2>&1 || { cat "$work/$log" >&2; exit 1; }
  end=$(date +%s.%N)
  python3 -c "print(f'{$end - $start:.2f}')"
}

# Inlier counts of the two-view geometries of consecutive images (by name) in a database.
adjacent_inliers() {
  python3 - "$1" <<'PY'
import sqlite3, sys
db = sqlite3.connect(sys.argv[1])
images = sorted(db.execute("SELECT name, image_id FROM images"))
counts = []
for (n1, a), (n2, b) in zip(images, images[1:]):
    i, j = min(a, b), max(a, b)
    row = db.execute("SELECT rows FROM two_view_geometries WHERE pair_id = ?",
                     (i * 2147483647 + j,)).fetchone()
    counts.append(row[0] if row else 0)
verified = db.execute("SELECT COUNT(*) FROM two_view_geometries WHERE rows > 0").fetchone()[0]
features = db.execute("SELECT SUM(rows) FROM keypoints").fetchone()[0]
print(f"features {features}, verified pairs {verified}, adjacent-pair inliers "
      f"{' '.join(map(str, counts))} (sum {sum(counts)})")
PY
}

echo "images: $images ($(ls "$images" | wc -l) files), cores: $(nproc)"
v_ext=$(timed varsfm_extract.log "$varsfm" extract --workspace "$work/varsfm.db" --images "$images")
v_match=$(timed varsfm_match.log "$varsfm" match --workspace "$work/varsfm.db" --strategy exhaustive)
echo "varsfm: extract ${v_ext} s, exhaustive match ${v_match} s"
echo "varsfm: $(adjacent_inliers "$work/varsfm.db")"

if ! command -v colmap >/dev/null; then
  echo "colmap is not installed: no comparison"
  exit 0
fi
c_ext=$(timed colmap_extract.log colmap feature_extractor --database_path "$work/colmap.db" \
  --image_path "$images" --SiftExtraction.use_gpu 0)
c_match=$(timed colmap_match.log colmap exhaustive_matcher --database_path "$work/colmap.db" \
  --SiftMatching.use_gpu 0)
echo "colmap: extract ${c_ext} s, exhaustive match ${c_match} s"
echo "colmap: $(adjacent_inliers "$work/colmap.db")"
python3 - "$v_ext" "$v_match" "$c_ext" "$c_match" <<'PY'
import sys
ve, vm, ce, cm = map(float, sys.argv[1:])
print(f"varsfm / colmap time: extract {ve / ce:.2f}, match {vm / cm:.2f}, "
      f"total {(ve + vm) / (ce + cm):.2f} (goal <= 0.5)")
PY
