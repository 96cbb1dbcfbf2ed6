#!/usr/bin/python3
"""Markdown tables of the many-light results (the paper's Tables 1-3) from manylight_bench JSON.
Usage: manylight_tables.py PAIRED.json EQUAL_TIME.json"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from bench_inputs import load_json  # noqa: E402

PAPER_T2 = {"sponza": ("50 / 60 s", "x1.16 / x1.13", "x1.52 / x1.40"),
            "sibenik_glossy": ("48 / 60 s", "x1.26 / x1.20", "x1.55 / x1.40"),
            "conference_large": ("38 / 60 s", "x1.23 / x1.13", "x1.41 / x1.22")}
PAPER_T3 = {"sponza": ("0.0145, 39.6 %", "0.0130, 60.7 %"), "sibenik_glossy": ("0.0263, 45.6 %", "0.0239, 61.6 %"),
            "conference_large": ("0.0770, 40.5 %", "0.0718, 55.3 %")}
PAPER_T1 = {"sponza": "100K, 262K, 10 s, 0.15", "sibenik_glossy": "200K, 143K, 12 s, 0.32",
            "conference_large": "200K, 10M, 22 s, 0.05"}
LABEL = {"sponza": "(a) sponza", "sibenik_glossy": "(b) sibenik_glossy", "conference_large": "(c) conference_large"}


def paired_speedups(s):
    """Geometric mean over repetitions of (MSE t)_exact / (MSE t)_mode: each repetition is a
    paired comparison (same VPL samples), so its ratio is far less noisy than the MSEs."""
    m = s["modes"]
    out = {}
    for k in m:
        prod = 1.0
        runs = list(zip(m["exact"]["mse_times_t"], m[k]["mse_times_t"]))
        for e, x in runs:
            prod *= e / x
        out[k] = prod ** (1.0 / len(runs))
    return out


def table2(results, per_rep=False):
    print("| scene | | exact | veach | proposed | conservative |")
    print("| --- | --- | --- | --- | --- | --- |")
    for s in results:
        m = s["modes"]
        t_exact = m["exact"]["time_to_exact_rmse_s"]
        if per_rep:
            sp = paired_speedups(s)
            for k in m:
                m[k]["speedup"] = sp[k]
                m[k]["time_to_exact_rmse_s"] = t_exact / sp[k]
                extra = 0.0 if k == "exact" else s["calibration_s"]
                pre = s["preprocess_cpu_s"]
                m[k]["speedup_with_preprocess"] = (t_exact + pre) / (t_exact / sp[k] + pre + extra)
        cells = [f"{m[k]['time_to_exact_rmse_s']:.2f} s (x{m[k]['speedup']:.2f})" for k in ("veach", "proposed", "conservative")]
        cells[1] = f"**{cells[1]}**"
        print(f"| {LABEL[s['scene']]} | render only | {t_exact:.2f} s | {' | '.join(cells)} |")
        w = [f"(x{m[k]['speedup_with_preprocess']:.2f})" for k in ("veach", "proposed", "conservative")]
        w[1] = f"**{w[1]}**"
        print(f"| | with VC ({s['preprocess_cpu_s']:.2f} s + calib {s['calibration_s']:.2f} s) | "
              f"{t_exact + s['preprocess_cpu_s']:.2f} s | {' | '.join(w)} |")
        p = PAPER_T2[s["scene"]]
        print(f"| | paper, without / with VC | {p[0]} | {p[1]} | {p[2]} | |")
    print()
    print("proposed vs veach (render only): " + ", ".join(
        f"x{s['modes']['proposed']['speedup'] / s['modes']['veach']['speedup']:.2f} ({s['scene']})" for s in results))
    print("mean skip rates: " + "; ".join(
        f"{s['scene']}: " + ", ".join(f"{k} {100 * s['modes'][k]['skip_rate']:.1f} %" for k in ("veach", "conservative", "proposed"))
        for s in results))
    print(("RMSE at equal passes: " if per_rep else "RMSE at equal time: ") + "; ".join(
        f"{s['scene']}: " + ", ".join(f"{k} {s['modes'][k]['rmse']:.3f}" for k in ("exact", "veach", "conservative", "proposed"))
        for s in results))
    print("MSE*t per run: " + "; ".join(
        f"{s['scene']}: " + ", ".join(f"{k} " + "/".join(f"{x:.3g}" for x in s['modes'][k]['mse_times_t'])
                                      for k in ("exact", "veach", "conservative", "proposed")) for s in results))
    print()


def table3(results):
    print("| scene | exact | veach | conservative | proposed | paper conservative | paper proposed |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for s in results:
        m = s["modes"]
        c = [f"{m[k]['rmse']:.3f}, {100 * m[k]['skip_rate']:.1f} %" for k in ("exact", "veach", "conservative", "proposed")]
        c[3] = f"**{c[3]}**"
        p = PAPER_T3[s["scene"]]
        print(f"| {LABEL[s['scene']][:3]} | {' | '.join(c)} | {p[0]} | {p[1]} |")
    print()


def table1(results):
    print("| scene | VPLs | triangles | VisibilityCluster (VPLs + points + clusters + r) | shadow rays for r (refined pairs) | t_skip / t_eval | paper |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for s in results:
        print(f"| {LABEL[s['scene']][:3]} | {s['vpls']:,} | {s['triangles']:,} | {s['preprocess_cpu_s']:.2f} s | "
              f"{s['shadow_rays_visibility_cluster'] / 1000:.0f}K ({s['refined_pairs']:,}) | "
              f"{s['t_skip_over_t_eval']:.3f} ({s['t_skip_us']:.3f} / {s['t_eval_us']:.3f} us) | {PAPER_T1[s['scene']]} |")
    print()


def load(path):
    results = load_json(path)
    if not isinstance(results, list) or not all(isinstance(s, dict) and "modes" in s for s in results):
        sys.exit(f"{path}: not a manylight_bench --json file (a list of scenes with their modes)")
    return results


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__.strip().splitlines()[-1])
    paired = load(sys.argv[1])
    equal = load(sys.argv[2])
    print("### paired (equal passes)\n")
    table2(paired, per_rep=True)
    print("### equal time\n")
    table2(equal)
    table3(equal)
    table1(paired)


if __name__ == "__main__":
    main()
