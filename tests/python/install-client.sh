#!/usr/bin/env bash
# Builds the Python client's wheel (client/python; stubs from proto/ with the system protoc and
# grpc_python_plugin) and installs it into a scratch virtual environment on Debian's python3, as a
# user would. Usage: install-client.sh SOURCE_DIR WORK_DIR; the environment is WORK_DIR/venv.
set -euo pipefail
source_dir="$1" work="$2"
rm -rf "$work" && mkdir -p "$work/src/client"
# Built from a copy, which must come out of the build as it went in: setup.py keeps setuptools'
# build/ and egg-info out of the folder pip is pointed at (a user's checkout).
cp -r "$source_dir/client/python" "$work/src/client/" && cp -r "$source_dir/proto" "$work/src/"
find "$work/src/client/python" | sort > "$work/files-before"
# Debian's interpreter, where python3-grpcio, python3-protobuf and python3-numpy are installed.
/usr/bin/python3 -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip wheel -q --no-build-isolation --no-deps --no-index -w "$work/dist" "$work/src/client/python"
find "$work/src/client/python" | sort > "$work/files-after"
if ! diff "$work/files-before" "$work/files-after" > "$work/files-left"; then
  echo "building the client left files in its source folder:"; cat "$work/files-left"; exit 1
fi
"$work/venv/bin/python" -m pip install -q --no-deps --no-index "$work"/dist/tessera_client-*.whl
