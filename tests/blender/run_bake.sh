#!/usr/bin/env bash
# The Blender add-on's "Bake frame range" (client/blender) in real headless Blender against the
# real tessera-server: the Python client installed from its wheel, the add-on enabled from a
# scratch scripts folder, blender_bake.py run in Blender (a shape-key animation baked, one frame
# an object; a bake cancelled, one refused), then every baked frame's mesh measured against
# OpenSubdiv's limit surface of that frame's cage (tessera-limit-check).
# Usage: run_bake.sh SOURCE_DIR BUILD_DIR SERVER_BINARY LIMIT_CHECK_BINARY
set -euo pipefail
source_dir="$1" build_dir="$2" server="$3" check="$4"
source "$source_dir/tests/blender/blender_env.sh"
work="$build_dir/blender-bake"
blender_run "$source_dir" "$work" blender_bake.py "$server"
tolerance=$(cat "$work/out/tolerance")
for frame in $(cat "$work/out/frames"); do
  report=$("$check" --cage "$work/out/cage-$frame.obj" --mesh "$work/out/result-$frame.obj" --uv-interpolation boundaries)
  echo "frame $frame: $report"
  python3 - "$report" "$tolerance" "$frame" <<'PY'
import json, sys
report, tolerance, frame = json.loads(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
assert report["relative"] <= tolerance, f"frame {frame}: {report['relative']:.3g} of the diagonal, asked {tolerance:g}"
assert report["uvWorst"] < 1e-4, f"frame {frame}: UVs {report['uvWorst']:.3g} off OpenSubdiv's"
print(f"frame {frame} within {report['relative'] / tolerance:.2f} of the tolerance {tolerance:g}")
PY
done
# The check tells frames apart: frame 1's mesh is refused against frame 2's cage.
other=$("$check" --cage "$work/out/cage-2.obj" --mesh "$work/out/result-1.obj")
python3 - "$other" "$tolerance" <<'PY'
import json, sys
report, tolerance = json.loads(sys.argv[1]), float(sys.argv[2])
assert report["relative"] > 10 * tolerance, f"frame 1's mesh within {report['relative']:.3g} of frame 2's limit surface"
print(f"frame 1's mesh is {report['relative']:.3g} of the diagonal from frame 2's limit surface")
PY
