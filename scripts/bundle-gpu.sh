#!/usr/bin/env bash
# Builds here a self-contained bundle that runs `prismoid render` and `prismoid devices` on a
# machine with a GPU driver but no package registry (our H100 machine): the executable (its
# SPIR-V is embedded), every shared library it needs but glibc's (the Vulkan loader included),
# the validation layer for --validate, and a launcher. See docs/gpu.md.
#   scripts/bundle-gpu.sh [OUT_DIR]      (default: bundle/)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-bundle}"
./scripts/setup.sh
./scripts/build.sh >/dev/null
rm -rf "$out"
mkdir -p "$out/lib" "$out/layers"
cp build/app/prismoid "$out/"
# The GPU test suites too, so the numerical tests can run against the CPU reference there
# (bundle/run-tests.sh [SUITE]); their libraries are a subset of prismoid's. test_gpu: volumes;
# test_rt: acceleration structures and the ray-tracing pipeline against the CPU BVH;
# test_surface_gpu: forward and shadowed forward; test_htex_gpu: the Htex passes;
# test_restir_gi: ReSTIR GI on the dense set; test_htex_gi: ReSTIR GI hosted by Htex;
# test_texel_gpu: texel shading; test_msa_gpu: the meshlet shading atlas; test_mixed_gpu: a volume
# inside its surfaces.
gpu_tests="test_gpu test_rt test_surface_gpu test_htex_gpu test_restir_gi test_htex_gi test_texel_gpu test_msa_gpu test_fastatlas_gpu test_surface_renderer test_mixed_gpu"
for t in $gpu_tests; do [ -x "build/tests/$t" ] && cp "build/tests/$t" "$out/"; done
# glibc and the dynamic linker come from the target machine (newer glibc runs older binaries).
ldd build/app/prismoid | awk '/=> \// {print $3}' |
  grep -vE '/(libc|libm|libdl|libpthread|librt|ld-linux-x86-64)\.so' |
  while read -r lib; do cp -L "$lib" "$out/lib/"; done
# The Khronos validation layer, for `--validate` there.
layer_json=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
if [ -f "$layer_json" ]; then
  cp -L /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$out/layers/"
  sed 's#"library_path": *"[^"]*"#"library_path": "./libVkLayer_khronos_validation.so"#' "$layer_json" >"$out/layers/VkLayer_khronos_validation.json"
fi
# Debug symbols stay here: the device call carries at most 64 MiB.
strip --strip-unneeded "$out/prismoid" "$out"/lib/*.so* "$out"/layers/*.so 2>/dev/null || true
for t in $gpu_tests; do [ -f "$out/$t" ] && strip --strip-unneeded "$out/$t"; done
cat >"$out/prismoid.sh" <<'LAUNCH'
#!/usr/bin/env bash
# Runs the bundled prismoid with its own libraries and the machine's Vulkan driver.
here="$(cd "$(dirname "$0")" && pwd)"
export LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export VK_ADD_LAYER_PATH="$here/layers"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp}"
# NVIDIA's ICD manifest where the GPU machine keeps it, unless the system loader finds one.
if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ] &&
   [ ! -f /usr/share/vulkan/icd.d/nvidia_icd.json ] && [ ! -f /etc/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
exec "$here/${PRISMOID_BUNDLE_EXE:-prismoid}" "$@"
LAUNCH
chmod +x "$out/prismoid.sh"
# The GPU tests with the same environment (validation layer on, as here).
# bundle/run-tests.sh [SUITE] [gtest options]: test_gpu, or test_SUITE (rt, surface_gpu, fastatlas_gpu, surface_renderer,
# htex_gpu, restir_gi, htex_gi, texel_gpu, msa_gpu, mixed_gpu).
printf '#!/usr/bin/env bash\nexe=test_gpu\ncase "${1:-}" in rt|surface_gpu|htex_gpu|restir_gi|htex_gi|texel_gpu|msa_gpu|fastatlas_gpu|surface_renderer|mixed_gpu) exe=test_$1; shift ;; esac\nPRISMOID_BUNDLE_EXE=$exe exec "$(dirname "$0")/prismoid.sh" "$@"\n' >"$out/run-tests.sh"
chmod +x "$out/run-tests.sh"
# About 80 MB with the VTK, TetGen and image libraries: over the 64 MiB a device call carries, so
# it also travels packed (about 17 MB): carry $out.tar.xz and unpack it there first.
tar -cJf "$out.tar.xz.partial" "$out" && mv "$out.tar.xz.partial" "$out.tar.xz"
du -sh "$out" "$out.tar.xz"
echo "bundle ready: $out/prismoid.sh devices (packed: $out.tar.xz)"
