#!/usr/bin/env python3
"""Turns tessera-bench's BM_Cold_* and BM_Edit_* JSON into the tables of bench/COLD-RESULTS.md.

    build/bench/tessera-bench --benchmark_filter='BM_(Cold|Edit)_' --benchmark_repetitions=1 \\
        --benchmark_format=json --benchmark_out=coldbench.json
    python3 bench/cold_table.py coldbench.json > tables.md

Each case pairs BM_<job>_Tessera/<model>/<eps> with BM_<job>_OsdBfrOracle/<model>/<eps> (medians
when the run has repetitions), for the jobs Cold and Edit (bench/cold_bench.cpp). Time ratios are
Tessera over Bfr; the summed row divides the sums over the cases both sides ran. Peak MiB is the
process's resident high-water mark above its size before the benchmark (setup included: for the
edit, Bfr's refiner, factory, surfaces and buffers, "kept MiB"). An oracle rate ">R" means no rate
within the oracle tool's triangle budget met eps: Bfr runs at R, so its time and memory are lower
bounds. A case one side skipped (an error, or left out of the run) is listed under the table.
"""
import argparse
import json
import sys

JOBS = ("Cold", "Edit")
SIDES = ("Tessera", "OsdBfrOracle")


def load(paths):
    """(job, side, model, eps) -> benchmark row, later files overriding earlier ones."""
    rows, context = {}, {}
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        context = context or data.get("context", {})
        for b in data["benchmarks"]:
            if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
                continue
            parts = (b["run_name"] if "run_name" in b else b["name"]).split("/")
            if len(parts) < 3 or not parts[0].startswith("BM_"):
                continue
            job_side = parts[0][len("BM_"):].split("_", 1)
            if len(job_side) != 2 or job_side[0] not in JOBS or job_side[1] not in SIDES:
                continue
            rows[(job_side[0], job_side[1], parts[1], parts[2])] = b
    return context, rows


def milliseconds(b):
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
    return b["real_time"] * scale


def ran(b):
    return b is not None and not b.get("error_occurred", False)


def case_order(rows):
    models, cases = [], set()
    for (_, _, model, eps) in rows:
        if model not in models:
            models.append(model)
        cases.add((model, eps))
    return sorted(cases, key=lambda c: (models.index(c[0]), -float(c[1])))


def table(job, rows):
    """The markdown table of one job; returns its lines and the cases one side lacks."""
    lines = [
        f"| model | ε | Tessera ms | of it preprocess ms | Bfr ms | Tessera / Bfr | Tessera triangles | "
        f"Bfr rate | Bfr triangles | Tessera peak MiB | Bfr peak MiB | Bfr kept MiB | others_cpu |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    sums = [0.0] * 4  # Tessera ms, Bfr ms, Tessera peak, Bfr peak over cases both sides ran
    missing = []
    for model, eps in case_order(rows):
        t = rows.get((job, "Tessera", model, eps))
        o = rows.get((job, "OsdBfrOracle", model, eps))
        if not ran(t) or not ran(o):
            why = lambda b, side: f"{side} {'not run' if b is None else b.get('error_message', 'error')}"
            missing.append(f"{model} {eps}: " + ", ".join(
                why(b, side) for b, side in ((t, "Tessera"), (o, "Bfr")) if not ran(b)))
            continue
        ms, oms = milliseconds(t), milliseconds(o)
        sums = [sums[0] + ms, sums[1] + oms, sums[2] + t["peak_mib"], sums[3] + o["peak_mib"]]
        beyond = ">" if o.get("oracle_beyond", 0) else ""
        busy = max(t.get("others_cpu", 0), o.get("others_cpu", 0))
        lines.append(
            f"| {model} | {eps} | {ms:.2f} | {t['preprocess_ms']:.2f} | {oms:.2f} | {ms / oms:.2f} | "
            f"{t['triangles']:,.0f} | {beyond}{o['rate']:.0f} | {beyond}{o['triangles']:,.0f} | "
            f"{t['peak_mib']:.1f} | {beyond}{o['peak_mib']:.1f} | {o['kept_mib']:.1f} | {busy:.2f} |")
    if sums[1] > 0:
        lines.append(f"| **sum** | | {sums[0]:.1f} | | {sums[1]:.1f} | **{sums[0] / sums[1]:.2f}** | | | | "
                     f"{sums[2]:.1f} | {sums[3]:.1f} | | |")
    return lines, missing


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("json", nargs="+", help="benchmark JSON; a later file's cases replace an earlier's")
    args = parser.parse_args()
    context, rows = load(args.json)
    print(f"Machine: {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs at "
          f"{context.get('mhz_per_cpu', '?')} MHz; run {context.get('date', '?')}.")
    for job in JOBS:
        lines, missing = table(job, rows)
        print(f"\n### {job}\n")
        print("\n".join(lines))
        if missing:
            print(f"\nNot in the {job} table: " + "; ".join(missing) + ".")


if __name__ == "__main__":
    sys.exit(main())
