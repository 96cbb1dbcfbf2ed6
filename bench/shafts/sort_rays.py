#!/usr/bin/python3
"""Reorders a RAYS file by a shaft-like key (origin voxel x cube-map direction cell).

An experiment on batch order, not a part of the accelerators: are the shaft lists' gains
separable from the coherence a classification-sorted batch would give any traversal?
(docs/history/shafts.md, session 20). The grid is near-cubical over the bounds of the ray origins,
VOXELS along its longest axis; directions fall into DIR_RES x DIR_RES cells on each cube face,
as in ShaftGrid. The sort is stable, so rays of one key keep their order.

usage: /usr/bin/python3 bench/shafts/sort_rays.py IN.rays OUT.rays [VOXELS] [DIR_RES]   (defaults 16 and 4)
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from bench_inputs import read_bytes, require_dir, require_module  # noqa: E402

np = require_module("numpy", "python3-numpy")

HEADER = 16  # "RAYS", uint32 version, uint64 count (include/rayscout/core/ray_file.h)


def shaft_keys(rays, voxels, dir_res):
    org, dirs = rays[:, 0:3], rays[:, 4:7]
    lo = org.min(axis=0)
    extent = np.maximum(org.max(axis=0) - lo, 1e-30)
    res = np.maximum(1, np.ceil(extent / (extent.max() / voxels))).astype(np.int64)
    idx = np.minimum(((org - lo) / extent * res).astype(np.int64), res - 1)
    voxel = (idx[:, 2] * res[1] + idx[:, 1]) * res[0] + idx[:, 0]
    n = np.arange(len(rays))
    axis = np.abs(dirs).argmax(axis=1)
    major = dirs[n, axis]
    face = 2 * axis + (major < 0)
    # Coordinates on the face in [-1, 1]; a zero direction lands in cell 0 of face 0.
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.nan_to_num(dirs[n, (axis + 1) % 3] / np.abs(major))
        v = np.nan_to_num(dirs[n, (axis + 2) % 3] / np.abs(major))
    iu = np.clip(((u + 1) / 2 * dir_res).astype(np.int64), 0, dir_res - 1)
    iv = np.clip(((v + 1) / 2 * dir_res).astype(np.int64), 0, dir_res - 1)
    return voxel * (6 * dir_res * dir_res) + (face * dir_res + iu) * dir_res + iv


def main():
    if len(sys.argv) not in (3, 4, 5):
        sys.exit(__doc__.strip().splitlines()[-1])
    voxels = int(sys.argv[3]) if len(sys.argv) > 3 else 16
    dir_res = int(sys.argv[4]) if len(sys.argv) > 4 else 4
    raw = read_bytes(sys.argv[1])
    require_dir(os.path.dirname(sys.argv[2]) or ".")
    if raw[:4] != b"RAYS" or (len(raw) - HEADER) % 32:
        sys.exit(f"{sys.argv[1]}: not a RAYS file")
    rays = np.frombuffer(raw[HEADER:], dtype="<f4").reshape(-1, 8)
    if len(rays) == 0 or not np.isfinite(rays[:, 0:3]).all():
        sys.exit(f"{sys.argv[1]}: needs at least one ray and finite origins")
    order = np.argsort(shaft_keys(rays, voxels, dir_res), kind="stable")
    with open(sys.argv[2], "wb") as out:
        out.write(raw[:HEADER] + rays[order].tobytes())
    print(f"{sys.argv[2]}: {len(rays)} rays sorted by origin voxel and direction cell")


if __name__ == "__main__":
    main()
