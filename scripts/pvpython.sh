#!/usr/bin/env bash
# ParaView's Python with the modules scripts/setup.sh unpacked (paraview/pvrun.py says why):
#   scripts/pvpython.sh SCRIPT [ARGS...]            pvpython
#   scripts/pvpython.sh --batch SCRIPT [ARGS...]    pvbatch (e.g. under mpirun -np N)
# The plugin built by scripts/build.sh is build/paraview/lib/paraview-plugins/PrismoidVolume/PrismoidVolume.so
# (LoadPlugin it, or set PV_PLUGIN_PATH to its folder).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
root="${PRISMOID_PARAVIEW_PYTHON:-/opt/prismoid/python3-paraview}"
if [ ! -x "$root/usr/bin/pvpython3.11" ]; then
  echo "scripts/pvpython.sh: ParaView's Python is not unpacked at $root: run scripts/setup.sh" >&2
  exit 2
fi
export PYTHONPATH="$root/usr/lib/python3/dist-packages${PYTHONPATH:+:$PYTHONPATH}"
if [ "${1:-}" = "--batch" ]; then
  shift
  exec pvbatch "$here/paraview/pvrun.py" "$@"
fi
exec "$root/usr/bin/pvpython3.11" "$here/paraview/pvrun.py" "$@"
