#!/usr/bin/env bash
# The GPU checks, run on a lent GPU machine from the folder stage-device-run.sh fills. Each step
# has its own time limit, so one hang cannot take the others' time; every step's output goes to
# $OUT (at most 8 files come back): summary.txt holds the device and each step's exit status.
set -uo pipefail
cd "$(dirname "$0")"
log="${OUT:-.}"
[ -d lib ] || tar -xzf lib.tar.gz  # packed by stage-device-run.sh
export LD_LIBRARY_PATH="$PWD/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export TESSERA_MODELS_DIR="$PWD/models" VK_LAYER_PATH="$PWD/layers"
export XDG_RUNTIME_DIR=/tmp/xdg && mkdir -p "$XDG_RUNTIME_DIR"
for f in gl/*.deb; do dpkg -x "$f" /; done
ldconfig
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -f "$icd" ]; then
  export VK_DRIVER_FILES="$icd" VK_ICD_FILENAMES="$icd"
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
summary="$log/summary.txt"
{ nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv; nproc; } \
  >"$summary" 2>&1

step() {  # step NAME SECONDS COMMAND...: output to NAME.txt (appended), status to the summary
  local name=$1 seconds=$2
  shift 2
  local start=$SECONDS
  timeout "$seconds" "$@" >>"$log/$name.txt" 2>&1
  echo "$name: $* -> exit $? in $((SECONDS - start)) s" >>"$summary"
}

# Most telling first: if the call runs out of time, the later steps are the ones lost.
step cuda-tests 90 ./tessera-cuda-tests
step server-engine 120 ./server-engine-check.sh
step table2 90 ./tessera-cuda-table2
step table1 60 ./tessera-cuda-bench
step adaptive 120 ./tessera-cuda-adaptive --tolerances 1e-2,1e-3
step render-tests 90 ./tessera-render-tests
step render-tests 90 ./tessera-render-engine-tests
if command -v compute-sanitizer >/dev/null; then
  for tool in memcheck racecheck synccheck; do
    step sanitizer 40 compute-sanitizer --tool "$tool" --error-exitcode 1 ./tessera-cuda-tests \
      --gtest_filter='CudaFas.MatchesCpuForCrease*:CudaFas.GlobalScratch*:CudaFas.SmoothBatch*'
  done
  step sanitizer 60 compute-sanitizer --tool memcheck --error-exitcode 1 ./tessera-cuda-tests \
    --gtest_filter='CudaUniformGrid.*'
  for tool in memcheck racecheck synccheck; do
    step sanitizer 60 compute-sanitizer --tool "$tool" --error-exitcode 1 ./tessera-cuda-tests \
      --gtest_filter='CudaVertices.EqualTheCpuEngineOnEveryShape'
  done
fi
step render-bench 45 ./tessera-render-bench --benchmark_min_time=0.2
step render-bench 60 ./tessera-frame-bench --benchmark_filter='Frame/'
# Where the kernels' time goes (no clock control, as METHOD.md asks): one launch of each.
if command -v ncu >/dev/null; then
  sections=(--section SpeedOfLight --section LaunchStats --section Occupancy --section WarpStateStats
            --section MemoryWorkloadAnalysis --section ComputeWorkloadAnalysis)
  step ncu 60 ncu --clock-control none "${sections[@]}" -k regex:warpFasKernel -c 1 \
    ./tessera-cuda-bench --rings 100000 --valences 6 --depths 5 --repetitions 1
  step ncu 60 ncu --clock-control none "${sections[@]}" -k regex:uniformGridKernel -c 1 \
    ./tessera-cuda-table2 --models t-rex --levels 64 --repetitions 1
  step ncu 60 ncu --clock-control none "${sections[@]}" -k regex:vertexKernel -c 1 \
    ./tessera-cuda-adaptive --models armorguy --tolerances 1e-3
fi
cat "$summary"
