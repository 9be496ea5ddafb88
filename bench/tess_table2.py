#!/usr/bin/env python3
"""Runs the paper's Table 2 (BM_TessUniform_*, bench/tess_bench.cpp) case by case, and prints its
rows for bench/TESS-RESULTS.md.

The host is shared: a two-thread OpenMP or TBB loop slows down sharply when another process holds
one of the two cores. So each (model, p) case runs in its own process while holding the shared
benchmark lock (/tmp/tessera-bench.lock, the lock `flock` takes), after the machine has been at
least 90 % idle for 3 s (waiting at most 45 s), and is re-run, up to 3 attempts, while any of its
methods' median others_cpu is above 0.1. Every attempt's JSON is kept; a row is the latest
attempt with every others_cpu <= 0.1, else the least disturbed one.

    python3 bench/tess_table2.py run --binary build-t2/bench/tessera-bench --out DIR [--levels 64,32,16]
    python3 bench/tess_table2.py table --out DIR [--levels 64,32,16]
"""
import argparse
import fcntl
import glob
import json
import os
import re
import subprocess
import time

MODELS = ["bigguy", "monsterfrog", "armorguy", "t-rex", "car"]
OSD = ["OsdBfr", "OsdBfrPerFace", "OsdEval"]
STRICT_FLOOR = 80.1e9  # bytes/s: the best two-thread bandwidth measured on this host (bench/RESULTS.md)
MAX_OTHERS = 0.1


def cpu_times():
    with open("/proc/stat") as f:
        fields = [int(x) for x in f.readline().split()[1:9]]
    return sum(fields), fields[3] + fields[4]


def wait_quiet(limit=45):
    start, calm = time.time(), 0
    total, idle = cpu_times()
    while calm < 3 and time.time() - start < limit:
        time.sleep(1)
        total2, idle2 = cpu_times()
        calm = calm + 1 if (idle2 - idle) / max(1, total2 - total) >= 0.9 else 0
        total, idle = total2, idle2
    return time.time() - start


def medians(path):
    with open(path) as f:
        data = json.load(f)
    rows = {b["run_name"].split("/")[0].replace("BM_TessUniform_", ""): b
            for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
    return data, rows


def worst_others(rows):
    return max(b.get("others_cpu", 0) for b in rows.values())


def run_case(binary, out_dir, model, p, attempt):
    out = os.path.join(out_dir, f"{model}-{p}-{attempt}.json")
    command = [binary, f"--benchmark_filter=BM_TessUniform_.*/{model}/{p}/", "--benchmark_repetitions=3",
               "--benchmark_report_aggregates_only=true", f"--benchmark_out={out}", "--benchmark_out_format=json"]
    with open("/tmp/tessera-bench.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        waited = wait_quiet()
        subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
        fcntl.flock(lock, fcntl.LOCK_UN)
    worst = worst_others(medians(out)[1])
    print(f"{model}/{p} attempt {attempt}: waited {waited:.0f} s for quiet, worst others_cpu {worst:.3f}", flush=True)
    return worst


def attempts(out_dir, model, p):
    files = glob.glob(os.path.join(out_dir, f"{model}-{p}-*.json"))
    return sorted(files, key=lambda f: int(re.search(r"-(\d+)\.json$", f).group(1)))


def chosen(files):
    best = None
    for f in files:
        rows = medians(f)[1]
        worst = worst_others(rows)
        if worst <= MAX_OTHERS or best is None or (best[2] > MAX_OTHERS and worst < best[2]):
            best = (f, rows, worst)
    return best


def print_table(out_dir, p):
    print(f"\n#### p = {p}\n")
    print("| model | Tessera ms (plan + eval) | OsdBfr ms | OsdBfrPerFace ms | OsdEval ms | fastest OSD ÷ Tessera "
          "| Tessera ÷ floor (÷ strict floor) | floor ms (GB/s) | pieces | samples Tessera / OSD "
          "| others_cpu T / (Bfr / BfrPerFace / Eval) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for model in MODELS:
        files = attempts(out_dir, model, p)
        if not files:
            continue
        _, rows, _ = chosen(files)
        t = rows["Tessera"]
        osd = {k: rows[k]["real_time"] for k in OSD}
        fastest = min(osd, key=osd.get)
        strict_ms = t["bytes_written"] / STRICT_FLOOR * 1e3
        others = "/".join(f"{rows[k]['others_cpu']:.2f}" for k in OSD)
        print(f"| {model} | {t['real_time']:.2f} ({t['plan_ms']:.2f} + {t['eval_ms']:.2f}) | {osd['OsdBfr']:.1f} "
              f"| {osd['OsdBfrPerFace']:.1f} | {osd['OsdEval']:.1f} | **{osd[fastest] / t['real_time']:.1f}×** "
              f"({fastest[3:]}) | **{t['real_time'] / t['floor_ms']:.1f}** ({t['real_time'] / strict_ms:.1f}) "
              f"| {t['floor_ms']:.2f} ({t['floor_GB/s']:.0f}) | {t['pieces'] / 1e3:.1f}K "
              f"| {t['samples'] / 1e6:.2f}M / {rows['OsdBfr']['samples'] / 1e6:.2f}M | {t['others_cpu']:.2f} / {others} |")
    print("\nEvery attempt (T: Tessera ms; ratios as in the table):")
    for model in MODELS:
        for f in attempts(out_dir, model, p):
            data, rows = medians(f)
            t = rows["Tessera"]
            fastest = min(rows[k]["real_time"] for k in OSD)
            strict_ms = t["bytes_written"] / STRICT_FLOOR * 1e3
            print(f"- {os.path.basename(f)} ({data['context']['date']}): T {t['real_time']:.2f}, OSD ÷ T "
                  f"{fastest / t['real_time']:.1f}, T ÷ floor {t['real_time'] / t['floor_ms']:.2f} "
                  f"(strict {t['real_time'] / strict_ms:.2f}, floor {t['floor_GB/s']:.0f} GB/s), "
                  f"worst others_cpu {worst_others(rows):.2f}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("command", choices=["run", "table"])
    parser.add_argument("--binary", default="build-t2/bench/tessera-bench")
    parser.add_argument("--out", required=True)
    parser.add_argument("--levels", default="64,32,16")
    parser.add_argument("--models", default=",".join(MODELS))
    args = parser.parse_args()
    levels = [int(x) for x in args.levels.split(",")]
    if args.command == "table":
        for p in levels:
            print_table(args.out, p)
        return
    os.makedirs(args.out, exist_ok=True)
    for p in levels:
        for model in args.models.split(","):
            for attempt in range(1, 4):
                if run_case(args.binary, args.out, model, p, attempt) <= MAX_OTHERS:
                    break


if __name__ == "__main__":
    main()
