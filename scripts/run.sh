#!/usr/bin/env bash
# Sets everything up and runs Prismoid on the embedded default dataset: the window when a
# display is available, otherwise a headless render to out/default.png with per-pass GPU
# times and its error against the CPU reference. Arguments, when given, go to the prismoid executable instead.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
# The build's progress goes to stderr (a first build takes minutes); stdout stays the program's.
./scripts/build.sh >&2
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="/tmp/prismoid-runtime-$(id -u)"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
fi
if [ $# -gt 0 ]; then exec build/app/prismoid "$@"; fi
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec build/app/prismoid view
fi
mkdir -p out
# The first image: the default dataset's colour in exact order, with what it cost (GPU time of each
# pass, best and median of 3 frames) and how far it is from the CPU double-precision reference.
exec build/app/prismoid render --frames 3 --reference-error --output out/default.png --stats out/default.json
