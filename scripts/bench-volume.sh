#!/usr/bin/env bash
# Times interval shading on the default dataset and the paper's real datasets (bunny, armadillo:
# datasets/fetch-real.sh builds them) and prints a markdown table of the GPU time of each pass,
# from the --stats JSON of `prismoid render` (optical depth, the default camera framing the data).
# Needs bash, awk and sort only: it runs on the GPU machine from the bundle (docs/gpu.md).
#
#   scripts/bench-volume.sh [options] [-- extra render options]
#     --data DIR         folder with bunny.vtk and armadillo.vtk (or .vtk.xz / .vtk.gz, unpacked
#                        into a temporary folder first); default $PRISMOID_REAL_DIR or datasets/real
#     --size WxH         image size; repeat for several (default 3840x2160 and 1024x1024)
#     --configs LIST     quantity:mode pairs, e.g. "optical-depth:interval color:interval-sorted"
#                        (default optical-depth:interval)
#     --color-array NAME point array for color on files (default height; the default dataset
#                        uses its density)
#     --frames N         timed frames per process after one warm-up frame (default 10); the
#                        per-process time is their median
#     --repeats N        processes per dataset, size and config (default 1)
#     --warmup N         untimed processes first (default 0)
#     --datasets LIST    names to run, e.g. "default bunny" (default: default bunny armadillo)
#     --out DIR          stats JSONs, the first run's PNG, times.tsv and table.md (default out/bench-volume)
#     --prismoid CMD     the executable (default $PRISMOID, else build/app/prismoid, else bundle/prismoid.sh)
# A dataset whose file is missing is reported and skipped. On lavapipe use a small --size.
set -euo pipefail
cd "$(dirname "$0")/.."

data_dir="${PRISMOID_REAL_DIR:-datasets/real}"
sizes=()
repeats=1
warmup=0
frames=10
configs="optical-depth:interval"
color_array=height
datasets="default bunny armadillo"
out_dir="out/bench-volume"
prismoid="${PRISMOID:-}"
extra=()

usage() { awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; }
fail() { echo "bench-volume: $*" >&2; exit 2; }
need_value() { [ $# -ge 2 ] || fail "$1 needs a value"; }

while [ $# -gt 0 ]; do
  case "$1" in
    --data) need_value "$@"; data_dir="$2"; shift 2 ;;
    --size) need_value "$@"; sizes+=("$2"); shift 2 ;;
    --repeats) need_value "$@"; repeats="$2"; shift 2 ;;
    --frames) need_value "$@"; frames="$2"; shift 2 ;;
    --configs) need_value "$@"; configs="$2"; shift 2 ;;
    --color-array) need_value "$@"; color_array="$2"; shift 2 ;;
    --warmup) need_value "$@"; warmup="$2"; shift 2 ;;
    --datasets) need_value "$@"; datasets="$2"; shift 2 ;;
    --out) need_value "$@"; out_dir="$2"; shift 2 ;;
    --prismoid) need_value "$@"; prismoid="$2"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    --) shift; extra=("$@"); break ;;
    *) fail "unknown option $1 (see --help)" ;;
  esac
done
[ ${#sizes[@]} -gt 0 ] || sizes=(3840x2160 1024x1024)
[[ "$repeats" =~ ^[1-9][0-9]*$ ]] || fail "--repeats must be a positive whole number"
[[ "$warmup" =~ ^[0-9]+$ ]] || fail "--warmup must be a whole number"
if [ -z "$prismoid" ]; then
  if [ -x build/app/prismoid ]; then prismoid=build/app/prismoid
  elif [ -x bundle/prismoid.sh ]; then prismoid=bundle/prismoid.sh
  else fail "no prismoid: build it (scripts/build.sh), or pass --prismoid CMD"; fi
fi
# The bundle's launcher sets XDG_RUNTIME_DIR; a plain build run from a bare shell needs one too.
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

mkdir -p "$out_dir"
scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT

# The file for a dataset name ("" for the embedded default), unpacking a compressed copy if that
# is all there is (compressed files travel to the GPU machine in a third of the space).
dataset_file() {
  local name="$1" base="$data_dir/$1.vtk"
  if [ "$name" = default ]; then echo ""; return; fi
  if [ -f "$base" ]; then echo "$base"; return; fi
  local unpacked="$scratch/$name.vtk"
  if [ -f "$unpacked" ]; then echo "$unpacked"; return; fi
  if [ -f "$base.xz" ]; then xz -dc "$base.xz" >"$unpacked.partial"
  elif [ -f "$base.gz" ]; then gzip -dc "$base.gz" >"$unpacked.partial"
  else return 1; fi
  mv "$unpacked.partial" "$unpacked"
  echo "$unpacked"
}

# One render; its stats JSON to $2. Exits with prismoid's output shown if the render fails.
render() {
  local file="$1" stats="$2" size="$3" image="$4" config="$5"
  local args=(render)
  [ -n "$file" ] && args+=("$file")
  args+=(--quantity "${config%%:*}" --mode "${config#*:}" --frames "$frames" --size "$size" --output "$image" --stats "$stats")
  # Colour needs a scalar field: the real datasets carry 'height' (datasets/meshprep.py); the
  # embedded default dataset uses its density.
  if [ "${config%%:*}" = color ] && [ -n "$file" ]; then args+=(--array "$color_array"); fi
  if ! "$prismoid" "${args[@]}" ${extra[@]+"${extra[@]}"} >"$scratch/log" 2>&1; then
    cat "$scratch/log" >&2
    echo "bench-volume: failed: $prismoid ${args[*]} ${extra[*]:-}" >&2
    exit 1
  fi
}

# Lines of a stats JSON as "pass<TAB>ms" (the layout app/common/stats_json writes: one pass per line).
passes_of() {
  sed -n 's/.*{"name": "\([^"]*\)", "gpu_ms": \([^,}]*\).*/\1\t\2/p' "$1"
}
json_field() {  # json_field FILE KEY: a top-level string or number
  sed -n -e "s/^  \"$2\": \"\(.*\)\",\{0,1\}$/\1/p" -e "s/^  \"$2\": \([^\",]*\),\{0,1\}$/\1/p" "$1" | head -n1
}

times="$out_dir/times.tsv"
printf 'dataset\tcells\tsize\tconfig\trun\tpass\tgpu_ms\n' >"$times"
device="" driver=""
for name in $datasets; do
  if ! file="$(dataset_file "$name")"; then
    echo "bench-volume: skipping $name: no $data_dir/$name.vtk (datasets/fetch-real.sh builds it)" >&2
    continue
  fi
  for size in "${sizes[@]}"; do
    for config in $configs; do
      for ((i = 1; i <= warmup; ++i)); do
        render "$file" "$scratch/warmup.json" "$size" "$scratch/image.png" "$config"
      done
      for ((i = 1; i <= repeats; ++i)); do
        stats="$out_dir/$name-$size-${config//:/-}-$i.json"
        image="$scratch/image.png"
        [ "$i" -eq 1 ] && image="$out_dir/$name-$size-${config//:/-}.png"
        render "$file" "$stats" "$size" "$image" "$config"
        cells="$(json_field "$stats" cells)"
        device="$(json_field "$stats" device)"
        driver="$(json_field "$stats" driver)"
        while IFS=$'\t' read -r pass ms; do
          printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$cells" "$size" "$config" "$i" "$pass" "$ms" >>"$times"
        done < <(passes_of "$stats")
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$cells" "$size" "$config" "$i" total "$(json_field "$stats" gpu_ms_total)" >>"$times"
        echo "  $name $size $config run $i: $(json_field "$stats" gpu_ms_total) ms GPU, $(json_field "$stats" gpu_mesh_bytes) mesh bytes, $(json_field "$stats" fragments) fragments, $(json_field "$stats" proxy_triangles) proxy triangles" >&2
      done
    done
  done
done
[ -n "$device" ] || fail "nothing ran"

# median (min-max) of each dataset x size x config x pass, passes as columns in order of appearance.
summarize() {
  local keys passes
  keys="$(awk -F'\t' 'NR > 1 && !seen[$1 FS $2 FS $3 FS $4]++ { print $1 "\t" $2 "\t" $3 "\t" $4 }' "$times")"
  passes="$(awk -F'\t' 'NR > 1 && !seen[$6]++ { print $6 }' "$times")"
  local camera="default camera (framing the data from +z)"
  [ ${#extra[@]} -gt 0 ] && camera="render options: ${extra[*]}"
  echo "Device: $device ($driver). $camera. GPU ms per pass: median of $frames frames after a warm-up frame; with several processes, median (min-max) of the $repeats process medians."
  echo
  printf '| dataset | cells | size | quantity:mode |'; while read -r p; do printf ' %s ms |' "$p"; done <<<"$passes"; echo
  printf '| --- | ---: | --- | --- |'; while read -r p; do printf ' ---: |'; done <<<"$passes"; echo
  while IFS=$'\t' read -r name cells size config; do
    printf '| %s | %s | %s | %s |' "$name" "$cells" "$size" "$config"
    while read -r p; do
      awk -F'\t' -v n="$name" -v s="$size" -v c="$config" -v p="$p" '$1 == n && $3 == s && $4 == c && $6 == p { print $7 }' "$times" |
        sort -g | awk '{ v[NR] = $1 } END {
          if (NR == 0) { printf " - |"; exit }
          m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
          if (NR == 1) printf " %s |", fmt(m); else printf " %s (%s-%s) |", fmt(m), fmt(v[1]), fmt(v[NR]) }
        function fmt(x) { return sprintf(x >= 100 ? "%.0f" : x >= 10 ? "%.1f" : x >= 1 ? "%.2f" : "%.3f", x) }'
    done <<<"$passes"
    echo
  done <<<"$keys"
}
summarize | tee "$out_dir/table.md"
