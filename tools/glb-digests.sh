#!/usr/bin/env bash
# SHA-256 of the GLBs `tessera tessellate` writes for a fixed set of cases, one line each: run it
# before and after a change that must not move a vertex (a refactoring, a faster loop) and diff
# the two listings. The set: the nine benchmark models at relative 1e-2 and 1e-3 (and four of them
# at 1e-4), the feature shapes (holes, n-gons, poles, semi-sharp and infinitely sharp creases,
# creases meeting boundaries, smooth triangles, valence 2, non-manifold), four pixel-accurate
# views, the quantized and meshopt encodings, and the uniform paths (η = 0, --level).
#   tools/glb-digests.sh [BUILD_DIR] [MODELS_DIR] > digests.txt
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
models="${2:-../shared/models}"
shapes="$models/opensubdiv-shapes"
cli="$build/client/tessera"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

digest() {  # NAME MODEL ARGS...
  local name="$1" model="$2"
  shift 2
  "$cli" tessellate "$model" "$@" -o "$out/$name.glb" >/dev/null
  echo "$(sha256sum <"$out/$name.glb" | cut -c1-64) $name"
}

for model in bigguy monsterfrog armorguy t-rex car; do
  for eps in 1e-2 1e-3; do digest "$model@$eps" "$models/$model.obj" --tolerance "$eps" --relative; done
done
for model in catmark_bishop catmark_rook catmark_cubes_semisharp catmark_torus_creases0; do
  for eps in 1e-2 1e-3; do digest "$model@$eps" "$shapes/$model.obj" --tolerance "$eps" --relative; done
done
for model in "$models/bigguy.obj" "$models/t-rex.obj" "$shapes/catmark_torus_creases0.obj" \
  "$shapes/catmark_cubes_semisharp.obj"; do
  digest "$(basename "$model" .obj)@1e-4" "$model" --tolerance 1e-4 --relative
done
for shape in catmark_hole_test1 catmark_hole_test4 catmark_nonquads catmark_fan catmark_pole8 \
  catmark_pole64 catmark_cube_creases2 catmark_dart_edgecorner catmark_tent_creases1 \
  catmark_inf_crease1 catmark_smoothtris1 catmark_val2_interior catmark_nonman_edges \
  catmark_chaikin2 catmark_gregory_test6; do
  digest "$shape@1e-3" "$shapes/$shape.obj" --tolerance 1e-3 --relative
done
view() {  # NAME MODEL PIXELS EYE TARGET
  digest "$1" "$2" --tolerance 1 --eye "$4" --target "$5" --up 0,1,0 --fov 40 --size 640x480 \
    --pixel-accuracy "$3"
}
view bigguy@view-front "$models/bigguy.obj" 0.5 0,5,40 0,5,0
view bigguy@view-close "$models/bigguy.obj" 1 12,8,10 0,5,0
view monsterfrog@view-side "$models/monsterfrog.obj" 0.5 40,5,0 0,0,0
view car@view-far "$models/car.obj" 2 0,20,120 0,0,0
for encoding in quantized meshopt; do
  digest "bigguy@1e-3-$encoding" "$models/bigguy.obj" --tolerance 1e-3 --relative --encoding "$encoding"
  digest "torus@1e-3-$encoding" "$shapes/catmark_torus_creases0.obj" --tolerance 1e-3 --relative \
    --encoding "$encoding"
done
digest "torus@eta0" "$shapes/catmark_torus_creases0.obj" --tolerance 1e-3 --relative --eta 0
digest "bigguy@eta0" "$models/bigguy.obj" --tolerance 1e-2 --relative --eta 0
digest "nonquads@eta0" "$shapes/catmark_nonquads.obj" --tolerance 1e-3 --relative --eta 0
digest "bigguy@level2" "$models/bigguy.obj" --tolerance 1 --level 2
digest "hole_test1@level4" "$shapes/catmark_hole_test1.obj" --tolerance 1 --level 4
