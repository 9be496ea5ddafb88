#!/usr/bin/env bash
# A cheap request beside a cold storm (issue 47, bench/LOAD-RESULTS.md "A warm request beside a
# cold storm"): a fresh server on SQLite with its default limits, bigguy uploaded and tessellated
# once at relative 1e-2 (warm), then for --seconds:
#   - the storm: `tessera bench --cold` with 4 clients, each uploading a new copy of armorguy, t-rex
#     or car (content the server has never seen) and tessellating it once at relative 1e-3, so
#     every job preprocesses a large mesh;
#   - the probe: one client sending bigguy at relative 1e-2 back to back (`tessera bench --mix
#     tessellate=1`), started 5 s into the storm.
# Prints both reports, then the probe's p50/p99, the storm's first GLBs, the server's patch-cache
# misses and evictions and its peak resident memory. --server-binary runs another build's server
# with the same client (before/after comparisons).
#
#   tools/storm-probe.sh [--build-dir build] [--server-binary PATH] [--seconds 60] [--keep-work]
set -euo pipefail
cd "$(dirname "$0")/.."

build=build
server_binary=
seconds=60
keep_work=0
models=${TESSERA_MODELS_DIR:-$(pwd)/../shared/models}
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=$2; shift 2 ;;
    --server-binary) server_binary=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --keep-work) keep_work=1; shift ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
cli=$build/client/tessera
server_binary=${server_binary:-$build/server/tessera-server}
work=$(mktemp -d)
cleanup() {
  [ -n "${server_pid:-}" ] && kill "$server_pid" 2>/dev/null && wait "$server_pid" 2>/dev/null || true
  [ "$keep_work" = 1 ] && echo "work folder: $work" >&2 || rm -rf "$work"
}
trap cleanup EXIT

"$server_binary" --listen 127.0.0.1:0 --metrics-listen 127.0.0.1:0 --ready-file "$work/ready" \
  --store "sqlite:$work/store.db" >"$work/server.log" 2>&1 &
server_pid=$!
for _ in $(seq 1 300); do [ -f "$work/ready" ] && break; sleep 0.1; done
[ -f "$work/ready" ] || { cat "$work/server.log" >&2; exit 1; }
address=$(sed -n 's/^grpc=//p' "$work/ready")
metrics=$(sed -n 's/^metrics=//p' "$work/ready")
for model in bigguy armorguy t-rex car; do
  "$cli" --server "$address" upload "$models/$model.obj" --name "$model" >/dev/null
done
"$cli" --server "$address" tessellate meshes/bigguy --tolerance 1e-2 --relative -o "$work/warm.glb" >/dev/null

"$cli" --server "$address" bench --cold 10000 --mesh meshes/armorguy meshes/t-rex meshes/car \
  --tolerance 1e-3 --relative --concurrency 4 --duration "${seconds}s" --timeout 300s \
  --json "$work/storm.json" >"$work/storm.txt" 2>&1 &
storm=$!
sleep 5
"$cli" --server "$address" bench --mix tessellate=1 --mesh meshes/bigguy --tolerance 1e-2 --relative \
  --concurrency 1 --requests 1000000 --duration "$((seconds - 10))s" --timeout 120s \
  --json "$work/probe.json" >"$work/probe.txt" 2>&1
wait "$storm" || true

echo "## storm"; cat "$work/storm.txt"
echo "## probe"; cat "$work/probe.txt"
page=$(curl -s "http://$metrics/metrics")
series() { echo "$page" | awk -v s="$1" '$1==s{print $2}'; }
python3 - "$work/probe.json" "$work/storm.json" <<'EOF'
import json, sys
probe, storm = (json.load(open(p))["levels"][0] for p in sys.argv[1:3])
p = probe["latency_ms"]
print(f"probe: {p['count']} warm Tessellates of bigguy at 1e-2, p50 {p['p50']:.0f} ms, "
      f"p99 {p['p99']:.0f} ms, max {p['max']:.0f} ms, errors {probe['errors']}")
t = storm["operations"]["tessellate"]
print(f"storm: {t['ok']} cold first GLBs in {storm['seconds']:.0f} s, p50 {t['latency_ms']['p50']:.0f} ms, "
      f"errors {storm['errors']}")
EOF
echo "patch-cache misses $(series tessera_patch_cache_misses_total), evictions $(series tessera_patch_cache_evictions_total)," \
  "peak RSS $(awk '$1=="VmHWM:"{print int($2/1024)}' "/proc/$server_pid/status") MiB"
