#!/usr/bin/python3
"""Plots of dacrt_bench's results (JSON) into docs/figures/dacrt/: the paper's figs. 8-10 beside ours.

usage: /usr/bin/python3 bench/dacrt/plot_dacrt.py docs/figures/dacrt/dacrt_results.json docs/figures/dacrt/
"""
import os
import sys
from collections import defaultdict

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from bench_inputs import load_json, require_dir, require_module  # noqa: E402

matplotlib = require_module("matplotlib", "python3-matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(path, out):
    r = load_json(path)
    require_dir(out)
    if not isinstance(r, dict):
        sys.exit(f"{path}: not a dacrt_bench --json file (an object with threads, reps and the experiments' rows)")
    if not any(k in r for k in ("frames", "resolution", "ablation", "sampling", "counts", "peers")):
        sys.exit(f"{path}: no rows of the experiments this script plots (frames, resolution, ablation, sampling, counts, peers)")
    note = f"threads={r.get('threads')}, median of {r.get('reps')}, {r.get('clock', '')}"
    if "frames" in r:
        fig, ax = plt.subplots(figsize=(8, 5))
        by_view = defaultdict(list)
        for f in r["frames"]:
            by_view[f["view"]].append(f)
        for i, (view, fs) in enumerate(sorted(by_view.items())):
            fs.sort(key=lambda f: f["res"])
            res = [f["res"] for f in fs]
            line, = ax.plot(res, [f["dacrt_ms"] / f["dacrt_rs_ms"] for f in fs], "o-", label=f"{view} (ours)")
            # null where the paper has no value (it measured 512^2 to 4096^2): a gap, not a 0
            paper = [f["paper_ratio"] if f["paper_ratio"] is not None else float("nan") for f in fs]
            ax.plot(res, paper, "x--", color=line.get_color(), alpha=0.6)
        ax.axhline(1.0, color="gray", lw=0.8)
        ax.set_xscale("log", base=2)
        ax.set_xlabel("image width = height (one primary ray per pixel)")
        ax.set_ylabel("dacrt time / dacrt-rs time (frame)")
        ax.set_title(f"Speed-up of ray sampling per resolution (dashed: paper)\n{note}", fontsize=9)
        ax.legend(fontsize=7, ncol=2)
        fig.tight_layout()
        fig.savefig(f"{out}/dacrt_speedup_resolution.png", dpi=110)
    if "resolution" in r:
        fig, ax = plt.subplots(figsize=(8, 5))
        rows = [x for x in r["resolution"] if x["res"] == max(y["res"] for y in r["resolution"])]
        labels = [f'{x["view"]}\n{x["batch"]}' for x in rows]
        ax.bar(range(len(rows)), [x["dacrt_ms"] / x["dacrt_rs_ms"] for x in rows])
        ax.axhline(1.0, color="gray", lw=0.8)
        ax.set_xticks(range(len(rows)))
        ax.set_xticklabels(labels, rotation=90, fontsize=6)
        ax.set_ylabel("dacrt / dacrt-rs")
        ax.set_title(f"Speed-up per batch at {rows[0]['res']}^2 (fig. 8b)\n{note}", fontsize=9)
        fig.tight_layout()
        fig.savefig(f"{out}/dacrt_speedup_batch.png", dpi=110)
    for key, fname, title in (("ablation", "dacrt_ablation.png", "Ablation (paper, Sibenik (a) 4096^2: cost 1.24, order 1.05, skip 1.28)"),
                              ("sampling", "dacrt_sampling.png", "Sampling strategies (fig. 9)")):
        if key not in r:
            continue
        fig, ax = plt.subplots(figsize=(8, 4.5))
        views = sorted({x["view"] for x in r[key]})
        configs = list(dict.fromkeys(x["config"] for x in r[key]))
        w = 0.8 / len(views)
        for i, v in enumerate(views):
            vals = {x["config"]: x["speedup"] for x in r[key] if x["view"] == v}
            ax.bar([c + i * w for c in range(len(configs))], [vals.get(c, 0) for c in configs], w, label=v)
        ax.axhline(1.0, color="gray", lw=0.8)
        ax.set_xticks([c + w * (len(views) - 1) / 2 for c in range(len(configs))])
        ax.set_xticklabels(configs, rotation=20, fontsize=7)
        ax.set_ylabel("speed-up vs dacrt (frame)")
        ax.set_title(f"{title}\n{note}", fontsize=9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(f"{out}/{fname}", dpi=110)
    if "counts" in r:
        fig, ax = plt.subplots(figsize=(8, 4.5))
        rows = r["counts"]
        x = range(len(rows))
        part = [100 * (c["rs_partition_box"] / c["dacrt_box"] - 1) for c in rows]
        allb = [100 * (c["rs_box"] / c["dacrt_box"] - 1) for c in rows]
        ax.bar([i - 0.2 for i in x], part, 0.4, label="partitioning tests only")
        ax.bar([i + 0.2 for i in x], allb, 0.4, label="including the sample rays' tests")
        ax.axhline(0, color="gray", lw=0.8)
        ax.set_xticks(list(x))
        ax.set_xticklabels([f'{c["view"]}\n{c["batch"]}' for c in rows], fontsize=7)
        ax.set_ylabel("ray-box tests of dacrt-rs vs dacrt (%)")
        ax.set_title(f"Ray-box test change per batch at {rows[0]['res']}^2 (paper: -30..-50 % primary/shadow, -20 % random)", fontsize=9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(f"{out}/dacrt_box_tests.png", dpi=110)
    if "peers" in r:
        fig, ax = plt.subplots(figsize=(8, 4.5))
        rows = r["peers"]
        x = list(range(len(rows)))
        ax.bar([i - 0.3 for i in x], [p["dacrt_ms"] for p in rows], 0.2, label="dacrt")
        ax.bar([i - 0.1 for i in x], [p["dacrt_rs_ms"] for p in rows], 0.2, label="dacrt-rs")
        ax.bar([i + 0.1 for i in x], [p["bvh_build_ms"] for p in rows], 0.2, label="bvh build", color="tab:gray")
        ax.bar([i + 0.1 for i in x], [p["bvh_trace_ms"] for p in rows], 0.2, bottom=[p["bvh_build_ms"] for p in rows], label="bvh trace", color="tab:green")
        ax.bar([i + 0.3 for i in x], [p["embree_build_ms"] for p in rows], 0.2, label="embree build", color="silver")
        ax.bar([i + 0.3 for i in x], [p["embree_trace_ms"] for p in rows], 0.2, bottom=[p["embree_build_ms"] for p in rows], label="embree trace", color="tab:purple")
        ax.set_xticks(x)
        ax.set_xticklabels([f'{p["view"]}\n{p["batch"]}' for p in rows], fontsize=7)
        ax.set_ylabel("ms")
        ax.set_title(f"DACRT vs building + tracing a BVH on the same batch at {rows[0]['res']}^2\n{note}", fontsize=9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(f"{out}/dacrt_peers.png", dpi=110)


if __name__ == "__main__":
    if len(sys.argv) > 3:
        sys.exit(__doc__.strip().splitlines()[-1])
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/figures/dacrt/dacrt_results.json",
         sys.argv[2] if len(sys.argv) > 2 else "docs/figures/dacrt")
