#!/usr/bin/env python3
"""Turns tessera-bench's BM_TessGlb JSON into the tables of bench/ADAPTIVE-RESULTS.md.

    build/bench/tessera-bench --benchmark_filter="BM_TessGlb_(Tessera|OsdBfrOracle)" --benchmark_repetitions=3 \\
        --benchmark_report_aggregates_only=true --benchmark_out=glb.json --benchmark_out_format=json
    build/bench/tessera-bench --benchmark_filter=BM_TessGlb_Paired --benchmark_min_time=2 \\
        --benchmark_out=paired.json --benchmark_out_format=json
    python3 bench/adaptive_table.py glb.json [--measured other.json] [--paired paired.json] > table.md

Each case pairs BM_TessGlb_Tessera/<model>/<eps> with BM_TessGlb_OsdBfrOracle/<model>/<eps>
(medians when the run has repetitions). An oracle rate ">R" means no rate within the oracle tool's
triangle budget met ε: Bfr runs at R, so its triangles and time are lower bounds. --measured takes measured_over_eps from another run of
the same binary (the measurement is not timed, so it can come from a run with less repetition).
Ratios are Tessera over the oracle; the summed row divides the sums. Cases over the issue's
per-case limits (triangles 1.5x, time 2x) are marked. --paired adds BM_TessGlb_Paired's time ratio
(the median of ratios of alternated blocks, steadier on a VM whose speed drifts) as a column, and
the cases over 2x by it. "round trip ns" is bench/machine_load.h's core-to-core round trip when
each run started (Tessera/Bfr; the paired run's before/after its blocks): ~90 ns or ~400 ns on
the 2-core VM, whose two placements time multi-phase work differently.
"""
import argparse
import json
import sys

TRIANGLE_LIMIT = 1.5
TIME_LIMIT = 2.0


def load(path):
    with open(path) as f:
        data = json.load(f)
    rows = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        name = b["run_name"] if "run_name" in b else b["name"]
        parts = name.split("/")
        if len(parts) < 3 or not parts[0].startswith("BM_TessGlb_"):
            continue
        kind, model, eps = parts[0][len("BM_TessGlb_"):], parts[1], parts[2]
        rows[(kind, model, eps)] = b
    return data.get("context", {}), rows


def paired_ratios(path):
    with open(path) as f:
        data = json.load(f)
    ratios = {}
    for b in data["benchmarks"]:
        parts = b.get("run_name", b["name"]).split("/")
        if len(parts) >= 3 and parts[0] == "BM_TessGlb_Paired" and "time_ratio" in b:
            trips = (b.get("core_round_trip_ns", 0), b.get("core_round_trip_after_ns", 0))
            ratios[(parts[1], parts[2])] = (b["time_ratio"], trips)
    return ratios


def trip_cell(*values):
    """Core-to-core round trips in ns (machine_load.h), '-' where a run did not record one."""
    return "/".join(f"{v:.0f}" if v > 0 else "-" for v in values)


def milliseconds(b):
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]
    return b["real_time"] * scale


def mark(ratio, limit):
    return f"**{ratio:.2f}**" if ratio > limit else f"{ratio:.2f}"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("json")
    parser.add_argument("--measured", help="a run whose measured_over_eps to use")
    parser.add_argument("--paired", help="a BM_TessGlb_Paired run whose time ratios to add")
    args = parser.parse_args()
    context, rows = load(args.json)
    paired = paired_ratios(args.paired) if args.paired else {}
    measured = load(args.measured)[1] if args.measured else rows
    cases = []
    for (kind, model, eps) in rows:
        if kind == "Tessera" and ("OsdBfrOracle", model, eps) in rows:
            cases.append((model, eps))
    order = []
    for (kind, model, eps) in rows:
        if model not in order:
            order.append(model)
    cases.sort(key=lambda c: (order.index(c[0]), -float(c[1])))

    print(f"Machine: {context.get('host_name', '?')}, {context.get('num_cpus', '?')} CPUs at "
          f"{context.get('mhz_per_cpu', '?')} MHz; run {context.get('date', '?')}.\n")
    paired_head = " paired time ratio | paired round trip ns |" if paired else ""
    print("| model | ε | Tessera triangles | oracle rate | oracle triangles | triangles ratio | "
          f"Tessera ms | Bfr ms | time ratio | round trip ns |{paired_head} measured / ε | bound / ε | others_cpu |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|" + ("---:|---:|" if paired else "") + "---:|---:|---:|")
    sums = [0.0, 0.0, 0.0, 0.0]
    over = []
    paired_over = []
    measures = []
    for model, eps in cases:
        t = rows[("Tessera", model, eps)]
        o = rows[("OsdBfrOracle", model, eps)]
        m = measured.get(("Tessera", model, eps), t)
        tri, otri = t["triangles"], o["triangles"]
        ms, oms = milliseconds(t), milliseconds(o)
        tri_ratio, time_ratio = tri / otri, ms / oms
        measure = m.get("measured_over_eps", -1)
        if measure >= 0:
            measures.append(measure)
        sums = [sums[0] + tri, sums[1] + otri, sums[2] + ms, sums[3] + oms]
        if tri_ratio > TRIANGLE_LIMIT or time_ratio > TIME_LIMIT:
            over.append(f"{model} {eps}")
        busy = max(t.get("others_cpu", 0), o.get("others_cpu", 0))
        beyond = ">" if o.get("oracle_beyond", 0) else ""
        paired_cell = ""
        if paired:
            ratio, trips = paired.get((model, eps), (None, (0, 0)))
            paired_cell = (f" {mark(ratio, TIME_LIMIT)} | {trip_cell(*trips)} |" if ratio is not None else " | |")
            if ratio is not None and ratio > TIME_LIMIT:
                paired_over.append(f"{model} {eps}")
        trips = trip_cell(t.get("core_round_trip_ns", 0), o.get("core_round_trip_ns", 0))
        print(f"| {model} | {eps} | {tri:,.0f} | {beyond}{o['rate']:.0f} | {beyond}{otri:,.0f} | "
              f"{mark(tri_ratio, TRIANGLE_LIMIT)} | {ms:.2f} | {oms:.2f} | {mark(time_ratio, TIME_LIMIT)} | {trips} |"
              f"{paired_cell} {measure:.2f} | {t['bound_over_eps']:.2f} | {busy:.2f} |")
    print(f"| **sum** | | {sums[0]:,.0f} | | {sums[1]:,.0f} | **{sums[0] / sums[1]:.2f}** | "
          f"{sums[2]:.1f} | {sums[3]:.1f} | **{sums[2] / sums[3]:.2f}** | |" + (" | |" if paired else "") + " | | |")
    if measures:
        print(f"\nMeasured error / ε: mean {sum(measures) / len(measures):.2f}, "
              f"max {max(measures):.2f} over {len(measures)} cases.")
    print(f"\nCases over a per-case limit (triangles > {TRIANGLE_LIMIT}x or time > {TIME_LIMIT}x): "
          f"{', '.join(over) if over else 'none'}.")
    if paired:
        print(f"\nCases over {TIME_LIMIT}x by the paired time ratio: "
              f"{', '.join(paired_over) if paired_over else 'none'}.")


if __name__ == "__main__":
    sys.exit(main())
