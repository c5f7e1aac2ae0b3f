#!/usr/bin/env bash
# Whether two varsfm binaries make the same sparse models, bit for bit, on every shared set: the
# check of a change that must not alter results (a renovation). Each binary runs
# `varsfm run SET OUT --until sparse` (extract, match, map) on the seven sets of ../shared/data,
# then every OUT/sparse/*/*.bin of the one is compared with the other's by `cmp`.
#   scripts/check_sparse_identical.sh BASELINE_BINARY NEW_BINARY [WORK_DIR]
# Environment: RUN_ARGS, more options for every `run` (e.g. "--intrinsics focal-per-image", to
# check a non-default path); SETS, a subset of the sets (e.g. "bundler/kermit bundler/ET").
# A binary's runs are kept under WORK_DIR/<hash of the binary and RUN_ARGS>/ (default /tmp/varsfm-sparse-identical)
# and reused while it is unchanged, so checking commit after commit against one baseline runs
# the baseline once. Prints one line per set (the number of .bin files compared, registered
# images and points of model 0) and exits 1 when any file differs or is missing, or a run fails.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
[[ $# -ge 2 ]] || { echo "usage: $0 BASELINE_BINARY NEW_BINARY [WORK_DIR]" >&2; exit 2; }
data="$root/../shared/data"
work="${3:-/tmp/varsfm-sparse-identical}"
[[ -d "$data" ]] || { echo "no shared data at $data" >&2; exit 2; }
sets=(strecha/fountain-P11/images strecha/fountain-P11-zoom/images strecha/Herz-Jesus-P8/images
      strecha/entry-P10/images bundler/kermit bundler/ET sceaux/images)
[[ -n "${SETS:-}" ]] && read -r -a sets <<<"$SETS"
read -r -a run_args <<<"${RUN_ARGS:-}"

# Runs binary $1 on every set under WORK_DIR/<sha256>; prints that folder.
run_all() {
  local binary sha dir set name
  binary="$(realpath "$1")"
  [[ -x "$binary" ]] || { echo "no varsfm binary $binary" >&2; exit 2; }
  sha="$( (sha256sum "$binary" | cut -c1-16; echo "${RUN_ARGS:-}") | sha256sum | cut -c1-16)"
  dir="$work/$sha"
  mkdir -p "$dir"
  for set in "${sets[@]}"; do
    name="$(echo "$set" | sed 's|/images$||; s|/|-|g')"
    [[ -f "$dir/$name.done" ]] && continue
    rm -rf "${dir:?}/$name"
    echo "== $name with $binary" >&2
    if ! "$binary" run "$data/$set" "$dir/$name" --until sparse "${run_args[@]}" >"$dir/$name.log" 2>&1; then
      echo "$name: run failed with $binary (log $dir/$name.log)" >&2
      exit 1
    fi
    touch "$dir/$name.done"
  done
  echo "$dir"
}

baseline="$(run_all "$1")"
new="$(run_all "$2")"
status=0
for set in "${sets[@]}"; do
  name="$(echo "$set" | sed 's|/images$||; s|/|-|g')"
  compared=0
  differ=()
  # The union of both runs' model files, so that a model only one of them made counts as a
  # difference.
  while IFS= read -r rel; do
    if cmp -s "$baseline/$name/$rel" "$new/$name/$rel"; then
      compared=$((compared + 1))
    else
      differ+=("$rel")
    fi
  done < <(cd "$baseline/$name" && find sparse -name '*.bin'; cd "$new/$name" && find sparse -name '*.bin')
  models="$(cd "$new/$name/sparse" && ls -d [0-9]* | wc -l)"
  figures="$(python3 -c 'import json, sys
s = json.load(open(sys.argv[1]))
registered, total, points = s["images_registered"], s["images_total"], s["points3D"]
print(f"{registered}/{total} registered, {points} points")' \
    "$new/$name/summary.json" 2>/dev/null || echo "?")"
  if [[ ${#differ[@]} -eq 0 ]]; then
    echo "$name: identical ($((compared / 2)) .bin files in $models model(s); $figures)"
  else
    echo "$name: DIFFERENT: ${differ[*]}"
    status=1
  fi
done
exit $status
