#!/usr/bin/env bash
# Sets everything up and runs Prismoid on the embedded default dataset: the window when a
# display is available, otherwise a headless render to out/default.png with per-pass GPU
# times. Arguments, when given, go to the prismoid executable instead.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/setup.sh
./scripts/build.sh >/dev/null
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="/tmp/prismoid-runtime-$(id -u)"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
fi
if [ $# -gt 0 ]; then exec build/app/prismoid "$@"; fi
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  exec build/app/prismoid view
fi
mkdir -p out
exec build/app/prismoid render --output out/default.png --stats out/default.json
