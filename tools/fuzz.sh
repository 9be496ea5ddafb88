#!/usr/bin/env bash
# Fuzzes the OBJ reader (readObj + requireManifold) with libFuzzer, ASan and UBSan for a bounded
# time: tools/fuzz.sh [SECONDS] (default 60). Builds in build-fuzz/ with clang-14, runs on a copy
# of tests/fuzz/corpus kept in build-fuzz/corpus (so inputs found by earlier runs are reused), and
# exits non-zero on a finding; the input that triggered it is left in build-fuzz/findings/.
set -euo pipefail

seconds="${1:-60}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]]; then
  echo "usage: $0 [SECONDS]" >&2
  exit 2
fi

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-fuzz"

CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -G Ninja \
  -DTESSERA_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j2 --target obj-reader-fuzz

mkdir -p "$build/corpus" "$build/findings"
for seed in "$root"/tests/fuzz/corpus/*; do
  # Keeps what is there; `cp -n` would do, but its exit status differs between coreutils versions.
  [[ -e "$build/corpus/$(basename "$seed")" ]] || cp "$seed" "$build/corpus/"
done

# New inputs go to the first folder only; the others are read-only seeds.
seeds=("$root/tests/data/malformed")
shapes="$root/../shared/models/opensubdiv-shapes"
if [[ -d "$shapes" ]]; then seeds+=("$shapes"); fi

exec "$build/tests/fuzz/obj-reader-fuzz" "$build/corpus" "${seeds[@]}" \
  -dict="$root/tests/fuzz/obj.dict" \
  -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=65536 -timeout=10 \
  -print_final_stats=1 -artifact_prefix="$build/findings/"
