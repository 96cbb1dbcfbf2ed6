#!/usr/bin/python3
"""Plots of bench/shafts CSVs: per-scene results and the budget / direction-resolution sweep.

usage: /usr/bin/python3 bench/shafts/plot_shafts.py MAIN.csv SWEEP.csv OUT_DIR
"""
import os
import sys
from collections import defaultdict

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from bench_inputs import read_csv, require_dir, require_module  # noqa: E402

matplotlib = require_module("matplotlib", "python3-matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The columns of shafts_bench --csv that the plots read.
MAIN_COLUMNS = ["scene", "base", "workload", "steps_bvh", "steps_shafts", "ms_bvh", "ms_shafts"]
SWEEP_COLUMNS = MAIN_COLUMNS + ["budget_rel", "dir_res", "bvh_mib", "shaft_mib"]


def results(main, out):
    data = read_csv(main, MAIN_COLUMNS)
    if not data:
        sys.exit(f"{main}: no rows (shafts_bench --csv FILE writes them)")
    scenes = sorted({r["scene"] for r in data}, key=[r["scene"] for r in data].index)
    workloads = sorted({r["workload"] for r in data}, key=[r["workload"] for r in data].index)
    fig, axes = plt.subplots(2, 2, figsize=(12, 7), sharex="col")
    for col, base in enumerate(["binary", "wide"]):
        for row, (key, label) in enumerate([("steps", "traversal steps saved (%)"), ("speed", "speedup (x)")]):
            ax = axes[row][col]
            width = 0.8 / max(1, len(workloads))
            for k, w in enumerate(workloads):
                vals = []
                for s in scenes:
                    r = [x for x in data if x["scene"] == s and x["workload"] == w and x["base"] == base]
                    if not r:
                        vals.append(0)
                        continue
                    r = r[0]
                    if key == "steps":
                        vals.append(100 * (1 - float(r["steps_shafts"]) / float(r["steps_bvh"])))
                    else:
                        vals.append(float(r["ms_bvh"]) / float(r["ms_shafts"]))
                ax.bar([i + k * width for i in range(len(scenes))], vals, width, label=w)
            if key == "steps":
                ax.axhline(42, color="k", ls="--", lw=0.8, label="paper avg 42 %")
                ax.axhline(50, color="r", ls=":", lw=0.8, label="goal 50 %")
            else:
                ax.axhline(1.0, color="k", lw=0.8)
                ax.axhline(1 / 0.85, color="k", ls="--", lw=0.8, label="paper ~15 % less time")
                ax.axhline(1.25 if base == "binary" else 1.10, color="r", ls=":", lw=0.8, label="goal")
            ax.set_ylabel(label)
            ax.set_title(f"shafts{'-wide' if base == 'wide' else ''} vs plain {'Bvh2' if base == 'binary' else 'WideBvh'}")
            ax.set_xticks([i + 0.4 - width / 2 for i in range(len(scenes))])
            ax.set_xticklabels(scenes)
            if row == 0 and col == 0:
                ax.legend(fontsize=7, ncol=2)
            if row == 1 and col == 0:
                ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{out}/shafts_results.png", dpi=110)


def sweep(path, out):
    # The plot is of shafts over Bvh2: a sweep run with the default --base binary,wide also
    # holds shafts-wide rows, which would join the same lines.
    data = [r for r in read_csv(path, SWEEP_COLUMNS) if r["base"] == "binary"]
    if not data:
        sys.exit(f"{path}: no rows with base 'binary' (shafts_bench --sweep --base binary --csv FILE writes them)")
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    groups = defaultdict(list)
    for r in data:
        groups[r["workload"]].append(r)
    for w, rs in groups.items():
        budget = sorted([r for r in rs if r["dir_res"] == "4"], key=lambda r: float(r["shaft_mib"]))
        axes[0].plot([float(r["shaft_mib"]) / float(r["bvh_mib"]) for r in budget],
                     [100 * (1 - float(r["steps_shafts"]) / float(r["steps_bvh"])) for r in budget], "o-", label=w)
        axes[1].plot([float(r["shaft_mib"]) / float(r["bvh_mib"]) for r in budget],
                     [float(r["ms_bvh"]) / float(r["ms_shafts"]) for r in budget], "o-", label=w)
        dres = sorted([r for r in rs if r["budget_rel"] == "1"], key=lambda r: int(r["dir_res"]))
        axes[2].plot([int(r["dir_res"]) for r in dres],
                     [100 * (1 - float(r["steps_shafts"]) / float(r["steps_bvh"])) for r in dres], "o-", label=w)
    axes[0].set_xlabel("collection memory / BVH memory")
    axes[0].set_ylabel("traversal steps saved (%)")
    axes[1].set_xlabel("collection memory / BVH memory")
    axes[1].set_ylabel("speedup (x)")
    axes[2].set_xlabel("direction resolution d (6 d^2 cells), budget_rel = 1")
    axes[2].set_ylabel("traversal steps saved (%)")
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    scene = data[0]["scene"] if data else ""
    fig.suptitle(f"shafts over Bvh2, {scene}: memory budget and direction resolution sweep")
    fig.tight_layout()
    fig.savefig(f"{out}/shafts_sweep.png", dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__.strip().splitlines()[-1])
    require_dir(sys.argv[3])
    results(sys.argv[1], sys.argv[3])
    sweep(sys.argv[2], sys.argv[3])
