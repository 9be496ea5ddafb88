#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite (README's second command, and
# what .ci/run calls): unit and end-to-end tests through ctest (the server's store tests also
# against a throwaway PostgreSQL cluster), then the OBJ reader's fuzzer for a bounded time
# (TESSERA_FUZZ_SECONDS, default 60).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/tessera-xdg}"
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
tools/build.sh
# Khronos glTF-Validator (npm) for the GLB tests; puppeteer-core (npm) for the web viewer's test.
(cd tests/gltf && npm ci --no-audit --no-fund --loglevel=error)
(cd tests/web && npm ci --no-audit --no-fund --loglevel=error)
# kubernetes-models (npm) for the offline validation of deploy/kubernetes.
(cd tests/deploy && npm ci --no-audit --no-fund --loglevel=error)

TESSERA_TEST_POSTGRES_URL="$(tools/pg-test-cluster.sh start)"
export TESSERA_TEST_POSTGRES_URL
trap 'tools/pg-test-cluster.sh stop >/dev/null 2>&1 || true' EXIT
ctest --test-dir build --output-on-failure -j2
tools/fuzz.sh "${TESSERA_FUZZ_SECONDS:-60}"
