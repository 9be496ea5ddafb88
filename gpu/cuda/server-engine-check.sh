#!/usr/bin/env bash
# On the GPU machine (device-run.sh's server-engine step, from the staged folder): the real server
# started with --engine cuda answers a tessellate request for bigguy, car and armorguy at 1e-3 of
# the diagonal with the GLB the CLI writes in process on the CPU, byte for byte; prints the
# server's info, each remote call's time and summary beside the local one, and the server's log.
set -uo pipefail
address=127.0.0.1:50071
work=$(mktemp -d)
./tessera-server --listen "$address" --metrics-listen off --store "sqlite:$work/meshes.db" --engine cuda \
  --ready-file "$work/ready" >"$work/server.log" 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null; wait "$server" 2>/dev/null; echo "--- server log"; cat "$work/server.log"' EXIT
for _ in $(seq 300); do [ -s "$work/ready" ] && break; sleep 0.1; done
./tessera --server "$address" info || exit 1
failed=0
for model in bigguy car armorguy; do
  ./tessera --server "$address" upload "models/$model.obj" --name "$model" || { failed=1; continue; }
  for run in 1 2; do  # the second call finds the patch set and the device's surface cached
    start=$(date +%s%N)
    ./tessera --server "$address" tessellate "meshes/$model" --tolerance 1e-3 --relative -o "$work/$model-cuda.glb" ||
      failed=1
    echo "$model remote call $run: $((($(date +%s%N) - start) / 1000000)) ms"
  done
  start=$(date +%s%N)
  ./tessera tessellate "models/$model.obj" --tolerance 1e-3 --relative -o "$work/$model-cpu.glb" || failed=1
  echo "$model local CPU call (with preprocessing): $((($(date +%s%N) - start) / 1000000)) ms"
  if cmp "$work/$model-cuda.glb" "$work/$model-cpu.glb"; then
    echo "$model: the CUDA engine's GLB equals the CPU's ($(stat -c %s "$work/$model-cpu.glb") bytes)"
  else
    echo "$model: the CUDA engine's GLB DIFFERS from the CPU's"
    failed=1
  fi
done
exit "$failed"
