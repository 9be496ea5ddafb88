#!/usr/bin/env bash
# A throwaway PostgreSQL cluster for tessera-server's tests, on a free loopback port.
#
#   tools/pg-test-cluster.sh start    # prints a URL for TESSERA_TEST_POSTGRES_URL
#   tools/pg-test-cluster.sh url      # prints it again
#   tools/pg-test-cluster.sh stop     # stops the cluster and deletes its files
#
# Typical use:  export TESSERA_TEST_POSTGRES_URL=$(tools/pg-test-cluster.sh start)
#
# The cluster lives in $TESSERA_PG_TEST_DIR (default /tmp/tessera-pg-test), listens on 127.0.0.1
# only, trusts local connections and skips fsync: it holds test data, nothing else. PostgreSQL
# refuses to run as root, so under root (CI) the server runs as the `postgres` OS user. The
# PostgreSQL binaries are found through $PG_BIN, pg_config, or /usr/lib/postgresql/<newest>/bin.
# Progress goes to stderr; stdout carries only the URL.
set -euo pipefail

dir=${TESSERA_PG_TEST_DIR:-/tmp/tessera-pg-test}
data=$dir/data

log() { echo "pg-test-cluster: $*" >&2; }
die() { log "$*"; exit 1; }

find_bin() {
  if [ -n "${PG_BIN:-}" ] && [ -x "$PG_BIN/pg_ctl" ]; then echo "$PG_BIN"; return; fi
  local candidate
  candidate=$(find /usr/lib/postgresql -mindepth 2 -maxdepth 2 -name bin 2>/dev/null | sort -V | tail -n 1 || true)
  if [ -n "$candidate" ] && [ -x "$candidate/pg_ctl" ]; then echo "$candidate"; return; fi
  if command -v pg_config >/dev/null && [ -x "$(pg_config --bindir)/pg_ctl" ]; then
    pg_config --bindir; return
  fi
  if command -v pg_ctl >/dev/null; then dirname "$(command -v pg_ctl)"; return; fi
  die "no PostgreSQL server binaries (initdb, pg_ctl) found; install the postgresql package or set PG_BIN"
}

# The OS user that owns and runs the cluster.
cluster_user() {
  if [ "$(id -u)" -ne 0 ]; then id -un; return; fi
  getent passwd postgres >/dev/null || die "running as root needs a 'postgres' OS user (apt-get install postgresql creates it)"
  echo postgres
}

# Runs a command as the cluster user, from a directory that user can enter.
as_owner() {
  local user; user=$(cluster_user)
  if [ "$user" = "$(id -un)" ]; then
    (cd "$dir" && "$@")
  elif command -v runuser >/dev/null; then
    (cd "$dir" && runuser -u "$user" -- "$@")
  else
    (cd "$dir" && su -s /bin/sh "$user" -c "$(printf '%q ' "$@")")
  fi
}

port_in_use() {
  if command -v ss >/dev/null; then
    ss -Hltn "sport = :$1" 2>/dev/null | grep -q . && return 0 || return 1
  fi
  (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null
}

free_port() {
  local port
  for _ in $(seq 1 200); do
    port=$(( 20000 + (RANDOM * 32768 + RANDOM) % 40000 ))
    if ! port_in_use "$port"; then echo "$port"; return; fi
  done
  die "found no free port"
}

url() { echo "postgresql://postgres@127.0.0.1:$(cat "$dir/port")/postgres"; }

running() {
  [ -f "$dir/port" ] && [ -d "$data" ] && as_owner "$bin/pg_ctl" -D "$data" status >/dev/null 2>&1
}

start() {
  if running; then log "already running"; url; return; fi
  rm -rf "$dir"
  mkdir -p "$dir"
  chmod 700 "$dir"
  local user; user=$(cluster_user)
  [ "$user" = "$(id -un)" ] || chown "$user" "$dir"
  log "initdb in $data (as $user)"
  as_owner "$bin/initdb" -D "$data" -U postgres --auth=trust --encoding=UTF8 --locale=C \
    --no-sync >"$dir/initdb.log" 2>&1 || { cat "$dir/initdb.log" >&2; die "initdb failed"; }
  # A port can be taken between the check and the start: try a few.
  local attempt port
  for attempt in 1 2 3 4 5; do
    port=$(free_port)
    cat >"$data/postgresql.auto.conf" <<CONF
listen_addresses = '127.0.0.1'
port = $port
unix_socket_directories = '$dir'
max_connections = 300
fsync = off
full_page_writes = off
CONF
    [ "$user" = "$(id -un)" ] || chown "$user" "$data/postgresql.auto.conf"
    if as_owner "$bin/pg_ctl" -D "$data" -l "$dir/server.log" -w -t 60 start >/dev/null 2>&1; then
      echo "$port" >"$dir/port"
      log "running on 127.0.0.1:$port"
      url
      return
    fi
    log "start on port $port failed (attempt $attempt); server log:"
    tail -n 5 "$dir/server.log" >&2 || true
  done
  die "could not start PostgreSQL"
}

stop() {
  if [ -d "$data" ]; then
    as_owner "$bin/pg_ctl" -D "$data" -m fast -w stop >/dev/null 2>&1 || true
  fi
  rm -rf "$dir"
  log "stopped"
}

bin=$(find_bin)
case "${1:-}" in
  start) start ;;
  stop) stop ;;
  url) running || die "not running"; url ;;
  status) if running; then log "running"; url; else log "not running"; exit 1; fi ;;
  *) echo "usage: $0 start|stop|url|status" >&2; exit 2 ;;
esac
