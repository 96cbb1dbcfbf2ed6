"""Adversarial ray sets in rayscout's RAYS v1 format (include/rayscout/core/ray_file.h).

usage: /usr/bin/python3 adversarial_rays.py OUT_DIR LO_X,LO_Y,LO_Z HI_X,HI_Y,HI_Z [N]
writes OUT_DIR/{A_uniform,B_far,C_axis,D_segments,E_lattice,G_scaled,H_special}.rays, N rays each,
for a scene box [LO, HI] (`rayscout info` prints it). Deterministic (seed 7).
"""
import os, struct, sys
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from bench_inputs import require_dir, require_module  # noqa: E402
np = require_module("numpy", "python3-numpy")
def write(path, o, tmin, d, tmax):
    n = len(o)
    a = np.zeros((n, 8), dtype='<f4')
    a[:, 0:3] = o; a[:, 3] = tmin; a[:, 4:7] = d; a[:, 7] = tmax
    with open(path, 'wb') as f:
        f.write(b'RAYS' + struct.pack('<IQ', 1, n)); f.write(a.tobytes())
def unit(rng, n):
    v = rng.normal(size=(n, 3)); return v / np.linalg.norm(v, axis=1)[:, None]
def corner(arg):
    try:
        v = [float(x) for x in arg.split(',')]
    except ValueError:
        v = []
    if len(v) != 3 or not np.isfinite(v).all():
        sys.exit(f"adversarial_rays.py: '{arg}': expected three finite numbers X,Y,Z")
    return np.array(v, dtype=np.float64)
if len(sys.argv) not in (4, 5) or (len(sys.argv) == 5 and not sys.argv[4].isdigit()):
    sys.exit(__doc__.strip().splitlines()[2])
lo, hi = corner(sys.argv[2]), corner(sys.argv[3])
out = sys.argv[1]; n = int(sys.argv[4]) if len(sys.argv) > 4 else 50000
require_dir(out)
rng = np.random.default_rng(7)
ext = hi - lo; diag = np.linalg.norm(ext); c = (lo + hi) / 2
inf = np.full(n, np.inf); zero = np.zeros(n)
# A: uniform origins in the box grown by 20 %, uniform directions
o = lo - 0.2 * ext + rng.random((n, 3)) * 1.4 * ext
write(out + '/A_uniform.rays', o, zero, unit(rng, n), inf)
# B: far outside (2..60 diagonals), aimed at a random point of the box
tgt = lo + rng.random((n, 3)) * ext
o = c + unit(rng, n) * diag * rng.uniform(2, 60, n)[:, None]
d = tgt - o
write(out + '/B_far.rays', o, zero, d, inf)
# C: axis-aligned and partly zero directions, +-0
d = np.zeros((n, 3)); ax = rng.integers(0, 3, n)
d[np.arange(n), ax] = rng.choice([-1.0, 1.0], n)
m = rng.random(n) < 0.5
d2 = unit(rng, n); d2[np.arange(n), (ax + 1) % 3] = 0.0
d[m] = d2[m]
o = lo + rng.random((n, 3)) * ext
dd = d.astype('<f4'); dd[(dd == 0) & (rng.random((n, 3)) < 0.5)] = -0.0
write(out + '/C_axis.rays', o, zero, dd, inf)
# D: random segments [tmin, tmax]
o = lo + rng.random((n, 3)) * ext
tmin = rng.random(n) * 0.3 * diag; tmax = tmin + rng.random(n) * 0.5 * diag
write(out + '/D_segments.rays', o, tmin, unit(rng, n), tmax)
# E: origins on a lattice of the box (k/64 of each extent: voxel faces of power-of-2 grids),
#    on box faces and corners; directions random or aimed at the box centre
k = rng.integers(0, 65, (n, 3)); o = lo + k / 64.0 * ext
d = unit(rng, n); m = rng.random(n) < 0.3; d[m] = (c - o)[m]
write(out + '/E_lattice.rays', o, zero, d, inf)
# G: unnormalised directions, lengths 1e-3 .. 1e3, some very long segments
o = lo + rng.random((n, 3)) * ext
d = unit(rng, n) * (10.0 ** rng.uniform(-3, 3, n))[:, None]
write(out + '/G_scaled.rays', o, zero, d, inf)
# H: special values, one kind per ray, aimed at a random point of the box (t = 1 there):
#    directions 1e20..3e38 or 1e-38..1e-20 long, a subnormal, -0 or +0 component, all zero;
#    empty segments (tmin > tmax, tmax = -inf or 0, tmin = inf), one-point segments [0, 0] and
#    [0.5, 0.5], NaN tmin or tmax; a NaN or infinite origin or direction component, a subnormal
#    origin coordinate. Every accelerator and Embree must agree: misses, or the same hits.
o = lo - 0.2 * ext + rng.random((n, 3)) * 1.4 * ext
d = lo + rng.random((n, 3)) * ext - o
tmin = np.zeros(n); tmax = np.full(n, np.inf)
kind = rng.integers(0, 13, n); comp = rng.integers(0, 3, n); sel = lambda k: np.nonzero(kind == k)[0]
d[sel(0)] *= (10.0 ** rng.uniform(20, 38, len(sel(0))))[:, None] / np.abs(d[sel(0)]).max(axis=1)[:, None]
d[sel(1)] *= (10.0 ** rng.uniform(-38, -20, len(sel(1))))[:, None] / np.abs(d[sel(1)]).max(axis=1)[:, None]
d = d.astype('<f4'); o = o.astype('<f4')
i = sel(2); d[i, comp[i]] = rng.choice([-1, 1], len(i)) * 10.0 ** rng.uniform(-45, -38, len(i))
i = sel(3); d[i, comp[i]] = -0.0; i = i[::2]; d[i, (comp[i] + 1) % 3] = 0.0
i = sel(4); d[i] = rng.choice(np.array([0.0, -0.0], dtype='<f4'), (len(i), 3))
i = sel(5); tmin[i] = rng.uniform(0.5, 1, len(i)); tmax[i] = np.nextafter(tmin[i].astype('<f4'), np.float32(0))
i = sel(6); tmax[i] = rng.choice([-np.inf, 0.0, -0.0], len(i)); tmin[i[::2]] = -0.0
i = sel(7); tmin[i] = np.inf
i = sel(8); tmin[i] = tmax[i] = rng.choice([0.0, 0.5], len(i))
i = sel(9); tmin[i[::2]] = np.nan; tmax[i[1::2]] = np.nan
i = sel(10); o[i, comp[i]] = rng.choice([np.nan, np.inf, -np.inf], len(i))
i = sel(11); d[i, comp[i]] = rng.choice([np.nan, np.inf, -np.inf], len(i))
i = sel(12); o[i, comp[i]] = rng.choice([-1, 1], len(i)) * 10.0 ** rng.uniform(-45, -39, len(i))
write(out + '/H_special.rays', o, tmin, d, tmax)
