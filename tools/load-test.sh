#!/usr/bin/env bash
# A fuller load test of tessera-server than tests/server/load_test.cpp, for the results file:
#
#   1. a concurrency sweep (default 1,2,4,8,16,32 clients, each on its own connection) with
#      `tessera bench` against a fresh server on SQLite: a mix dominated by small tessellations of
#      bigguy, plus get/list/info; the server's memory after each level;
#   2. the same 32 clients against the default admission limits, to show what they refuse;
#   3. the gRPC overhead for a result of about 100K triangles (bigguy at relative 6e-4): a remote
#      call end to end (the GLB streamed and its SHA-256 checked, as the CLI does) against
#      tessellate() + writeGlb() in-process on a prebuilt patch set (what the server does once the
#      mesh's patch set is cached): --pairs pairs of --runs runs each way (after 5 unmeasured
#      ones), back to back, median per side and pair, then the median over the pairs;
#   4. the cold mix (issue 46): `tessera bench --cold N`, N uploads per level of bigguy copies whose
#      content the server has not seen, each tessellated once (first-GLB and upload latency), at
#      each of --cold-tolerances on a fresh server (its peak VmHWM, and its patch-set cache misses
#      to show that it preprocessed each copy), then the same tolerance warm on that server.
#
#   tools/load-test.sh [--build-dir build] [--out bench/LOAD-RESULTS.md] [--requests 3000]
#                      [--levels 1,2,4,8,16,32] [--runs 11] [--pairs 10] [--keep-work]
#                      [--cold 32] [--cold-levels 1,2] [--cold-tolerances 1e-2,1e-3] [--cold-only]
#
# --cold-only runs part 4 alone and replaces the "Cold mix" section of --out, keeping the rest.
#
# Needs the targets tessera, tessera-server and tessera-inprocess-timing in the build folder.
# The host is shared with builds and other benchmarks: before each measurement the script waits
# (at most --quiet-wait seconds) for the machine to be idle, repeats a measurement (up to
# --attempts times) while other processes took more than --max-others of the CPU during it, keeps
# the least disturbed attempt, and reports for each measurement that share and the attempts. Everything runs on
# 127.0.0.1; every level is bounded in requests and time, and every call has a deadline.
set -euo pipefail
cd "$(dirname "$0")/.."

build=build
out=bench/LOAD-RESULTS.md
requests=3000
levels=1,2,4,8,16,32
runs=11
pairs=10
warmup=5
quiet_wait=300
attempts=3
max_others=0.10
keep_work=0
level_limit=300s
models=${TESSERA_MODELS_DIR:-$(pwd)/../shared/models}
mix=tessellate=8,get=1,list=1,info=1
small_request=(--tolerance 1e-2 --relative)
overhead_tolerance=6e-4
cold=32
cold_levels=1,2
cold_tolerances=1e-2,1e-3
cold_only=0

while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --requests) requests=$2; shift 2 ;;
    --levels) levels=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --pairs) pairs=$2; shift 2 ;;
    --quiet-wait) quiet_wait=$2; shift 2 ;;
    --attempts) attempts=$2; shift 2 ;;
    --max-others) max_others=$2; shift 2 ;;
    --keep-work) keep_work=1; shift ;;
    --cold) cold=$2; shift 2 ;;
    --cold-levels) cold_levels=$2; shift 2 ;;
    --cold-tolerances) cold_tolerances=$2; shift 2 ;;
    --cold-only) cold_only=1; shift ;;
    *) echo "usage: $0 [--build-dir DIR] [--out FILE] [--requests N] [--levels LIST]" \
            "[--runs N] [--pairs N] [--quiet-wait SECONDS] [--attempts N] [--max-others SHARE]" \
            "[--keep-work] [--cold N] [--cold-levels LIST] [--cold-tolerances LIST] [--cold-only]" >&2
       exit 2 ;;
  esac
done

cli=$build/client/tessera
server_binary=$build/server/tessera-server
inprocess=$build/tools/tessera-inprocess-timing
binaries=("$cli" "$server_binary")
[ "$cold_only" = 1 ] || binaries+=("$inprocess")
for binary in "${binaries[@]}"; do
  [ -x "$binary" ] || { echo "load-test: $binary is missing; build it with" \
    "cmake --build $build --target tessera tessera-server tessera-inprocess-timing" >&2; exit 2; }
done
[ -f "$models/bigguy.obj" ] || { echo "load-test: no $models/bigguy.obj (TESSERA_MODELS_DIR)" >&2; exit 2; }

work=$(mktemp -d /tmp/tessera-load-XXXXXX)
server_pid=""
stop_server() {
  if [ -n "$server_pid" ]; then
    kill -TERM "$server_pid" 2>/dev/null || true
    wait "$server_pid" 2>/dev/null || true
    server_pid=""
  fi
}
trap 'stop_server; if [ "$keep_work" = 1 ]; then log "raw results kept in $work"; else rm -rf "$work"; fi' EXIT
trap 'exit 130' INT TERM  # so that the EXIT trap stops the server
log() { echo "load-test: $*" >&2; }

# start_server NAME [FLAGS...]: a fresh server on SQLite in $work; sets server_pid and address.
start_server() {
  local name=$1; shift
  "$server_binary" --listen 127.0.0.1:0 --metrics-listen 127.0.0.1:0 \
    --ready-file "$work/$name.ready" --store "sqlite:$work/$name.db" "$@" \
    >"$work/$name.log" 2>&1 &
  server_pid=$!
  for _ in $(seq 1 300); do [ -f "$work/$name.ready" ] && break; sleep 0.1; done
  [ -f "$work/$name.ready" ] || { log "the server did not start:"; cat "$work/$name.log" >&2; exit 1; }
  address=$(sed -n 's/^grpc=//p' "$work/$name.ready")
  metrics_address=$(sed -n 's/^metrics=//p' "$work/$name.ready")
  "$cli" --server "$address" upload "$models/bigguy.obj" --name bigguy >/dev/null
}

# Clock ticks from /proc: the machine's busy and total time, one process's CPU time.
machine_ticks() { awk '/^cpu /{print $2+$3+$4+$7+$8+$9, $2+$3+$4+$5+$6+$7+$8+$9}' /proc/stat; }
process_ticks() { awk '{print $14+$15}' "/proc/$1/stat"; }
memory_kib() { awk -v f="$2:" '$1==f{print $2}' "/proc/$1/status"; }
# Waits until the machine has been at least 90% idle for 3 seconds in a row (bounded).
wait_quiet() {
  local calm=0 waited=0 before after
  before=$(machine_ticks)
  while [ "$calm" -lt 3 ] && [ "$waited" -lt "$quiet_wait" ]; do
    sleep 1; waited=$((waited + 1))
    after=$(machine_ticks)
    if awk -v b="$before" -v a="$after" 'BEGIN{split(b,x," ");split(a,y," ");
         exit !((y[2]-x[2])>0 && 1-(y[1]-x[1])/(y[2]-x[2]) >= 0.9)}'; then
      calm=$((calm + 1)); else calm=0; fi
    before=$after
  done
  [ "$calm" -ge 3 ] || log "the machine did not become quiet within $quiet_wait s; measuring anyway"
}

# measure LABEL COMMAND...: runs the command (stdout to $work/LABEL.out) and writes to
# $work/LABEL.row the share of the machine's CPU taken by processes other than the server and
# the command, the command's and the server's CPU seconds, and the wall time.
measure() {
  local label=$1; shift
  local TIMEFORMAT='%R %U %S' hz m0 m1 s0 s1 wall user system
  hz=$(getconf CLK_TCK)
  m0=$(machine_ticks); s0=$(process_ticks "$server_pid")
  { time "$@" >"$work/$label.out" 2>"$work/$label.err"; } 2>"$work/$label.time"
  s1=$(process_ticks "$server_pid"); m1=$(machine_ticks)
  read -r wall user system <"$work/$label.time"
  awk -v l="$label" -v hz="$hz" -v m0="$m0" -v m1="$m1" -v s0="$s0" -v s1="$s1" \
      -v wall="$wall" -v client="$(awk -v u="$user" -v s="$system" 'BEGIN{print u+s}')" \
      'BEGIN{split(m0,a," "); split(m1,b," ");
      busy=(b[1]-a[1])/hz; total=(b[2]-a[2])/hz; server=(s1-s0)/hz;
      others=busy-server-client; if (others<0) others=0;
      printf "%s\t%.4f\t%.2f\t%.2f\t%.2f\n", l, (total > 0 ? others / total : 0), client, server, wall}' \
      >"$work/$label.row"
  cat "$work/$label.row" >>"$work/all-attempts.tsv"
}

# measure_quietly LABEL COMMAND...: measure, after a quiet wait, up to $attempts times until other
# processes took at most $max_others of the CPU; keeps the least disturbed attempt's output
# ($work/LABEL.out, and $work/LABEL.json if the command writes one) and adds its row to
# $work/disturbance.tsv with the number of attempts. Every attempt stays in all-attempts.tsv.
measure_quietly() {
  local label=$1; shift
  local try best_share=2 share tries=0
  for try in $(seq 1 "$attempts"); do
    wait_quiet
    measure "$label" "$@"
    tries=$try
    share=$(cut -f 2 "$work/$label.row")
    if awk -v s="$share" -v b="$best_share" 'BEGIN{exit !(s < b)}'; then
      best_share=$share
      for ext in out json row; do
        [ -f "$work/$label.$ext" ] && cp "$work/$label.$ext" "$work/$label.best.$ext"
      done
    fi
    if awk -v s="$share" -v m="$max_others" 'BEGIN{exit !(s <= m)}'; then break; fi
    log "  $label: other processes took $share of the CPU; trying again"
  done
  for ext in out json row; do
    [ -f "$work/$label.best.$ext" ] && mv "$work/$label.best.$ext" "$work/$label.$ext"
  done
  printf "%s\t%s\n" "$(cat "$work/$label.row")" "$tries" >>"$work/disturbance.tsv"
}

bench() { "$cli" --server "$address" bench "$@"; }
# Preprocessings the server has started (its patch-set cache misses).
patch_misses() {
  curl -sf "http://$metrics_address/metrics" | awk '$1 == "tessera_patch_cache_misses_total" {print $2}'
}

# 4. The cold mix, on a fresh server per tolerance. Measured once, not repeated while disturbed:
# a repeat on the same server would meet its own copies (same ids), and on another would not be
# the same run; the others' share is reported instead.
cold_mix() {
  local tolerance
  IFS=, read -r -a cold_tolerance_list <<<"$cold_tolerances"
  for tolerance in "${cold_tolerance_list[@]}"; do
    log "cold mix: $cold new meshes per level, levels $cold_levels, relative $tolerance"
    start_server "cold-$tolerance"
    { echo "rss-before $(memory_kib "$server_pid" VmRSS)"
      echo "misses-before $(patch_misses)"; } >"$work/cold-$tolerance-server.txt"
    wait_quiet
    measure "cold-$tolerance" bench --cold "$cold" --mesh meshes/bigguy --tolerance "$tolerance" \
      --relative --concurrency "$cold_levels" --timeout 120s --json "$work/cold-$tolerance.json"
    printf "%s\t1\n" "$(cat "$work/cold-$tolerance.row")" >>"$work/disturbance.tsv"
    { echo "misses-after $(patch_misses)"
      echo "peak $(memory_kib "$server_pid" VmHWM)"
      echo "rss-after $(memory_kib "$server_pid" VmRSS)"; } >>"$work/cold-$tolerance-server.txt"
    # The warm reference: the source mesh at the same tolerance, its patch set cached.
    bench --mesh meshes/bigguy --tolerance "$tolerance" --relative --concurrency 1 \
      --requests "$cold" --warmup 5 --json "$work/cold-$tolerance-warm.json" >/dev/null
    stop_server
  done
}

if [ "$cold_only" = 1 ]; then
  [ -f "$out" ] || { log "--cold-only replaces a section of $out, which does not exist"; exit 2; }
else
  # 1. The sweep, one bench run per level so that the server's memory is read after each.
  log "sweep: levels $levels, $requests requests each (a fresh server on SQLite)"
  start_server sweep --max-queued-jobs 64
  # VmRSS, and its anonymous part (heap: caches and per-call buffers; the rest is file-backed,
  # mostly shared libraries).
  { echo "before $(memory_kib "$server_pid" VmRSS)"
    echo "anon-before $(memory_kib "$server_pid" RssAnon)"; } >"$work/sweep-memory.txt"
  IFS=, read -r -a level_list <<<"$levels"
  for c in "${level_list[@]}"; do
    log "  concurrency $c"
    measure_quietly "level-$c" bench --mix "$mix" --mesh meshes/bigguy "${small_request[@]}" \
      --concurrency "$c" --requests "$requests" --duration "$level_limit" --warmup 50 \
      --timeout 60s --json "$work/level-$c.json"
    { echo "$c $(memory_kib "$server_pid" VmRSS)"
      echo "anon-$c $(memory_kib "$server_pid" RssAnon)"; } >>"$work/sweep-memory.txt"
  done
  echo "peak $(memory_kib "$server_pid" VmHWM)" >>"$work/sweep-memory.txt"
  stop_server

  # 2. The default admission limits (running = cores, queue = 32 per running job) under 32 clients.
  log "32 clients against the default admission limits"
  start_server defaults
  measure_quietly defaults bench --mix "$mix" --mesh meshes/bigguy "${small_request[@]}" \
    --concurrency 32 --requests 1000 --duration "$level_limit" --warmup 0 --timeout 60s \
    --json "$work/defaults.json"
  stop_server

  # 3. The overhead, in pairs: in-process runs, then remote calls with and without the checksum,
  # back to back, so that both sides of a pair run under the same conditions (the host's load
  # drifts over minutes); a pair disturbed by other processes is repeated as a whole.
  overhead_pair() {
    local pair=$1
    "$inprocess" "$models/bigguy.obj" --relative "$overhead_tolerance" --runs "$runs" \
      --warmup "$warmup" --name bigguy >"$work/inprocess-$pair.json"
    bench --mesh meshes/bigguy --tolerance "$overhead_tolerance" --relative --concurrency 1 \
      --requests "$runs" --warmup "$warmup" --json "$work/remote-$pair.json"
    bench --mesh meshes/bigguy --tolerance "$overhead_tolerance" --relative --concurrency 1 \
      --requests "$runs" --warmup "$warmup" --no-verify --json "$work/unverified-$pair.json"
  }
  log "overhead: bigguy at relative $overhead_tolerance, $pairs pairs of $runs runs each way"
  start_server overhead
  bench --mesh meshes/bigguy --tolerance "$overhead_tolerance" --relative --concurrency 1 \
    --requests 5 >/dev/null  # fills the server's patch cache
  for pair in $(seq 1 "$pairs"); do
    measure_quietly "pair-$pair" overhead_pair "$pair"
  done
  stop_server
fi
cold_mix

# The results file.
{
  echo "cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -n 1)"
  echo "cores=$(nproc)"
  echo "memory_kib=$(awk '/^MemTotal:/{print $2}' /proc/meminfo)"
  echo "kernel=$(uname -r)"
  echo "date=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)$(git diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
  # An empty CMAKE_BUILD_TYPE means the project's default, Release (CMakeLists.txt).
  build_type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt" 2>/dev/null)
  echo "build_type=${build_type:-Release}"
} >"$work/machine.txt"
python3 tools/load_test/write_results.py "$work" "$out" \
  --levels "$levels" --requests "$requests" --mix "$mix" --runs "$runs" --pairs "$pairs" \
  --overhead-tolerance "$overhead_tolerance" --warmup "$warmup" --attempts "$attempts" \
  --max-others "$max_others" --cold "$cold" --cold-levels "$cold_levels" \
  --cold-tolerances "$cold_tolerances" $([ "$cold_only" = 1 ] && echo --cold-only)
log "wrote $out"
