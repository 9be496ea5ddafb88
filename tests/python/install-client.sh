#!/usr/bin/env bash
# Builds the Python client's wheel (client/python; stubs from proto/ with the system protoc and
# grpc_python_plugin) and installs it into a scratch virtual environment on Debian's python3, as a
# user would. Usage: install-client.sh SOURCE_DIR WORK_DIR; the environment is WORK_DIR/venv.
set -euo pipefail
source_dir="$1" work="$2"
rm -rf "$work" && mkdir -p "$work/src/client"
# Built from a copy so that setuptools' build folders stay out of the checkout.
cp -r "$source_dir/client/python" "$work/src/client/" && cp -r "$source_dir/proto" "$work/src/"
# Debian's interpreter, where python3-grpcio, python3-protobuf and python3-numpy are installed.
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip wheel -q --no-build-isolation --no-deps --no-index -w "$work/dist" "$work/src/client/python"
"$work/venv/bin/python" -m pip install -q --no-deps --no-index "$work"/dist/tessera_client-*.whl
