#!/usr/bin/env bash
# Installs the system packages Prismoid needs, through apt. Idempotent: when every
# package is already installed at a good version it returns without touching apt.
set -euo pipefail

# Packages from bookworm itself.
BASE_PACKAGES=(
  build-essential cmake ninja-build ccache pkg-config
  libvulkan-dev vulkan-tools vulkan-validationlayers
  glslang-tools
  libglfw3-dev libglm-dev libstb-dev libimgui-dev
  libgtest-dev
  libvtk9-dev
  nlohmann-json3-dev
  tetgen libtet1.5-dev
  libopenvdb-dev
  libmeshoptimizer-dev
  libimgui-dev
  clang libclang-rt-14-dev
  xvfb xauth
  paraview paraview-dev openmpi-bin python3-numpy
)
# Mesa's lavapipe from bookworm-backports: 25.x exposes VK_EXT_mesh_shader; bookworm's 22.3 does not.
BACKPORTS_PACKAGES=(mesa-vulkan-drivers)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${BASE_PACKAGES[@]}" "${BACKPORTS_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
mesa_version=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
mesa_ok=0
if [ -n "$mesa_version" ] && dpkg --compare-versions "$mesa_version" ge 25; then mesa_ok=1; fi

export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -ne 0 ] || [ $mesa_ok -ne 1 ]; then
  echo "[setup] installing: ${missing[*]:-} (mesa-vulkan-drivers from bookworm-backports)"
  if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    echo "deb http://deb.debian.org/debian bookworm-backports main" | $SUDO tee /etc/apt/sources.list.d/prismoid-backports.list >/dev/null
  fi
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${BASE_PACKAGES[@]}"
  $SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports "${BACKPORTS_PACKAGES[@]}"
fi

# ParaView's Python (pvpython, the paraview and vtkmodules packages, the class hierarchies the
# plugin's wrapping reads) ships in python3-paraview, which conflicts with python3-vtk9: both
# hold a vtkmodules package, and libvtk9-dev (the main build's VTK) depends on python3-vtk9.
# So it is unpacked beside the system, not installed; scripts/pvpython.sh runs it, and the
# plugin's build reads its hierarchies from there (paraview/CMakeLists.txt).
PV_PYTHON_ROOT=/opt/prismoid/python3-paraview
pv_version=$(dpkg-query -W -f='${Version}' paraview)
if [ "$(cat "$PV_PYTHON_ROOT/version" 2>/dev/null)" != "$pv_version" ]; then
  echo "[setup] unpacking python3-paraview $pv_version into $PV_PYTHON_ROOT"
  tmp=$(mktemp -d)
  chmod 755 "$tmp"
  (cd "$tmp" && { apt-get download "python3-paraview=$pv_version" 2>/dev/null || { $SUDO apt-get update -q && apt-get download "python3-paraview=$pv_version"; }; })
  $SUDO rm -rf "$PV_PYTHON_ROOT"
  $SUDO mkdir -p "$PV_PYTHON_ROOT"
  $SUDO dpkg -x "$tmp"/python3-paraview_*.deb "$PV_PYTHON_ROOT"
  echo "$pv_version" | $SUDO tee "$PV_PYTHON_ROOT/version" >/dev/null
  rm -rf "$tmp"
fi
echo "[setup] done"
