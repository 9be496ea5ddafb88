#!/usr/bin/env bash
# Installs the Python client (client/python) from a wheel into a scratch virtual environment, as
# a user would, and runs its tests against the real tessera-server (test_client.py).
# Usage: run.sh SOURCE_DIR BUILD_DIR SERVER_BINARY
set -euo pipefail
source_dir="$1" build_dir="$2" server="$3"
work="$build_dir/python-client"
rm -rf "$work" && mkdir -p "$work/src/client"
# Built from a copy so that setuptools' build folders stay out of the checkout.
cp -r "$source_dir/client/python" "$work/src/client/" && cp -r "$source_dir/proto" "$work/src/"
# Debian's interpreter, where python3-grpcio, python3-protobuf and python3-numpy are installed.
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip wheel -q --no-build-isolation --no-deps --no-index -w "$work/dist" "$work/src/client/python"
"$work/venv/bin/python" -m pip install -q --no-deps --no-index "$work"/dist/tessera_client-*.whl
cd "$work"
TESSERA_SERVER_BINARY="$server" TESSERA_SAMPLE_OBJ="$source_dir/samples/rounded-box.obj" \
  "$work/venv/bin/python" "$source_dir/tests/python/test_client.py"
