#!/usr/bin/env bash
# Fuzzes every reader of outside data: builds the libFuzzer harnesses of fuzz/ (clang, ASan +
# UBSan, VARSFM_FUZZ=ON) in build-fuzz, runs each for SECONDS (default 600) on its seed corpus
# (fuzz/corpus/<name>, read only; new inputs go to build-fuzz/corpus/<name>), and reports
# executions and findings: a crash, leak, timeout (> 25 s) or out-of-memory (> 2 GB) input is
# saved under build-fuzz/findings/<name>/, with the log in build-fuzz/logs/<name>.log. Exits 1
# when anything was found. Fix the reader, and add the input as a unit test in tests/<module>.
#   scripts/fuzz.sh [SECONDS] [HARNESS...]     e.g. scripts/fuzz.sh 60 ply colmap_binary
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
shift || true
harnesses=("$@")
if [ "${#harnesses[@]}" -eq 0 ]; then
  for f in fuzz/*_fuzzer.cc; do
    f="${f##*/}"
    harnesses+=("${f%_fuzzer.cc}")
  done
fi

launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DVARSFM_FUZZ=ON -DVARSFM_BUILD_TESTS=OFF \
  -DVARSFM_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
cmake --build build-fuzz -j "${FUZZ_BUILD_JOBS:-2}" --target "${harnesses[@]/%/_fuzzer}"

export UBSAN_OPTIONS="print_stacktrace=1:${UBSAN_OPTIONS:-}"
mkdir -p build-fuzz/logs
found=0
printf '%-16s %12s %8s %6s  %s\n' harness executions exec/s time finding
for name in "${harnesses[@]}"; do
  corpus="build-fuzz/corpus/$name" findings="build-fuzz/findings/$name" log="build-fuzz/logs/$name.log"
  mkdir -p "$corpus" "$findings"
  status=0
  "build-fuzz/fuzz/${name}_fuzzer" -max_total_time="$seconds" -timeout=25 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$findings/" "$corpus" "fuzz/corpus/$name" \
    >"$log" 2>&1 || status=$?
  runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
  rate="$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)"
  elapsed="$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)"
  finding="-"
  if [ "$status" -ne 0 ]; then
    found=1
    finding="$(grep -m1 -oE '(ERROR|WARNING): [A-Za-z]+: [^(]*|runtime error: .*|Test unit written to .*' "$log" || true)"
    finding="${finding:-exit $status}; $(ls "$findings" | head -1)"
  fi
  printf '%-16s %12s %8s %6s  %s\n' "$name" "${runs:-?}" "${rate:-?}" "${elapsed:-$seconds}" "$finding"
done
exit "$found"
