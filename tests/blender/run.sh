#!/usr/bin/env bash
# The Blender add-on (client/blender) in real headless Blender against the real tessera-server:
# the Python client installed from its wheel, the add-on enabled from a scratch scripts folder as
# a user installs it, blender_round_trip.py run in Blender, then what came back measured against
# OpenSubdiv's limit surface of the cage Blender sent (tessera-limit-check).
# Usage: run.sh SOURCE_DIR BUILD_DIR SERVER_BINARY LIMIT_CHECK_BINARY
set -euo pipefail
source_dir="$1" build_dir="$2" server="$3" check="$4"
source "$source_dir/tests/blender/blender_env.sh"
work="$build_dir/blender-addon"
blender_run "$source_dir" "$work" blender_round_trip.py "$server"
# Within the tolerance asked of OpenSubdiv's limit surface of the cage, UVs as OpenSubdiv's.
report=$("$check" --cage "$work/out/cage.obj" --mesh "$work/out/result.obj" \
  --uv-interpolation "$(cat "$work/out/uv-interpolation")")
echo "$report"
python3 - "$report" "$(cat "$work/out/tolerance")" <<'PY'
import json, sys
report, tolerance = json.loads(sys.argv[1]), float(sys.argv[2])
assert report["relative"] <= tolerance, f"measured {report['relative']:.3g} of the diagonal, asked {tolerance:g}"
assert report["uvCornersChecked"] > 100, "too few corners inside faces to check UVs"
assert report["uvWorst"] < 1e-4, f"UVs {report['uvWorst']:.3g} off OpenSubdiv's"
print("within", tolerance, "of the limit surface; UVs within", report["uvWorst"])
PY
