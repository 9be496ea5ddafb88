#!/usr/bin/env python3
"""Prints the Fig. 5 tables of bench/TESS-RESULTS.md (section (c)) from a tessera-bench JSON file
of the BM_TessEtaRings and BM_TessEta cases (medians of repetitions):

    tessera-bench --benchmark_filter='BM_TessEta' --benchmark_repetitions=3 \\
        --benchmark_report_aggregates_only=true --benchmark_out=fig5.json --benchmark_out_format=json
    python3 bench/fig5_table.py fig5.json

Times are relative to η = 0, the paper's single-phase baseline, as in the paper's figure.
"""
import json
import sys

MODELS = ["bigguy", "monsterfrog", "armorguy", "t-rex", "car"]
ETAS = list(range(10))  # η = k / 10


def medians(path):
    with open(path) as f:
        data = json.load(f)
    rows = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        kind, model, eta = b["run_name"].split("/")[:3]
        rows[(kind, model, int(eta))] = b
    return rows


def table(rows, kind, title):
    print(f"#### {title}: time ÷ time at η = 0 (triangles)\n")
    header = " | ".join(f"η = {k / 10:g}" for k in ETAS)
    print(f"| model | ms at η = 0 | {header} | fastest η | others_cpu max |")
    print("|---|---|" + "---|" * len(ETAS) + "---|---|")
    depths = []
    for model in MODELS:
        cases = [rows.get((kind, model, k)) for k in ETAS]
        if any(c is None for c in cases):
            continue
        base = cases[0]["real_time"]
        cells = [f"{c['real_time'] / base:.2f} ({c['triangles'] / 1e3:.1f}K)" for c in cases]
        fastest = min(ETAS, key=lambda k: cases[k]["real_time"])
        others = max(c.get("others_cpu", 0) for c in cases)
        print(f"| {model} | {base:.1f} | " + " | ".join(cells) + f" | {fastest / 10:g} | {others:.2f} |")
        depths.append(f"{model} " + " ".join(f"{c['avg_depth']:.2f}" for c in cases))
    print("\nAverage FAS depth per η (0 … 0.9): " + "; ".join(depths) + "\n")


def main():
    rows = medians(sys.argv[1])
    table(rows, "BM_TessEtaRings", "Fig. 5, singularities only")
    table(rows, "BM_TessEta", "Fig. 5, whole model")


if __name__ == "__main__":
    main()
