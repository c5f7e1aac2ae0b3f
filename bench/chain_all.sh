#!/usr/bin/env bash
# The whole chain, `varsfm run` with default settings, on the seven shared sets, checked against
# issue 17's acceptance: no crash (exit 0), a mesh of at least 2,000 faces whose median
# vertex-to-dense-point distance is below 0.5 % of the dense cloud's extent, and a texture that
# covers the photos (the mean fraction of each registered photo's pixels the textured model
# covers, rendered by `varsfm evaluate --render`, at least MIN_COVERAGE, default 0.10).
#   bench/chain_all.sh VARSFM_BINARY WORK_DIR [TAG]
# Prints a table (dense points, faces, median distance / extent, coverage, seconds per stage,
# peak memory of the run from GNU time) and writes bench/results/<date>-chain-all[-TAG].md and
# .json. Reads OUT/sparse/0 or OUT/sparse, whichever the binary writes. Exits 1 when a set fails.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
[[ $# -ge 2 ]] || { echo "usage: $0 VARSFM_BINARY WORK_DIR [TAG]" >&2; exit 2; }
varsfm="$(realpath "$1")"
work="$2"
tag="${3:+-$3}"
data="$root/../shared/data"
[[ -x "$varsfm" ]] || { echo "no varsfm binary $varsfm" >&2; exit 2; }
[[ -d "$data" ]] || { echo "no shared data at $data" >&2; exit 2; }
mkdir -p "$work"
sets=(strecha/fountain-P11/images strecha/fountain-P11-zoom/images strecha/Herz-Jesus-P8/images
      strecha/entry-P10/images bundler/kermit bundler/ET sceaux/images)
gnu_time=()
[[ -x /usr/bin/time ]] && gnu_time=(/usr/bin/time -v)
load_start="$(cut -d' ' -f1-3 /proc/loadavg)"
for set in "${sets[@]}"; do
  name="$(echo "$set" | sed 's|/images$||; s|/|-|g')"
  out="$work/$name"
  rm -rf "$out"
  mkdir -p "$out"
  echo "== $name" >&2
  set +e
  "${gnu_time[@]}" "$varsfm" run "$data/$set" "$out/run" >"$out/run.log" 2>&1
  echo $? >"$out/run.rc"
  set -e
  sparse="$out/run/sparse/0"
  [[ -d "$sparse" ]] || sparse="$out/run/sparse"
  if [[ -f "$out/run/textured/model.obj" ]]; then
    "$varsfm" evaluate "$sparse" --render --images "$data/$set" --textured "$out/run/textured" \
      --json "$out/render.json" >"$out/render.log" 2>&1 || true
  fi
done
python3 - "$work" "$root/bench/results" "$tag" "$varsfm" "$load_start" "${MIN_COVERAGE:-0.10}" \
  "${sets[@]}" <<'PY'
import datetime, json, os, re, sys
work, results, tag, binary, load_start, min_coverage = sys.argv[1:7]
min_coverage = float(min_coverage)
sets = sys.argv[7:]
rows, failed = [], 0
for s in sets:
    name = re.sub(r"/images$", "", s).replace("/", "-")
    out = os.path.join(work, name)
    row = {"set": name, "exit": int(open(os.path.join(out, "run.rc")).read())}
    log = open(os.path.join(out, "run.log"), errors="replace").read()
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", log)
    row["peak_mib"] = int(m.group(1)) / 1024 if m else None
    m = re.search(r"varsfm: (?:unexpected )?error: (.*)", log)
    row["error"] = m.group(1) if m else None
    try:
        summary = json.load(open(os.path.join(out, "run", "summary.json")))
    except (OSError, ValueError):
        summary = {}
    row["seconds"] = summary.get("seconds", {})
    mesh = summary.get("mesh", {})
    row.update({k: mesh.get(k) for k in ("points", "faces", "relative_distance", "depth")})
    row["texture_coverage"] = summary.get("texture", {}).get("mean_coverage")
    try:
        render = json.load(open(os.path.join(out, "render.json")))
        row["render_coverage"] = render.get("render", render).get("mean_coverage")
    except (OSError, ValueError):
        row["render_coverage"] = None
    checks = [row["exit"] == 0, (row["faces"] or 0) >= 2000,
              row["relative_distance"] is not None and row["relative_distance"] < 0.005,
              (row["render_coverage"] or 0) >= min_coverage]
    row["pass"] = all(checks)
    failed += not row["pass"]
    rows.append(row)

def f(v, fmt):
    return "-" if v is None else fmt.format(v)

stages = ["extract", "match", "map", "densify", "mesh", "texture"]
head = ("| set | exit | dense points | faces | median dist / extent | coverage (render) | "
        + " | ".join(f"{s} s" for s in stages) + " | peak MiB | pass |")
lines = [head, "|" + "---|" * (head.count("|") - 1)]
for r in rows:
    lines.append("| " + " | ".join(
        [r["set"], str(r["exit"]), f(r["points"], "{:,}"), f(r["faces"], "{:,}"),
         f(r["relative_distance"] and 100 * r["relative_distance"], "{:.3f} %"),
         f(r["render_coverage"] and 100 * r["render_coverage"], "{:.1f} %")]
        + [f(r["seconds"].get(s), "{:.1f}") for s in stages]
        + [f(r["peak_mib"], "{:.0f}"), "yes" if r["pass"] else "NO"]) + " |")
    if r["error"]:
        lines.append(f"| | {r['error']} |")
table = "\n".join(lines)
print(table)
now = datetime.datetime.now(datetime.timezone.utc)
load_end = open("/proc/loadavg").read().split()[:3]
md = (f"# The whole chain on the seven shared sets ({now:%Y-%m-%d %H:%M:%S} UTC)\n\n"
      f"`bench/chain_all.sh {binary} WORK`: `varsfm run IMAGES OUT` with default settings per "
      f"set, then `varsfm evaluate OUT/sparse/0 --render` for the coverage (mean over the "
      f"registered photos of the fraction of pixels the textured model covers). Pass: exit 0, "
      f">= 2,000 faces, median mesh-vertex-to-dense-point distance < 0.5 % of the dense cloud's "
      f"extent (5-95 % percentile box diagonal), coverage >= {100 * min_coverage:.0f} %. "
      f"Seconds from summary.json; peak memory of the whole run from GNU time.\n"
      f"Machine: {os.cpu_count()} cores, load average at start {load_start}, at end "
      f"{' '.join(load_end)}.\n\n{table}\n\n{len(rows) - failed} of {len(rows)} sets pass.\n")
os.makedirs(results, exist_ok=True)
base = os.path.join(results, f"{now:%Y-%m-%d}-chain-all{tag}")
open(base + ".md", "w").write(md)
json.dump({"date": now.isoformat(), "binary": binary, "load_start": load_start,
           "load_end": load_end, "min_coverage": min_coverage, "sets": rows},
          open(base + ".json", "w"), indent=2)
print(f"wrote {base}.md and .json; {len(rows) - failed} of {len(rows)} sets pass")
sys.exit(1 if failed else 0)
PY
