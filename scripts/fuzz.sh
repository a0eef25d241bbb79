#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang, in build-fuzz: Prismoid's own parsers only, no VTK)
# and runs each for SECONDS (default 30) from its seed corpus. Inputs that grow coverage go to
# build-fuzz/corpus/<target>, so later runs start where earlier ones stopped. A crash, leak,
# undefined behaviour or violated property stops with a non-zero exit and leaves the input as
# build-fuzz/findings/<target>/crash-* (reproduce: build-fuzz/fuzz/fuzz_<target> FILE).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-30}"
build=build-fuzz
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DPRISMOID_FUZZ=ON \
  "${launcher[@]}" >/dev/null
cmake --build "$build" -j "$(nproc)" --target fuzz_targets

status=0
for exe in "$build"/fuzz/fuzz_*; do
  [ -x "$exe" ] || continue
  target="${exe##*/fuzz_}"
  corpus="$build/corpus/$target" findings="$build/findings/$target"
  mkdir -p "$corpus" "$findings"
  # -rss_limit_mb: the size guards keep honest inputs far below it; more is a finding.
  if "$exe" "$corpus" "$build/fuzz/seeds/$target" -max_total_time="$seconds" -rss_limit_mb=1024 -timeout=10 \
      -max_len=4096 -artifact_prefix="$findings/" -print_final_stats=1 >"$build/fuzz-$target.log" 2>&1; then
    echo "[fuzz] $target: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$build/fuzz-$target.log" | grep -o '[0-9]*$') runs in ${seconds} s, no finding"
  else
    status=1
    echo "[fuzz] $target: FOUND A PROBLEM (input in $findings/); the log's end:"
    tail -n 40 "$build/fuzz-$target.log"
  fi
done
exit $status
