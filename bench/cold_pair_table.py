#!/usr/bin/env python3
"""Before and after of the cold and edit jobs (bench/cold_bench.cpp), from runs of two builds'
tessera-bench on the same machine in the same minutes: per case the median of each build's runs,
Bfr's median over all of them, the ratios, the triangles and the peak memory (largest of a build's
runs), and the sums. Markdown on stdout.

  bench/cold_pair_table.py --before old1.json old2.json --after new1.json new2.json
"""
import argparse
import json
import statistics


def load(path):
    cases = {}
    for b in json.load(open(path))["benchmarks"]:
        name = b["name"].split("/")
        cases[(name[0], name[1], name[2])] = b
    return cases


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--before", nargs="+", required=True)
    parser.add_argument("--after", nargs="+", required=True)
    args = parser.parse_args()
    before, after = [load(p) for p in args.before], [load(p) for p in args.after]
    print("| job | model | ε | before ms | after ms | after / before | Bfr ms | / Bfr before → after |"
          " triangles before → after | peak MiB before → after (Bfr) | others_cpu (max) |")
    print("|---|---|---|---:|---:|---:|---:|---|---|---|---:|")
    sums = {}
    for job in ["Cold", "Edit"]:
        for key in after[0]:
            if key[0] != f"BM_{job}_Tessera":
                continue
            bfr_key = (f"BM_{job}_OsdBfrOracle", key[1], key[2])
            old = statistics.median(r[key]["real_time"] for r in before)
            new = statistics.median(r[key]["real_time"] for r in after)
            bfr = statistics.median(r[bfr_key]["real_time"] for r in before + after)
            peak_old = max(r[key]["peak_mib"] for r in before)
            peak_new = max(r[key]["peak_mib"] for r in after)
            peak_bfr = max(r[bfr_key]["peak_mib"] for r in before + after)
            others = max(r[k]["others_cpu"] for r in before + after for k in (key, bfr_key))
            total = sums.setdefault(job.lower(), [0.0, 0.0, 0.0])
            total[0] += old
            total[1] += new
            total[2] += bfr
            print(f"| {job.lower()} | {key[1]} | {key[2]} | {old:.1f} | {new:.1f} | {new / old:.2f} | {bfr:.2f} |"
                  f" {old / bfr:.1f} → **{new / bfr:.1f}** | {int(before[0][key]['triangles']):,} →"
                  f" {int(after[0][key]['triangles']):,} | {peak_old:.1f} → {peak_new:.1f} ({peak_bfr:.1f}) |"
                  f" {others:.2f} |")
    print()
    for job, (old, new, bfr) in sums.items():
        print(f"- {job}, summed: before {old / 1000:.1f} s, after {new / 1000:.1f} s, Bfr {bfr / 1000:.1f} s:"
              f" {old / bfr:.2f}× → {new / bfr:.2f}× Bfr's")


if __name__ == "__main__":
    main()
