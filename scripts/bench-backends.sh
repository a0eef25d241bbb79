#!/usr/bin/env bash
# Times the two interval backends (mesh shaders, compute) side by side on the paper's datasets
# and views, each run `prismoid render --frames N` with its --stats JSON kept, the SM clock
# sampled by nvidia-smi during the runs where it exists. scripts/backends-table.py turns the
# folder into the markdown tables of docs/results.md. Needs bash only (runs from the GPU
# bundle, docs/gpu.md).
#
#   scripts/bench-backends.sh [--data DIR] [--size WxH] [--frames N] [--out DIR] [--prismoid CMD] [--sets LIST]
#     --data DIR      bunny.vtk and armadillo.vtk, or .vtk.xz (unpacked first); default datasets/real
#     --size WxH      image size (default 3840x2160)
#     --frames N      timed frames per run, after the warm-up (default 20)
#     --sets LIST     which runs: paper (bunny and armadillo, optical depth and exact-order colour,
#                     the default, close and inside views), rate (8x8 images: the geometry-bound
#                     rate), cells (10^7 cells of an analytic field); default "paper rate cells"
#     --backends LIST default "mesh compute"
set -euo pipefail
cd "$(dirname "$0")/.."
data=datasets/real size=3840x2160 frames=20 out=out/bench-backends sets="paper rate cells" backends="mesh compute"
prismoid="${PRISMOID:-}"
while [ $# -gt 0 ]; do
  case "$1" in
    --data) data="$2"; shift 2 ;;
    --size) size="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --prismoid) prismoid="$2"; shift 2 ;;
    --sets) sets="$2"; shift 2 ;;
    --backends) backends="$2"; shift 2 ;;
    *) echo "bench-backends: unknown option $1" >&2; exit 2 ;;
  esac
done
if [ -z "$prismoid" ]; then
  if [ -x build/app/prismoid ]; then prismoid=build/app/prismoid; else prismoid=bundle/prismoid.sh; fi
fi
mkdir -p "$out"
unpacked="$(mktemp -d)"
trap 'rm -rf "$unpacked"; [ -n "${smi:-}" ] && kill "$smi" 2>/dev/null || true' EXIT
file_of() {  # the dataset's .vtk, unpacked from .xz when that is what there is
  if [ -f "$data/$1.vtk" ]; then echo "$data/$1.vtk"
  elif [ -f "$data/$1.vtk.xz" ]; then xz -dc "$data/$1.vtk.xz" >"$unpacked/$1.vtk" && echo "$unpacked/$1.vtk"
  else echo ""; fi
}
if command -v nvidia-smi >/dev/null; then
  nvidia-smi --query-gpu=timestamp,clocks.sm,utilization.gpu --format=csv,noheader,nounits -lms 100 >"$out/clock.csv" &
  smi=$!
fi
run() {  # NAME, then render options
  local name="$1"; shift
  local start end
  start=$(date +%s.%N)
  if "$prismoid" render "$@" --frames "$frames" --output "$out/$name.png" --stats "$out/$name.json" >"$out/$name.log" 2>&1; then
    end=$(date +%s.%N)
    echo "$name $start $end" >>"$out/runs.txt"
    echo "ok   $name"
  else
    echo "FAIL $name (see $out/$name.log)"
  fi
}
for set in $sets; do
  case "$set" in
    paper)
      for d in bunny armadillo; do
        f="$(file_of "$d")"
        [ -n "$f" ] || { echo "skip $d: not in $data"; continue; }
        for b in $backends; do
          run "$d-od-$b" "$f" --size "$size" --quantity optical-depth --mode interval --volume-backend "$b"
          run "$d-color-$b" "$f" --size "$size" --quantity color --mode interval-exact-order --array height --volume-backend "$b"
          if [ "$d" = armadillo ]; then  # the paper's close and inside views
            run "$d-close-$b" "$f" --size "$size" --quantity optical-depth --mode interval --volume-backend "$b" --eye 0,21.5,90 --target 0,21.5,0 --near 0.5
            run "$d-inside-$b" "$f" --size "$size" --quantity optical-depth --mode interval --volume-backend "$b" --eye 0,21.5,0 --target 0,21.5,-100 --near 0.5
          fi
        done
      done ;;
    rate)
      f="$(file_of armadillo)"
      [ -n "$f" ] && for b in $backends; do run "rate-$b" "$f" --size 8x8 --quantity optical-depth --mode interval --volume-backend "$b"; done ;;
    cells)
      for b in $backends; do run "cells-1e7-$b" field:marschner-lobb:119 --size "$size" --quantity optical-depth --mode interval --volume-backend "$b"; done ;;
    *) echo "bench-backends: unknown set $set" >&2; exit 2 ;;
  esac
done
echo "stats in $out; tables: scripts/backends-table.py $out"
