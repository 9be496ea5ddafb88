#!/usr/bin/env bash
# Builds here (in build/, the tree tools/build.sh configures) and stages into build/device-run/
# everything a lent GPU machine needs to run the GPU checks: the CUDA tests and benchmarks
# (Table 1: FAS; Table 2: the uniform grid; the adaptive tessellation's vertices), the server
# (built without the renderer in build-device-server/) and the CLI for the CUDA engine's check, the Vulkan renderer's tests and benchmarks, the shared
# libraries a bare CUDA image lacks (found with ldd; glibc, libstdc++ and the driver stay the
# machine's own), the Vulkan loader and glvnd packages (docs: ../.library/device/README.md), the
# Khronos validation layer, and the shared meshes the tests read. tessera-bench comes along for the
# CPU benchmarks on that machine's own cores: it reads bench/oracle_rates.csv under the source path
# compiled into it, so link the checkout there to that path first. The GPU machine cannot build Tessera
# (no OpenSubdiv, TBB, GoogleTest or Vulkan headers there); it only runs this.
# Then, on the GPU machine, from the repository root (carry: build/device-run):
#   build/device-run/run.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$root/build"
[ -f "$build/CMakeCache.txt" ] || cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
programs=(tests/cuda/tessera-cuda-tests gpu/cuda/tessera-cuda-bench gpu/cuda/tessera-cuda-table2
          gpu/cuda/tessera-cuda-adaptive
          tests/vulkan/tessera-render-tests tests/render_engine/tessera-render-engine-tests
          bench/tessera-render-bench bench/tessera-frame-bench bench/tessera-bench client/tessera)
targets=()
for program in "${programs[@]}"; do targets+=("$(basename "$program")"); done
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"
# The server without the renderer: the renderer's OpenImageIO alone brings some 380 MB of
# libraries, past what a device call carries (64 MiB).
server_build="$root/build-device-server"
[ -f "$server_build/CMakeCache.txt" ] || cmake -S "$root" -B "$server_build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DTESSERA_BUILD_VULKAN=OFF -DTESSERA_BUILD_TESTS=OFF -DTESSERA_BUILD_BENCH=OFF
cmake --build "$server_build" -j"$(nproc)" --target tessera-server

stage="$build/device-run"
rm -rf "$stage"
mkdir -p "$stage/lib" "$stage/models" "$stage/layers" "$stage/gl"
for program in "${programs[@]/#/$build/}" "$server_build/server/tessera-server"; do
  cp "$program" "$stage/"
  ldd "$program" | awk '$3 ~ /^\// {print $3}' |
    { grep -Ev '/(libc|libm|libdl|librt|libpthread|libstdc\+\+|libgcc_s|libvulkan|libcuda)\.so' || true; } |
    xargs -r cp -L -t "$stage/lib/"
done
cp "$root"/../shared/models/{bigguy,monsterfrog,armorguy,t-rex,car}.obj "$stage/models/"
cp -r "$root/../shared/models/opensubdiv-shapes" "$stage/models/"
cp /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json "$stage/layers/"
cp -L /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$stage/lib/"
# The loader and glvnd, as amd64 Debian packages, unpacked into / there.
apt_options=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64)
mkdir -p /tmp/amd64/partial
[ -n "$(ls /tmp/amd64/*Packages* 2>/dev/null)" ] || apt-get "${apt_options[@]}" update >/dev/null
(cd "$stage/gl" && apt-get "${apt_options[@]}" download libvulkan1 libegl1 libglvnd0 libopengl0 \
  libgl1 libglx0 libgles2 >/dev/null)
# Packed: a device call carries 64 MiB at most, and the libraries are 55 MB as files (the
# validation layer alone 22 MB), about 20 MB packed. run.sh unpacks them.
tar -czf "$stage/lib.tar.gz" -C "$stage" lib && rm -r "$stage/lib"
cp "$root/gpu/cuda/device-run.sh" "$stage/run.sh"
cp "$root/gpu/cuda/server-engine-check.sh" "$stage/"
du -sh "$stage"
