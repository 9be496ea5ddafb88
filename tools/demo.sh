#!/usr/bin/env bash
# The main job on a bundled sample: what Tessera sees in the mesh, then a GLB within 1e-3 of
# the bounding-box diagonal of the exact limit surface.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x build/client/tessera ] || tools/build.sh
build/client/tessera inspect samples/rounded-box.obj
build/client/tessera tessellate samples/rounded-box.obj --tolerance 1e-3 --relative -o rounded-box.glb
