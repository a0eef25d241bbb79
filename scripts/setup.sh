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

if [ ${#missing[@]} -eq 0 ] && [ $mesa_ok -eq 1 ]; then
  exit 0
fi

echo "[setup] installing: ${missing[*]:-} (mesa-vulkan-drivers from bookworm-backports)"
if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  echo "deb http://deb.debian.org/debian bookworm-backports main" | $SUDO tee /etc/apt/sources.list.d/prismoid-backports.list >/dev/null
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${BASE_PACKAGES[@]}"
$SUDO apt-get install -y -q --no-install-recommends -t bookworm-backports "${BACKPORTS_PACKAGES[@]}"
echo "[setup] done"
