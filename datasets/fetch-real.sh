#!/usr/bin/env bash
# Builds the real datasets the interval-shading paper times, as tetrahedral legacy .vtk files:
#   datasets/real/bunny.vtk      Stanford bunny, about 61k tetrahedra (the paper: 61,042)
#   datasets/real/armadillo.vtk  armadillo, about 962k tetrahedra (the paper: 959,042)
#   datasets/real/bunny_fog.vdb  an OpenVDB fog volume of the bunny (prismoid convert, with a build)
# from the closed surface meshes in Debian's libcgal-demo (downloaded and unpacked into a cache,
# never installed), tetrahedralized by Debian's TetGen 1.5. Each file carries a cell array
# 'extinction' = 1 (TetGen writes no arrays). Idempotent: existing outputs are kept.
#   datasets/fetch-real.sh [--force] [--pack]
#     --force  rebuilds the .vtk files
#     --pack   also writes xz-compressed copies to datasets/real/packed/ (2.7x smaller: 11 MB for
#              the armadillo), the folder to carry to the GPU machine with the bundle, whose
#              copy may carry 64 MiB in all; scripts/bench-volume.sh --data reads them as they are
# Environment: PRISMOID_REAL_DIR (output folder, default datasets/real),
#              PRISMOID_DATA_CACHE (download cache, default datasets/.cache).
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$(pwd)"
out_dir="${PRISMOID_REAL_DIR:-$repo/datasets/real}"
cache="${PRISMOID_DATA_CACHE:-$repo/datasets/.cache}"
force=0
pack=0
for arg in "$@"; do
  case "$arg" in
    --force) force=1 ;;
    --pack) pack=1 ;;
    *) echo "usage: datasets/fetch-real.sh [--force] [--pack]" >&2; exit 2 ;;
  esac
done

fail() { echo "fetch-real: $*" >&2; exit 1; }
step() { echo "== $*"; }

# Debian's python3 has the vtk module (python3-vtk9); a pyenv or venv python3 first on PATH may not.
python=/usr/bin/python3
meshprep() { "$python" "$repo/datasets/meshprep.py" "$@"; }

# The same switches for both meshes: TetGen's quality bound (radius-edge ratio) sets the count;
# the bunny's scanned surface is first decimated so that the same kind of mesh lands near the
# paper's count. Counts below are what this recipe gave with Debian 12's tetgen 1.5.0-5, VTK 9.1.
bunny_triangles=3000
bunny_switches=-pq1.414
armadillo_switches=-pq1.385
expected_bunny=60952
expected_armadillo=962363

apt_install() {
  local packages=("$@")
  [ "$(id -u)" -eq 0 ] || fail "needs ${packages[*]}; run as root (apt-get install ${packages[*]})"
  step "apt-get install ${packages[*]}"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${packages[@]}" >/dev/null ||
    { apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q "${packages[@]}" >/dev/null; } ||
    fail "apt-get install ${packages[*]} failed"
}

ensure_tools() {
  command -v tetgen >/dev/null || apt_install tetgen
  "$python" -c 'import vtk' 2>/dev/null || apt_install python3-vtk9
  command -v tetgen >/dev/null || fail "tetgen is still missing after installing it"
  "$python" -c 'import vtk' 2>/dev/null || fail "$python cannot import vtk (python3-vtk9)"
}

# bunny00.off and armadillo.off from libcgal-demo's data.tar.gz, downloaded once.
fetch_meshes() {
  local meshes="$cache/meshes"
  if [ -f "$meshes/bunny00.off" ] && [ -f "$meshes/armadillo.off" ] && [ -f "$meshes/elephant.off" ] &&
     [ -f "$out_dir/skull_2.9.inr" ]; then return; fi
  mkdir -p "$cache/deb" "$meshes"
  step "downloading libcgal-demo (not installed: unpacked into $cache)"
  # apt-get download writes into the current folder; as root it warns that the _apt user cannot
  # write there, which is harmless.
  (cd "$cache/deb" && { apt-get download -q libcgal-demo 2>/dev/null ||
                        { apt-get update -q >/dev/null && apt-get download -q libcgal-demo; }; }) ||
    fail "apt-get download libcgal-demo failed"
  local deb
  deb="$(ls "$cache"/deb/libcgal-demo_*.deb | head -n1)"
  rm -rf "$cache/unpacked"
  dpkg -x "$deb" "$cache/unpacked" || fail "dpkg -x $deb failed"
  local data
  data="$(find "$cache/unpacked" -name data.tar.gz | head -n1)"
  [ -n "$data" ] || fail "no data.tar.gz in $deb"
  tar -xzf "$data" -C "$cache/unpacked" data/meshes/bunny00.off data/meshes/armadillo.off data/meshes/elephant.off ||
    fail "$data has no data/meshes/bunny00.off, armadillo.off or elephant.off"
  mv "$cache/unpacked/data/meshes/bunny00.off" "$cache/unpacked/data/meshes/armadillo.off" \
     "$cache/unpacked/data/meshes/elephant.off" "$meshes/"
  # The CT skull opens as it is (an INRIMAGE volume, 64^3 float voxels: 1.5 M tetrahedra).
  mkdir -p "$out_dir"
  tar -xzf "$data" -C "$cache/unpacked" data/images/skull_2.9.inr || fail "$data has no data/images/skull_2.9.inr"
  mv "$cache/unpacked/data/images/skull_2.9.inr" "$out_dir/"
  echo "   $(basename "$deb"): $data"
  rm -rf "$cache/unpacked" "$cache/deb"
}

seconds_since() { awk -v s="$1" -v e="$(date +%s.%N)" 'BEGIN { printf "%.1f", e - s }'; }

# tetrahedralize NAME SURFACE.off SWITCHES EXPECTED: TetGen, then the finished binary .vtk.
tetrahedralize() {
  local name="$1" surface="$2" switches="$3" expected="$4"
  local final="$out_dir/$name.vtk" work="$cache/work/$name"
  if [ -f "$final" ] && [ "$force" -eq 0 ]; then
    echo "   $final exists (--force rebuilds it)"
    return
  fi
  rm -rf "$work" && mkdir -p "$work"
  cp "$surface" "$work/$name.off"
  step "tetgen $switches -kQ $name.off"
  local start
  start="$(date +%s.%N)"
  (cd "$work" && tetgen "$switches" -kQ "$name.off" >tetgen.log 2>&1) ||
    { cat "$work/tetgen.log" >&2; fail "tetgen failed on $name.off"; }
  local seconds
  seconds="$(seconds_since "$start")"
  [ -f "$work/$name.1.vtk" ] || fail "tetgen wrote no $name.1.vtk"
  meshprep finish "$work/$name.1.vtk" "$final.partial" >/dev/null
  mv "$final.partial" "$final"
  local tets
  tets="$(meshprep count "$final")"
  echo "   $name: $tets tetrahedra in ${seconds} s (tetgen), $(du -h "$final" | cut -f1) $final"
  [ "$tets" -eq "$expected" ] ||
    echo "   note: $name has $tets tetrahedra where this recipe gave $expected with Debian 12's tetgen"
  rm -rf "$work"
}

ensure_tools
fetch_meshes
mkdir -p "$out_dir"
step "input surfaces"
meshprep info "$cache/meshes/bunny00.off"
meshprep info "$cache/meshes/armadillo.off"

bunny_surface="$cache/meshes/bunny-$bunny_triangles.off"
if [ ! -f "$bunny_surface" ]; then
  step "decimating bunny00.off to $bunny_triangles triangles (VTK quadric decimation)"
  meshprep simplify "$cache/meshes/bunny00.off" "$bunny_surface.partial" "$bunny_triangles"
  mv "$bunny_surface.partial" "$bunny_surface"
fi
meshprep info "$bunny_surface"

tetrahedralize bunny "$bunny_surface" "$bunny_switches" "$expected_bunny"
tetrahedralize armadillo "$cache/meshes/armadillo.off" "$armadillo_switches" "$expected_armadillo"
# The elephant through Prismoid's own surface path (the TetGen library, in-process checks), when
# a prismoid build is at hand: 5,558 triangles -> about 153,000 tetrahedra with -q1.2.
prismoid_exe="${PRISMOID:-$repo/build/app/prismoid}"
if [ -x "$prismoid_exe" ]; then
  if [ ! -f "$out_dir/elephant.vtu" ]; then
    step "tetrahedralizing elephant.off with prismoid convert (TetGen -pq1.2)"
    XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}" "$prismoid_exe" convert "$cache/meshes/elephant.off" "$out_dir/elephant.vtu" \
      --tetgen-quality 1.2 || fail "prismoid convert elephant.off failed"
  fi
  # An OpenVDB fog volume made from the full-resolution bunny by OpenVDB's meshToLevelSet and
  # sdfToFogVolume (voxel size: the bounding-box diagonal / 128; about 100k active voxels).
  if [ ! -f "$out_dir/bunny_fog.vdb" ] || [ "$force" -eq 1 ]; then
    step "bunny00.off -> bunny_fog.vdb with prismoid convert (OpenVDB fog volume)"
    XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}" "$prismoid_exe" convert "$cache/meshes/bunny00.off" "$out_dir/bunny_fog.vdb" \
      --vdb fog --fill-holes || fail "prismoid convert bunny00.off bunny_fog.vdb failed"
  fi
  # Generated analytic fields, for accuracy against closed forms: the constant-extinction ball
  # (optical depth = sigma x chord) and Marschner-Lobb sampled at the points of a 32^3-cube box.
  # (`prismoid render field:marschner-lobb:32 --mode interval-march` marches the field itself.)
  for spec in "ball:4 ball" "field:marschner-lobb:32 marschner_lobb"; do
    set -- $spec
    if [ ! -f "$out_dir/$2.vtu" ]; then
      step "generating $2.vtu ($1)"
      XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}" "$prismoid_exe" convert "$1" "$out_dir/$2.vtu" >/dev/null ||
        fail "prismoid convert $1 failed"
    fi
  done
else
  echo "   (no prismoid build at $prismoid_exe: elephant.vtu, bunny_fog.vdb skipped; scripts/build.sh makes one)"
fi
if [ "$pack" -eq 1 ]; then
  mkdir -p "$out_dir/packed"
  for name in bunny armadillo; do
    packed="$out_dir/packed/$name.vtk.xz"
    if [ -f "$packed" ] && [ "$packed" -nt "$out_dir/$name.vtk" ]; then continue; fi
    step "xz $name.vtk -> $packed"
    xz -T2 -c "$out_dir/$name.vtk" >"$packed.partial" || fail "xz $name.vtk failed"
    mv "$packed.partial" "$packed"
  done
  du -h "$out_dir"/packed/*.vtk.xz
fi
step "done: $(cd "$out_dir" && ls -1 ./*.vtk ./*.vtu ./*.inr ./*.vdb 2>/dev/null | tr '\n' ' ')in $out_dir"
