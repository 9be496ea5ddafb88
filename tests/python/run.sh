#!/usr/bin/env bash
# Installs the Python client (client/python) from a wheel into a scratch virtual environment, as
# a user would, and runs its tests against the real tessera-server (test_client.py).
# Usage: run.sh SOURCE_DIR BUILD_DIR SERVER_BINARY
set -euo pipefail
source_dir="$1" build_dir="$2" server="$3"
work="$build_dir/python-client"
"$source_dir/tests/python/install-client.sh" "$source_dir" "$work"
cd "$work"
TESSERA_SERVER_BINARY="$server" TESSERA_SAMPLE_OBJ="$source_dir/samples/rounded-box.obj" \
  "$work/venv/bin/python" "$source_dir/tests/python/test_client.py"
