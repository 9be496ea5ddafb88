#!/usr/bin/env bash
# Builds the CUDA backend here (build-cuda/) and stages what a GPU machine needs to run its tests
# and Table 1 benchmark into build-cuda/device-run/: the two programs and the shared libraries a
# bare CUDA image lacks (TBB; the CUDA runtime too, so the version matches the build). The GPU
# machine cannot build Tessera itself (no OpenSubdiv, TBB or GoogleTest there); it only runs this.
# Then, on the GPU machine, from the repository root (build-cuda/device-run carried along):
#   cd build-cuda/device-run && ./run.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="$root/build-cuda"
cmake -S "$root" -B "$build" -G Ninja -DTESSERA_BUILD_SERVER=OFF -DTESSERA_BUILD_VULKAN=OFF \
  -DTESSERA_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target tessera-cuda-tests tessera-cuda-bench

stage="$build/device-run"
rm -rf "$stage"
mkdir -p "$stage"
cp "$build/tests/cuda/tessera-cuda-tests" "$build/gpu/cuda/tessera-cuda-bench" "$stage/"
for program in tessera-cuda-tests tessera-cuda-bench; do
  ldd "$stage/$program" | awk '/libtbb|libcudart/ {print $3}' | xargs -r cp -L -t "$stage/"
done
cat >"$stage/run.sh" <<'RUN'
#!/usr/bin/env bash
# The GPU-only checks of the CUDA backend, in order; output is also saved to $OUT when set.
set -uo pipefail
cd "$(dirname "$0")"
export LD_LIBRARY_PATH="$PWD${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
log="${OUT:-.}"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>&1 | tee "$log/gpu.txt"
./tessera-cuda-tests 2>&1 | tee "$log/tests.txt"
if command -v compute-sanitizer >/dev/null; then
  for tool in memcheck racecheck synccheck; do
    compute-sanitizer --tool "$tool" --error-exitcode 1 ./tessera-cuda-tests \
      --gtest_filter='CudaFas.MatchesCpuForCrease*:CudaFas.GlobalScratch*:CudaFas.SmoothBatch*' \
      2>&1 | tail -n 20 | tee "$log/sanitizer-$tool.txt"
  done
fi
./tessera-cuda-bench 2>&1 | tee "$log/table1.txt"
RUN
chmod +x "$stage/run.sh"
du -sh "$stage"
