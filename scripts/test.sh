#!/usr/bin/env bash
# Sets everything up and runs the whole test suite (.ci/run calls exactly this). Arguments go to
# ctest: `./scripts/test.sh -R IsolatedRead` runs those tests only (the bench and fuzz steps then
# are skipped: they belong to the whole gate). Each phase prints the time it took.
# GPU tests run on Mesa's lavapipe with the Khronos validation layer on; the window tests
# run under Xvfb.
set -euo pipefail
cd "$(dirname "$0")/.."
phase_start=$(date +%s)
phase() {  # phase NAME: the time since the previous phase ended
  local now
  now=$(date +%s)
  echo "[test.sh] $1: $(( now - phase_start )) s"
  phase_start=$now
}
./scripts/setup.sh
phase "set-up"
./scripts/build.sh
phase "build"
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="/tmp/prismoid-runtime-$(id -u)"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
fi
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --test-dir build --output-on-failure -j "$(nproc)" "$@"
phase "ctest"
if [ $# -gt 0 ]; then exit 0; fi
# The bench's quick preset, as a step of its own: `prismoid bench` runs end to end on every
# configuration it knows, with validation on (its times are reported, never asserted).
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" build/app/prismoid bench --quick --validate --replace --out build/bench-quick > build/bench-quick.log
phase "bench --quick (build/bench-quick/report.md)"
# libFuzzer on Prismoid's own parsers (fuzz/), briefly: 20 s per target, about 2 minutes in all.
./scripts/fuzz.sh 20
phase "fuzz"
