#!/usr/bin/env bash
# The Blender add-on's live mode (client/blender) in real headless Blender against the real
# tessera-server: the Python client installed from its wheel, the add-on enabled from a scratch
# scripts folder as a user installs it, blender_live.py run in Blender (edits, frames and a
# viewport move, each checked as it arrives; round trips in WORK/out/live-round-trips.json), then
# the final mesh measured against OpenSubdiv's limit surface of the last cage sent, and the pixel
# mode's mesh against the bound the server proved for it (tessera-limit-check).
# Usage: run_live.sh SOURCE_DIR BUILD_DIR SERVER_BINARY LIMIT_CHECK_BINARY
set -euo pipefail
source_dir="$1" build_dir="$2" server="$3" check="$4"
source "$source_dir/tests/blender/blender_env.sh"
work="$build_dir/blender-live"
blender_run "$source_dir" "$work" blender_live.py "$server"
final=$("$check" --cage "$work/out/cage.obj" --mesh "$work/out/result.obj" \
  --uv-interpolation "$(cat "$work/out/uv-interpolation")")
pixel=$("$check" --cage "$work/out/pixel-cage.obj" --mesh "$work/out/pixel-result.obj" \
  --uv-interpolation "$(cat "$work/out/uv-interpolation")")
echo "final: $final"
echo "pixel mode: $pixel"
python3 - "$final" "$pixel" "$(cat "$work/out/tolerance")" "$(cat "$work/out/pixel-bound")" <<'PY'
import json, sys
final, pixel = json.loads(sys.argv[1]), json.loads(sys.argv[2])
tolerance, bound = float(sys.argv[3]), float(sys.argv[4])
assert final["relative"] <= tolerance, f"final mesh: {final['relative']:.3g} of the diagonal, asked {tolerance:g}"
assert final["uvWorst"] < 1e-4, f"final mesh: UVs {final['uvWorst']:.3g} off OpenSubdiv's"
distance = pixel["relative"] * pixel["diagonal"]
assert distance <= bound, f"pixel mode: {distance:.3g} from the limit surface, the server proved {bound:.3g}"
print(f"final mesh within {final['relative'] / tolerance:.2f} of the tolerance {tolerance:g}; "
      f"pixel mode's {distance:.3g} within the proven {bound:.3g}")
PY
