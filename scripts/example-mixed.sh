#!/usr/bin/env bash
# The user guide's example of a volume inside its geometry (docs/user-guide.md, "A volume inside
# its geometry"): the embedded default dataset (three Gaussian blobs of density in a box) around an
# opaque sphere, over a floor, lit by the default key light (which casts shadows). Writes the
# image and its stats into OUT_DIR and prints how far the GPU frame is from the CPU reference.
#   scripts/example-mixed.sh [--prismoid EXE] [OUT_DIR] [render options...]
#   (default: build/app/prismoid, docs/images; e.g. --size 1920x1080 --volume-backend compute)
set -euo pipefail
cd "$(dirname "$0")/.."
exe=build/app/prismoid
if [ "${1:-}" = "--prismoid" ]; then exe="$2"; shift 2; fi
out="${1:-docs/images}"
[ $# -gt 0 ] && shift
mkdir -p "$out"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The sphere (an icosphere, radius 0.3, low in the box beside the densest blob) and a floor
# under the box: plain OFF files.
python3 - "$work" <<'PY'
import math, sys
work = sys.argv[1]
t = (1 + 5 ** 0.5) / 2
v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
     (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
     (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
for _ in range(3):
    mid, nf = {}, []
    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            p = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
            n = math.sqrt(sum(x * x for x in p))
            v.append(tuple(x / n for x in p))
            mid[k] = len(v) - 1
        return mid[k]
    for a, b, c in f:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    f = nf
centre, r = (0.3, -0.45, 0.45), 0.3
with open(f"{work}/sphere.off", "w") as o:
    o.write(f"OFF\n{len(v)} {len(f)} 0\n")
    o.writelines(" ".join(f"{centre[i] + r * p[i]:.9g}" for i in range(3)) + "\n" for p in v)
    o.writelines(f"3 {a} {b} {c}\n" for a, b, c in f)
with open(f"{work}/floor.off", "w") as o:
    o.write("OFF\n4 2 0\n-4 -1.05 -4\n4 -1.05 -4\n4 -1.05 4\n-4 -1.05 4\n3 0 3 2\n3 0 2 1\n")
PY
"$exe" convert "$work/blobs.vtu" >/dev/null
"$exe" render "$work/blobs.vtu" "$work/sphere.off" "$work/floor.off" --quantity color --mode interval-exact-order \
  --eye 2.6,1.7,3.6 --target 0,-0.2,0 --size 800x600 --density-scale 45 --reference-error --output "$out/mixed-example.png" \
  --stats "$out/mixed-example.json" "$@"
