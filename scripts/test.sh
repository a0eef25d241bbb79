#!/usr/bin/env bash
# Sets everything up and runs the whole test suite (.ci/run calls exactly this).
# GPU tests run on Mesa's lavapipe with the Khronos validation layer on; the window tests
# run under Xvfb.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="/tmp/prismoid-runtime-$(id -u)"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
fi
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
# The bench's quick preset, as a step of its own: `prismoid bench` runs end to end on every
# configuration it knows, with validation on (its times are reported, never asserted).
bench_start=$(date +%s)
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" build/app/prismoid bench --quick --validate --out build/bench-quick > build/bench-quick.log
echo "bench --quick: $(( $(date +%s) - bench_start )) s, build/bench-quick/report.md"
# libFuzzer on Prismoid's own parsers (fuzz/), briefly: 20 s per target, about 2 minutes in all.
./scripts/fuzz.sh 20
