#!/usr/bin/python3
"""Plots of the manylight bench: RMSE over time per scene and mode, and the skip-rate images
(the paper's Fig. 3) side by side.
Usage: /usr/bin/python3 bench/manylight/plot_manylight.py RESULT_DIR OUT_PREFIX
RESULT_DIR holds rmse_over_time.csv and the *_skip_*.png written by manylight_bench."""
import os
import sys
from collections import defaultdict

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from bench_inputs import read_csv, require_dir, require_module  # noqa: E402

matplotlib = require_module("matplotlib", "python3-matplotlib")
matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

MODES = ["exact", "veach", "conservative", "proposed"]
COLORS = {"exact": "black", "veach": "tab:orange", "conservative": "tab:blue", "proposed": "tab:red"}


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: /usr/bin/python3 bench/manylight/plot_manylight.py RESULT_DIR OUT_PREFIX")
    src, out = sys.argv[1], sys.argv[2]
    require_dir(os.path.dirname(out) or ".")
    curves = defaultdict(list)
    for row in read_csv(os.path.join(src, "rmse_over_time.csv"), ["scene", "mode", "rep", "seconds", "rmse"]):
        curves[(row["scene"], row["mode"], row["rep"])].append((float(row["seconds"]), float(row["rmse"])))
    if not curves:
        sys.exit(f"{os.path.join(src, 'rmse_over_time.csv')}: no rows")
    scenes = sorted({k[0] for k in curves}, key=lambda s: ["sponza", "sibenik_glossy", "conference_large"].index(s)
                    if s in ["sponza", "sibenik_glossy", "conference_large"] else 9)
    fig, axes = plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 4), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for mode in MODES:
            for (s, m, rep), pts in sorted(curves.items()):
                if s != scene or m != mode:
                    continue
                t, e = zip(*pts)
                ax.loglog(t, e, color=COLORS[mode], alpha=1.0 if rep == "0" else 0.4,
                          label=mode if rep == "0" else None)
        ax.set_title(scene)
        ax.set_xlabel("render time (process CPU s, all threads summed)")
        ax.set_ylabel("RMSE (reference noise removed)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.tight_layout()
    fig.savefig(out + "_rmse_over_time.png", dpi=80)

    skip_modes = ["veach", "conservative", "proposed"]
    fig, axes = plt.subplots(len(scenes), len(skip_modes), figsize=(4.2 * len(skip_modes), 2.6 * len(scenes)),
                             squeeze=False)
    for i, scene in enumerate(scenes):
        for j, mode in enumerate(skip_modes):
            ax = axes[i][j]
            path = os.path.join(src, f"{scene}_skip_{mode}.png")
            if os.path.exists(path):
                ax.imshow(mpimg.imread(path), cmap="gray", vmin=0, vmax=1)
            ax.set_title(f"{scene}: {mode}", fontsize=9)
            ax.axis("off")
    fig.suptitle("skip rate per pixel (white = shadow ray skipped)")
    fig.tight_layout()
    fig.savefig(out + "_skip_rates.png", dpi=70)


if __name__ == "__main__":
    main()
