#!/usr/bin/env bash
# The main job on a bundled sample: what Tessera sees in the mesh.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/client/tessera ] || tools/build.sh
build/client/tessera inspect samples/rounded-box.obj
