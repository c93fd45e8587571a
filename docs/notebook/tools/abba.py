"""Two `multirate` binaries' `bench` in the order A B B A, each row the mean of its two runs.

Usage: python3 docs/notebook/tools/abba.py OLD_BINARY NEW_BINARY OUT_DIR BENCH_ARGUMENTS...
(without --out). Sets GALLIVM_PERF=nopt, or the value of ABBA_GALLIVM_PERF where that is set (empty:
llvmpipe's default, LLVM's optimisation passes on). Rows of the cost model ("auto", guarded) are
matched as such, whatever area each build's model gives. Prints a markdown table on stdout.
"""
import csv, subprocess, sys, os, statistics, tempfile
old, new, out = sys.argv[1], sys.argv[2], sys.argv[3]
args = sys.argv[4:]
env = dict(os.environ, GALLIVM_PERF=os.environ.get("ABBA_GALLIVM_PERF", "nopt"))
if not env["GALLIVM_PERF"]:
    del env["GALLIVM_PERF"]
runs = {}
for i, (name, binary) in enumerate([("old", old), ("new", new), ("new", new), ("old", old)]):
    d = f"{out}/run{i}_{name}"
    subprocess.run([binary, "bench", *args, "--out", d], env=env, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(f"{d}/bench.csv") as f:
        for row in csv.DictReader(f):
            guarded = row.get("frames_drawn_as_pixel", "NA") not in ("NA", "")
            area = "auto" if guarded else row.get("min_estimated_area", "")
            key = (row["scene"], row["width"], row["mode"], row["n_max"], area)
            runs.setdefault((name, key), []).append(row)
keys = sorted({k for (_, k) in runs}, key=lambda k: (k[0], k[1], k[2]))
cols = ["gpu_ms_median", "min_estimated_area", "frames_drawn_as_pixel", "pre_pass_ms_median", "cull_ms_median", "range_ms_median", "estimate_ms_median", "refine_ms_median", "patches_ms_median", "saving_share", "evaluations", "pixels_over_epsilon"]
def avg(rows, c):
    vals = [float(r[c]) for r in rows if c in r and r[c] not in ("NA", "")]
    return statistics.mean(vals) if vals else float("nan")
print("| scene | mode | build | " + " | ".join(cols) + " |")
for k in keys:
    for name in ("old", "new"):
        rows = runs.get((name, k), [])
        area = f" area {k[4]}" if k[4] not in ("", "NA") else ""
        print(f"| {k[0]} {k[1]} | {k[2]} n_max {k[3]}{area} | {name} | " + " | ".join(f"{avg(rows, c):.3f}" for c in cols) + " |")
