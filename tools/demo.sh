#!/usr/bin/env bash
# The main job: start tessera-server on the embedded store (SQLite in a scratch folder, loopback,
# a free port), then a round trip with the CLI: upload the bundled sample, fetch a GLB within
# 1e-3 of the bounding-box diagonal of its exact limit surface and a pixel-accurate PNG frame.
# Outputs land in ./demo-output/. Installs what is missing and builds first (README's first command).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
tools/build.sh

out="demo-output"
mkdir -p "$out"
work="$(mktemp -d)"
server_pid=""
cleanup() {
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null && wait "$server_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

build/server/tessera-server --listen 127.0.0.1:0 --store "sqlite:$work/tessera.db" \
  --metrics-listen 127.0.0.1:0 --ready-file "$work/ready" --log-level warn &
server_pid=$!
for _ in $(seq 1 100); do [ -f "$work/ready" ] && break; sleep 0.1; done
[ -f "$work/ready" ] || { echo "tessera-server did not start" >&2; exit 1; }
address="$(sed -n 's/^grpc=//p' "$work/ready")"
echo "tessera-server listening on $address"

cli() { build/client/tessera --server "$address" "$@"; }
cli info
cli upload samples/rounded-box.obj --name rounded-box
cli list
cli tessellate meshes/rounded-box --tolerance 1e-3 --relative -o "$out/rounded-box.glb"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/tessera-xdg}"
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
cli render meshes/rounded-box --eye 3,2.5,4 --target 0,0,0 --size 640x480 -o "$out/rounded-box.png"
echo "demo: wrote $out/rounded-box.glb and $out/rounded-box.png"
