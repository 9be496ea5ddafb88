#!/usr/bin/env python3
"""Turns tessera-bench JSON (--benchmark_format=json) into the Markdown tables of RESULTS.md.

    python3 bench/results_table.py [--stat=median|min] [--bandwidth=GB/s] run.json [sweep.json ...]

Every figure comes from the JSON: the median (or min) aggregate when the run had repetitions,
else the single run. Targets checked (issue): CER FAS >= 5x faster than OpenSubdiv, and <= 2x the floor.
"""
import json
import re
import sys
from collections import defaultdict

OSD_TARGET = 5.0
FLOOR_TARGET = 2.0


def load(paths):
    runs, contexts = [], []
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        contexts.append(data["context"])
        runs.extend(data["benchmarks"])
    return runs, contexts


def pick(runs, stat):
    """name -> run: the `stat` aggregate (median or min) when the run had repetitions, else the
    single run."""
    chosen = {}
    for run in runs:
        name = run["run_name"]
        if run.get("error_occurred"):
            chosen.setdefault(name, run)
        elif run.get("run_type") == "aggregate":
            if run.get("aggregate_name") == stat:
                chosen[name] = run
        elif name not in chosen:
            chosen[name] = run
    return chosen


def ms(run):
    scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[run["time_unit"]]
    return run["real_time"] * scale


def fmt(value, digits=2):
    return "—" if value is None else f"{value:.{digits}f}"


KINDS = ("BM_Fas_Cer", "BM_Fas_OsdStencil", "BM_Fas_OsdStencilBuild")


def cases_of(chosen):
    cases = defaultdict(dict)
    pattern = re.compile(r"^(" + "|".join(KINDS) + r")/(\d+)/(\d+)/")
    for name, run in chosen.items():
        m = pattern.match(name)
        if m:
            cases[(int(m.group(2)), int(m.group(3)))][m.group(1)] = run
    return cases


def bytes_of(c):
    return next((run["bytes_written"] for run in c.values() if "bytes_written" in run), None)


def adjacent_floor(c, kind):
    """The floor measured on `kind`'s own output buffer right after its iterations."""
    run = c.get(kind)
    return run.get("floor_ms") if run else None


def best_bandwidth(cases):
    """Bytes per ms of the fastest write-floor measurement anywhere in the run."""
    best = 0.0
    for c in cases.values():
        for run in c.values():
            for key in ("floor_ms", "floor_best_ms"):
                if key in run and run[key] > 0:
                    best = max(best, run["bytes_written"] / run[key])
    return best


def timed(c, kind):
    run = c.get(kind)
    return None if run is None or run.get("error_occurred") else ms(run)


def table1(chosen, reference_gbps=None):
    cases = cases_of(chosen)
    if not cases:
        return []
    header = ["n", "depth", "CER ms", "OSD ms", "OSD build ms", "floor ms", "OSD/CER", "CER/floor",
              "CER/adjacent floor", "adjacent GB/s", "others_cpu"]
    bandwidth = reference_gbps * 1e6 if reference_gbps else best_bandwidth(cases)
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    met_osd = met_floor = total = 0
    ratios = defaultdict(list)
    for (n, d) in sorted(cases):
        c = cases[(n, d)]
        cer, osd, build = timed(c, "BM_Fas_Cer"), timed(c, "BM_Fas_OsdStencil"), timed(c, "BM_Fas_OsdStencilBuild")
        floor = bytes_of(c) / bandwidth if bandwidth else None
        adjacent = adjacent_floor(c, "BM_Fas_Cer")
        ratio_osd = osd / cer if cer and osd else None
        ratio_floor = cer / floor if cer and floor else None
        ratio_adjacent = cer / adjacent if cer and adjacent else None
        for key, value in (("OSD/CER", ratio_osd), ("CER/floor", ratio_floor),
                           ("CER/adjacent floor", ratio_adjacent)):
            if value is not None:
                ratios[key].append(value)
        if ratio_osd is not None and ratio_floor is not None:
            total += 1
            met_osd += ratio_osd >= OSD_TARGET
            met_floor += ratio_floor <= FLOOR_TARGET
        others = max(run.get("others_cpu", 0.0) for run in c.values())
        lines.append("| " + " | ".join([str(n), str(d), fmt(cer), fmt(osd, 1), fmt(build, 1), fmt(floor),
                                        fmt(ratio_osd, 1), fmt(ratio_floor),
                                        fmt(ratio_adjacent),
                                        fmt(bytes_of(c) / adjacent / 1e6 if adjacent else None, 1),
                                        fmt(others)]) + " |")
    lines.append("")
    source = "the bandwidth given with --bandwidth" if reference_gbps else "the best write bandwidth measured in the run"
    lines.append(f"Floor: bytes / {source}, {bandwidth / 1e6:.1f} GB/s.")
    lines.append(f"OSD/CER >= {OSD_TARGET:g}: met in {met_osd} of {total} cases. "
                 f"CER/floor <= {FLOOR_TARGET:g}: met in {met_floor} of {total} cases.")
    lines.append("Ranges: " + "; ".join(f"{key} {fmt(min(values))}–{fmt(max(values))}"
                                        for key, values in ratios.items()) + ".")
    return lines


def kernel_table(chosen):
    """BM_CerKernel: core's FAS kernel forced to AVX2 (0) or AVX-512 (1), same workload."""
    pattern = re.compile(r"^BM_CerKernel/(\d+)/(\d+)/(\d)/")
    cells = defaultdict(dict)
    for name, run in chosen.items():
        m = pattern.match(name)
        if m and not run.get("error_occurred"):
            cells[(int(m.group(1)), int(m.group(2)))][int(m.group(3))] = run
    if not cells:
        return []
    lines = ["| n | depth | AVX2 ms | AVX-512 ms | AVX2/AVX-512 | AVX2/adjacent floor | "
             "AVX-512/adjacent floor |", "|---|---|---|---|---|---|---|"]
    faster = total = 0
    for (n, d) in sorted(cells):
        narrow, wide = cells[(n, d)].get(0), cells[(n, d)].get(1)
        a, b = (ms(narrow) if narrow else None), (ms(wide) if wide else None)
        if a and b:
            total += 1
            faster += b < a
        lines.append("| " + " | ".join([str(n), str(d), fmt(a), fmt(b),
                                        fmt(a / b if a and b else None),
                                        fmt(narrow.get("x_floor") if narrow else None),
                                        fmt(wide.get("x_floor") if wide else None)]) + " |")
    lines.append("")
    lines.append(f"AVX-512 faster than AVX2 in {faster} of {total} cases.")
    return lines


def floor_table(chosen):
    rows = [(name, run) for name, run in chosen.items() if name.startswith("BM_WriteFloor/")]
    if not rows:
        return []
    lines = ["| write | ms per GiB | GB/s (mean) | GB/s (best iteration) | others_cpu |",
             "|---|---|---|---|---|"]
    for name, run in sorted(rows):
        label = name.replace("BM_WriteFloor/", "").replace("/manual_time", "")
        lines.append(f"| {label} | {fmt(ms(run))} | {fmt(run.get('GB/s'), 1)} | "
                     f"{fmt(run.get('best_GB/s'), 1)} | {fmt(run.get('others_cpu'))} |")
    return lines


def sweep_table(chosen):
    pattern = re.compile(r"^BM_OsdChunkSweep/(\d+)/(\d+)/(\d+)/(\d)")
    cells = defaultdict(dict)
    busy = defaultdict(float)
    sizes = set()
    for name, run in chosen.items():
        m = pattern.match(name)
        if not m or run.get("error_occurred"):
            continue
        n, d, rings, balanced = map(int, m.groups())
        cells[(n, d, balanced)][rings] = ms(run)
        busy[(n, d, balanced)] = max(busy[(n, d, balanced)], run.get("others_cpu", 0.0))
        sizes.add(rings)
    if not cells:
        return []
    sizes = sorted(sizes)
    header = ["n", "depth", "order"] + [f"R={r}" for r in sizes] + ["others_cpu (max)"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for (n, d, balanced) in sorted(cells):
        row = cells[(n, d, balanced)]
        best = min(row.values())
        values = [("**" + fmt(row[r], 0) + "**" if row.get(r) == best else fmt(row.get(r), 0)) for r in sizes]
        order = "balanced" if balanced else "level"
        values.append(fmt(busy[(n, d, balanced)]))
        lines.append("| " + " | ".join([str(n), str(d), order] + values) + " |")
    return lines


def main(argv):
    stat = "median"
    reference_gbps = None  # --bandwidth=GB/s: judge the floor target against a fixed bandwidth
    while argv and argv[0].startswith("--"):
        key, value = argv[0].split("=", 1)
        if key == "--stat":
            stat = value
        elif key == "--bandwidth":
            reference_gbps = float(value)
        else:
            sys.exit(f"unknown option {key}")
        argv = argv[1:]
    runs, contexts = load(argv)
    chosen = pick(runs, stat)
    for context in contexts:
        print(f"<!-- {context.get('date')} {context.get('host_name')} cpus={context.get('num_cpus')} "
              f"mhz={context.get('mhz_per_cpu')} load_avg={context.get('load_avg')} stat={stat} -->")
    for section in (floor_table(chosen), table1(chosen, reference_gbps), kernel_table(chosen),
                    sweep_table(chosen)):
        if section:
            print("\n".join(section))
            print()


if __name__ == "__main__":
    main(sys.argv[1:])
