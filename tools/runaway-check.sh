#!/usr/bin/env bash
# Issue 47's "Done when" lines that a script can measure against a fresh server with its default
# limits (bench/RUNAWAY-RESULTS.md has the rest: the tests, the storm probe and the soak):
#   1. the issue's runaway request (an 8-vertex cube at +-1, pixel camera at (0,0,5) looking at the
#      origin, 640x480, fov 1e-6, 1e-9 and 1e-2 degrees): how it ends and how soon, and the
#      server's CPU and resident memory after;
#   2. pixel mode's floor: the coarsest pixel accuracy that fov 1e-2 allows is served, and the
#      tolerance it planned to, over the cube's diagonal, is at least --min-relative-tolerance;
#   3. SIGTERM with long jobs running (bigguy at relative 1e-6 on every job slot and one queued):
#      the seconds until the process is gone, against --drain-delay + 5 s;
#   4. a 8192 x 8192 RAW frame of bigguy: resident memory before (after a 64 x 64 frame), after, 5 s
#      after, the peak, and what the caches grew by.
# Prints one line per measurement.
#   tools/runaway-check.sh [--build-dir build]
set -euo pipefail
cd "$(dirname "$0")/.."

build=build
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=$2; shift 2 ;;
    *) echo "usage: $0 [--build-dir DIR]" >&2; exit 2 ;;
  esac
done
models=${TESSERA_MODELS_DIR:-$(pwd)/../shared/models}
cli=$build/client/tessera
server_binary=$build/server/tessera-server
work=$(mktemp -d /tmp/tessera-runaway-XXXXXX)
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$work}
server_pid=
cleanup() {
  [ -n "$server_pid" ] && kill -9 "$server_pid" 2>/dev/null || true
  jobs -p | xargs -r kill 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

now() { date +%s.%N; }
rss_mib() { awk '/^VmRSS/ {printf "%.0f", $2 / 1024}' "/proc/$1/status"; }
hwm_mib() { awk '/^VmHWM/ {printf "%.0f", $2 / 1024}' "/proc/$1/status"; }
cpu_ticks() { awk '{print $14 + $15}' "/proc/$1/stat"; }
# Seconds until the process used no CPU for 0.5 s (sampled every 0.1 s), up to 20 s.
seconds_until_idle() {
  local pid=$1 start last quiet=0 ticks
  start=$(now)
  last=$(cpu_ticks "$pid")
  while awk -v s="$start" -v n="$(now)" 'BEGIN {exit !(n - s < 20)}'; do
    sleep 0.1
    ticks=$(cpu_ticks "$pid")
    if [ "$ticks" = "$last" ]; then quiet=$((quiet + 1)); else quiet=0; fi
    last=$ticks
    if [ "$quiet" -ge 5 ]; then awk -v s="$start" -v n="$(now)" 'BEGIN {printf "%.1f", n - s - 0.5}'; return; fi
  done
  echo "busy"
}
start_server() {  # extra flags...
  rm -f "$work/ready"
  "$server_binary" --listen 127.0.0.1:0 --store "sqlite:$work/tessera-$RANDOM.db" --metrics-listen 127.0.0.1:0 \
    --ready-file "$work/ready" "$@" >"$work/server.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 200); do [ -s "$work/ready" ] && break; sleep 0.05; done
  address=$(sed -n 's/^grpc=//p' "$work/ready")
  metrics=$(sed -n 's/^metrics=//p' "$work/ready")
  [ -n "$address" ] || { echo "the server did not start" >&2; cat "$work/server.log" >&2; exit 1; }
}
stop_server() { kill -TERM "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; server_pid=; }
metric() { curl -s "http://$metrics/metrics" | awk -v name="$1" '$1 == name {print $2}'; }

cat >"$work/cube.obj" <<'EOF'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
EOF

# 1, 2: the issue's runaway request and pixel mode's floor.
start_server
"$cli" --server "$address" upload "$work/cube.obj" --name cube >/dev/null
rss_before=$(rss_mib "$server_pid")
pixel() {  # FOV PIXELS
  "$cli" --server "$address" tessellate meshes/cube --eye 0,0,5 --target 0,0,0 --up 0,1,0 --fov "$1" \
    --size 640x480 --pixel-accuracy "$2" -o "$work/pixel.glb" 2>&1
}
for fov in 1e-6 1e-9 1e-2; do
  t0=$(now)
  answer=$(pixel "$fov" 0.5 || true)
  elapsed=$(awk -v s="$t0" -v n="$(now)" 'BEGIN {printf "%.0f", 1000 * (n - s)}')
  echo "runaway fov $fov: answered in $elapsed ms: $(echo "$answer" | tr '\n' ' ' | cut -c1-300)"
  echo "  server CPU idle $(seconds_until_idle "$server_pid") s after; VmRSS $(rss_mib "$server_pid") MiB (before: $rss_before MiB)"
done
answer=$(pixel 1e-2 4 || true)
tolerance=$(echo "$answer" | sed -n 's/^tolerance *\([^ ]*\) .*/\1/p')
echo "pixel floor: fov 1e-2 at 4 px: $(echo "$answer" | grep -E '^triangles|^tolerance' | tr -s ' ' | tr '\n' ' ')"
awk -v t="$tolerance" 'BEGIN {d = 2 * sqrt(3); printf "  planned tolerance %.3g of the cube'"'"'s diagonal (floor 1e-06): %s\n", t / d, (t / d >= 1e-6 ? "at or above" : "BELOW")}'
stop_server

# 3: SIGTERM with every job slot running a long job and one queued, 2, 6 and 10 s after they
# started (preprocessing and planning, evaluation and triangulation, the UVs and the GLB).
for delay in 2 6 10; do
  start_server
  "$cli" --server "$address" upload "$models/bigguy.obj" --name bigguy >/dev/null
  slots=$(nproc)
  clients=()
  for _ in $(seq $((slots + 1))); do
    "$cli" --server "$address" tessellate meshes/bigguy --tolerance 1e-6 --relative -o /dev/null >/dev/null 2>&1 &
    clients+=($!)
  done
  for _ in $(seq 200); do
    [ "$(metric tessera_jobs_running)" = "$slots" ] && break
    sleep 0.1
  done
  sleep "$delay"
  running=$(metric tessera_jobs_running)
  t0=$(now)
  kill -TERM "$server_pid"
  wait "$server_pid" 2>/dev/null || true
  server_pid=
  echo "SIGTERM $delay s into $running long jobs (and one queued; drain 1 s, grace 4 s): gone in" \
       "$(awk -v s="$t0" -v n="$(now)" 'BEGIN {printf "%.2f", n - s}') s (bound: drain + 5 s = 6 s)"
  for pid in "${clients[@]}"; do wait "$pid" || true; done
done

# 4: a 8192 x 8192 RAW frame.
start_server
"$cli" --server "$address" upload "$models/bigguy.obj" --name bigguy >/dev/null
frame() {  # SIZE
  "$cli" --server "$address" render meshes/bigguy --eye 0.535,1.055,47.075 --target 0.535,1.055,0.075 --fov 40 \
    --size "$1" --format raw -o "$work/frame.raw" --timeout 600 >/dev/null
}
frame 64x64
caches_before=$(awk -v a="$(metric tessera_patch_cache_bytes)" -v b="$(metric tessera_cache_bytes)" 'BEGIN {print a + b}')
rest=$(rss_mib "$server_pid")
t0=$(now)
frame 8192x8192
elapsed=$(awk -v s="$t0" -v n="$(now)" 'BEGIN {printf "%.1f", n - s}')
after=$(rss_mib "$server_pid")
sleep 5
later=$(rss_mib "$server_pid")
caches=$(awk -v a="$(metric tessera_patch_cache_bytes)" -v b="$(metric tessera_cache_bytes)" -v c="$caches_before" \
  'BEGIN {printf "%.0f", (a + b - c) / 1048576}')
echo "8192x8192 RAW frame ($elapsed s): VmRSS at rest $rest MiB, after $after MiB, 5 s later $later MiB," \
     "peak $(hwm_mib "$server_pid") MiB; the caches grew by $caches MiB"
stop_server
