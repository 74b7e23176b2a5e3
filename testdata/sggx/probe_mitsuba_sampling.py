"""Mitsuba 3.9.1's `sggx` against its own density: the fraction of sampled directions in each
octant next to the integral of `eval_pdf` over it (uniform directions, Monte Carlo), for three
incident directions, on `flakes.vol`. Prints the table quoted in
`crates/gonio-render/tests/sggx.rs` (with ωi along z the two agree; otherwise they do not).

    python probe_mitsuba_sampling.py   (needs mitsuba==3.9.1 and LLVM for llvm_ad_rgb)
"""
from pathlib import Path

import drjit as dr
import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_rgb")
here = Path(__file__).resolve().parent
phase = mi.load_dict({"type": "sggx", "S": {"type": "gridvolume", "filename": str(here / "flakes.vol")}})
ctx = mi.PhaseFunctionContext(None)
rng = np.random.default_rng(1)


def interactions(wi, n):
    it = dr.zeros(mi.MediumInteraction3f, n)
    it.wi = mi.Vector3f(wi)
    it.sh_frame = mi.Frame3f(it.wi)
    it.p = mi.Point3f(0.5, 0.5, 0.5)
    return it


def octant(d):
    return (d[:, 0] > 0) * 1 + (d[:, 1] > 0) * 2 + (d[:, 2] > 0) * 4


for w in [(0.3, -0.4, 0.8), (0.0, 0.0, 1.0), (0.9, 0.1, -0.2)]:
    wi = dr.normalize(mi.Vector3f(*w))
    n = 400_000
    u = mi.Point2f(rng.random(n).astype(np.float32), rng.random(n).astype(np.float32))
    wo, weight, pdf = phase.sample(ctx, interactions(wi, n), mi.Float(np.zeros(n, np.float32)), u)
    sampled = np.array(wo).T
    m = 2_000_000
    d = rng.normal(size=(m, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    dirs = mi.Vector3f(*(d[:, k].astype(np.float32) for k in range(3)))
    value, _ = phase.eval_pdf(ctx, interactions(wi, m), dirs)
    value = np.array(value)[0] * 4 * np.pi  # one channel of the (grey) RGB value, / uniform density
    print(f"omega_i = normalize{w}:")
    for o in range(8):
        frac = np.mean(octant(sampled) == o)
        mass = np.sum(value * (octant(d) == o)) / m
        print(f"  octant {o} (x>0: {o & 1}, y>0: {o >> 1 & 1}, z>0: {o >> 2}): sampled {frac:.4f}, density {mass:.4f}")
