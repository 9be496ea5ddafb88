#!/usr/bin/env bash
# The memory soak of issues 16 and 46: a fresh tessera-server on SQLite (loopback,
# --memory-budget 3GiB, 256 MiB for each cache) under tools/soak's 32 clients, 8 of them hostile
# and 8 a cold storm (uploads of meshes the server has never seen, each tessellated once), for
# ten minutes; the report goes to bench/SOAK-RESULTS.md with the machine and the command. A short
# run of the same tool is the test Server.SoakTest.* (label "load").
#
#   tools/soak.sh [--build-dir build] [--out bench/SOAK-RESULTS.md] [--seconds 600] [--clients 32]
#                 [--hostile 8] [--cold 8] [--budget 3GiB]
set -euo pipefail
cd "$(dirname "$0")/.."

build=build
out=bench/SOAK-RESULTS.md
seconds=600
clients=32
hostile=8
cold=8
budget=3GiB
models=${TESSERA_MODELS_DIR:-$(pwd)/../shared/models}
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --clients) clients=$2; shift 2 ;;
    --hostile) hostile=$2; shift 2 ;;
    --cold) cold=$2; shift 2 ;;
    --budget) budget=$2; shift 2 ;;
    *) echo "usage: $0 [--build-dir DIR] [--out FILE] [--seconds N] [--clients N] [--hostile N] [--cold N]" \
            "[--budget SIZE]" >&2
       exit 2 ;;
  esac
done
for binary in "$build/server/tessera-server" "$build/tools/tessera-soak"; do
  [ -x "$binary" ] || { echo "soak: $binary is missing; build it with" \
    "cmake --build $build --target tessera-server tessera-soak" >&2; exit 2; }
done

work=$(mktemp -d /tmp/tessera-soak-XXXXXX)
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$work}
server_flags=(--listen 127.0.0.1:0 --store "sqlite:$work/tessera.db" --metrics-listen off
              --memory-budget "$budget" --cache-bytes 256MiB --patch-cache-bytes 256MiB)
"$build/server/tessera-server" "${server_flags[@]}" --ready-file "$work/ready" >"$work/server.log" 2>&1 &
server_pid=$!
trap 'kill -TERM $server_pid 2>/dev/null || true; wait $server_pid 2>/dev/null || true; rm -rf "$work"' EXIT
for _ in $(seq 100); do [ -s "$work/ready" ] && break; sleep 0.1; done
address=$(sed -n 's/^grpc=//p' "$work/ready")
[ -n "$address" ] || { echo "soak: the server did not start" >&2; cat "$work/server.log" >&2; exit 1; }

command=("$build/tools/tessera-soak" --server "$address" --server-pid "$server_pid" --models "$models"
         --clients "$clients" --hostile "$hostile" --cold "$cold" --seconds "$seconds")
started=$(date -u +%FT%TZ)
status=0
"${command[@]}" >"$work/report.md" || status=$?
{
  echo "# Memory soak: hostile, cold and normal requests from many clients"
  echo
  echo "\`tools/soak.sh --seconds $seconds --clients $clients --hostile $hostile --cold $cold --budget $budget\` at commit" \
       "$(git rev-parse --short HEAD), started $started."
  echo "Server: \`tessera-server ${server_flags[*]}\` (a fresh SQLite store, Vulkan on lavapipe where"
  echo "available). Machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) CPUs," \
       "$(awk '/MemTotal/ {printf "%.0f GiB", $2 / 1048576}' /proc/meminfo), $(. /etc/os-release; echo "$PRETTY_NAME")."
  echo
  echo "The hostile clients send, at random: every edge of bigguy a semi-sharp crease of sharpness 9.5"
  echo "(upload, and tessellation if accepted), armorguy at uniform level 40 and at relative 1e-5, an"
  echo "8192 x 8192 raw frame, a malformed upload, a NaN tolerance, bigguy at 1e-4 with a 50 ms deadline,"
  echo "and armorguy at 1e-3 abandoned after the first message. The normal clients send bigguy at"
  echo "1e-2 and 1e-3, GetMesh and 256 x 256 frames, and wait out the server's pushback"
  echo "(grpc-retry-pushback-ms) as a well-behaved client does; their meshes' patch sets are warm."
  echo "The cold storm's clients upload, one after another, copies of bigguy, monsterfrog, car, t-rex and"
  echo "armorguy, each vertex moved by a smooth displacement of at most 3e-3 of the diagonal that depends"
  echo "on the client and the copy (client/remote_cold_copies.h: new content, so the server preprocesses"
  echo "each), tessellate each once at relative 1e-3 (the first GLB), delete it and go on; its patch set"
  echo "stays in the cache, which the storm churns. A cold call may end OK or RESOURCE_EXHAUSTED with a"
  echo "message (after waiting out any pushback). tools/soak/soak_requests.h lists which codes each"
  echo "request may end with; any other counts as unexpected. Each hostile client's first request, and"
  echo "those it sends in the soak's last 4 s, are runaways: bigguy at relative 1e-5 (legitimate, ~1.5 s"
  echo "alone) with a 1 s deadline; after the clients end, one more alone with a 0.3 s deadline, and the"
  echo "report says how soon after it the server's CPU is idle."
  echo
  cat "$work/report.md"
} >"$out"
echo "soak: wrote $out (tessera-soak exit $status)"
exit $status
