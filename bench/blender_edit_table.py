#!/usr/bin/env python3
"""Issue 48, item 6: an edit's round trip in the Blender add-on's live mode against Blender's own
Subdivision Surface modifier at the uniform level of equal error, in the same Blender process
(bench/blender_edit_bench.py runs in Blender; see there what is timed). For each model: the
Python client installed from its wheel and the add-on enabled as tests/blender/run_live.sh does,
Blender run on the model, then every mesh it wrote measured with tessera-limit-check against the
limit surface of the cage sent (Tessera's last result, and each level's evaluated mesh).

Blender's level L gives 2^L segments a cage edge, as OpenSubdiv's Bfr tessellation at rate 2^L;
the oracle rate R (bench/oracle_rates.csv: the smallest uniform rate within the tolerance) gives
L = ceil(log2 R). Levels L-1, L and L+1 (from 1) are timed unless --levels says otherwise; the
table marks which are within the tolerance as measured here (Blender's modifier evaluates the limit
surface approximately, its Quality setting, so its level L may measure above the tolerance where
Bfr's rate 2^L does not).

  python3 bench/blender_edit_table.py --build build --models ../shared/models \\
      --model bigguy --model armorguy --model t-rex --reps 7 --out build/blender-edit-bench
(Debian's /usr/bin/python3: under another interpreter's environment Blender's Python did not find
NumPy.)
"""
import argparse
import json
import math
import os
import subprocess
import sys
from pathlib import Path

SOURCE = Path(__file__).resolve().parent.parent


def oracle_level(model: str, tolerance: float) -> int:
    for line in (SOURCE / "bench" / "oracle_rates.csv").read_text().splitlines():
        fields = line.split(",")
        if fields[0] == model and not line.startswith("#") and math.isclose(float(fields[1]), tolerance):
            return max(1, math.ceil(math.log2(int(fields[2]))))
    raise SystemExit(f"bench/oracle_rates.csv has no {model} at {tolerance:g}")


def limit_check(check: Path, cage: Path, mesh: Path) -> dict:
    # The UV rule of the modifier's default (Keep Boundaries) as the add-on sends it; the UVs are
    # checked on Tessera's mesh only (the levels' meshes are written without them).
    result = subprocess.run([str(check), "--cage", str(cage), "--mesh", str(mesh), "--uv-interpolation", "boundaries"],
                            check=True, capture_output=True, text=True)
    return json.loads(result.stdout)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", type=Path, required=True)
    parser.add_argument("--models", type=Path, required=True, help="the folder of the models' OBJ files")
    parser.add_argument("--model", action="append", required=True)
    parser.add_argument("--tolerance", type=float, default=1e-3)
    parser.add_argument("--reps", type=int, default=7)
    parser.add_argument("--levels", action="append", default=[], help="MODEL=L1,L2 instead of the oracle's L-1,L")
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--skip-install", action="store_true", help="reuse OUT/client")
    args = parser.parse_args()
    build = args.build.resolve()
    out = args.out.resolve()
    server, check = build / "server" / "tessera-server", build / "tools" / "tessera-limit-check"
    client = out / "client"
    if not args.skip_install:
        subprocess.run([str(SOURCE / "tests" / "python" / "install-client.sh"), str(SOURCE), str(client)], check=True)
    addons = out / "scripts" / "addons"
    addons.mkdir(parents=True, exist_ok=True)
    link = addons / "tessera_subdiv"
    if not link.exists():
        link.symlink_to(SOURCE / "client" / "blender" / "tessera_subdiv")
    site = subprocess.run([str(client / "venv" / "bin" / "python"), "-c",
                           "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          check=True, capture_output=True, text=True).stdout.strip()
    chosen = dict(entry.split("=", 1) for entry in args.levels)
    environment = dict(os.environ, BLENDER_USER_SCRIPTS=str(out / "scripts"), PYTHONPATH=site)
    environment.setdefault("XDG_RUNTIME_DIR", str(out))
    rows = []
    for model in args.model:
        if model in chosen:
            levels = [int(x) for x in chosen[model].split(",")]
        else:
            level = oracle_level(model, args.tolerance)
            levels = [x for x in (level - 1, level, level + 1) if x >= 1]
        work = out / model
        work.mkdir(parents=True, exist_ok=True)
        subprocess.run(["blender", "-b", "--factory-startup", "--python-use-system-env", "--python-exit-code", "1",
                        "--python", str(SOURCE / "bench" / "blender_edit_bench.py"), "--",
                        str(work), str(server), str(args.models / f"{model}.obj"), repr(args.tolerance),
                        ",".join(map(str, levels)), str(args.reps)], check=True, env=environment)
        times = json.loads((work / "times.json").read_text())
        times["tessera_error"] = limit_check(check, work / "cage.obj", work / "tessera.obj")
        for level in levels:
            times["levels"][str(level)]["error"] = limit_check(check, work / "cage.obj", work / f"level-{level}.obj")
        (work / "results.json").write_text(json.dumps(times, indent=1))
        rows.append(times)
    print("| model | Tessera edit round trip (median) | its triangles | Blender level | modifier edit (median) | "
          "its quads | ratio | load average |")
    print("|---|---:|---:|---:|---:|---:|---:|---|")
    for t in rows:
        for level, entry in t["levels"].items():
            print(f"| {t['model']} | {1000 * t['tessera_median_s']:.0f} ms | {t['tessera_triangles']:,} | {level} | "
                  f"{1000 * entry['median_s']:.1f} ms | {entry['faces']:,} | "
                  f"{t['tessera_median_s'] / entry['median_s']:.2f}× | "
                  f"{t['load_average'][0]:.1f}–{t['load_average'][1]:.1f} |")
    # tessera-limit-check's two directions apart (bench/BLENDER-EDIT-RESULTS.md, "Measured error").
    print("\n| model | mesh | two-sided | mesh → limit (face) | limit → mesh |")
    print("|---|---|---:|---:|---:|")
    for t in rows:
        meshes = [("Tessera", t["tessera_error"])] + [(f"level {level}", e["error"]) for level, e in t["levels"].items()]
        for name, error in meshes:
            d = error["diagonal"]
            print(f"| {t['model']} | {name} | {error['relative']:.4g} | {error['meshToLimit'] / d:.4g} "
                  f"({error['meshToLimitFace']}) | {error['limitToMesh'] / d:.4g} |")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
