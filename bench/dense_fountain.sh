#!/usr/bin/env bash
# Times the dense half of the chain (densify, then mesh) on a sparse model and prints the figures
# issue 6 asks for: seconds per densify phase, points, how close they lie to the sparse model,
# mesh seconds and manifoldness.
#   bench/dense_fountain.sh [SPARSE_DIR] [IMAGE_DIR] [VARSFM_BINARY] [WORK_DIR]
# SPARSE_DIR (a model folder, or a folder of models 0/, 1/, ...: model 0) defaults to
# WORK_DIR/sparse/0, made by `varsfm run IMAGE_DIR WORK_DIR --until sparse`
# when missing (IMAGE_DIR: ../shared/data/strecha/fountain-P11/images; binary: build/varsfm;
# WORK_DIR: a temporary folder, removed at the end unless given).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
images="${2:-$root/../shared/data/strecha/fountain-P11/images}"
varsfm="${3:-$root/build/varsfm}"
[[ -d "$images" ]] || { echo "no image folder $images" >&2; exit 1; }
[[ -x "$varsfm" ]] || { echo "no varsfm binary $varsfm (build it first)" >&2; exit 1; }
if [[ -n "${4:-}" ]]; then
  work="$4"
  mkdir -p "$work"
else
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
fi
sparse="${1:-$work/sparse/0}"
if [[ ! -d "$sparse" ]]; then
  echo "no sparse model: running varsfm run (sparse only) into $work/run"
  "$varsfm" run "$images" "$work/run" --until sparse >"$work/run.log" 2>&1 ||
    { cat "$work/run.log" >&2; exit 1; }
  sparse="$work/run/sparse/0"
fi

echo "sparse: $sparse, images: $images, cores: $(nproc), load: $(cut -d' ' -f1-3 /proc/loadavg)"
# GNU time's wall and CPU seconds: CPU is steadier when the machine is shared.
/usr/bin/time -f "densify: %e s wall, %U s user, %M KB" \
  "$varsfm" densify --sparse "$sparse" --images "$images" --output "$work/dense" \
  >"$work/densify.log" 2>&1 || { cat "$work/densify.log" >&2; exit 1; }
grep -E "^densify:|fused points|median distance" "$work/densify.log" | sed 's/^\[[^]]*\] //'
/usr/bin/time -f "mesh: %e s wall, %U s user, %M KB" \
  "$varsfm" mesh --input "$work/dense/dense.ply" --output "$work/mesh" --sparse "$sparse" \
  --images "$images" >"$work/mesh.log" 2>&1 || { cat "$work/mesh.log" >&2; exit 1; }
grep -E "^mesh:|surface:|info mesh" "$work/mesh.log" | sed 's/^\[[^]]*\] //'
python3 - "$work/dense/dense_summary.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
c = s["sparse_check"]
print(f"dense: {s['points']} points from {s['pairs']} pairs ({s['matches']} matches); phases (s): "
      + ", ".join(f"{k} {v:.1f}" for k, v in s["seconds"].items()))
print(f"dense vs sparse (units of the median scene depth {c['scene_depth']:.3g}): median distance "
      f"to nearest sparse point {c['median_distance_to_nearest_sparse_point']:.4f}, to the local "
      f"sparse plane {c['median_distance_to_local_sparse_plane']:.4f}; "
      f"{100 * c['fraction_within_1_percent_of_depth']:.1f} % within 1 %")
PY
echo "load at end: $(cut -d' ' -f1-3 /proc/loadavg)"
