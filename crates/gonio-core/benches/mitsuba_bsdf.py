"""Mitsuba 3 reference for `benches/bsdf.rs` (issue 2 §8): ns per lane of BSDF sample + eval,
sample alone and eval alone, in a vectorized variant (default `llvm_ad_spectral`), 2^20 lanes
spread over every core by Dr.Jit's thread pool (per-core cost = figure × cores). With a
`scalar_*` variant: ns per call from a Python loop, binding overhead included (the `null` row).

Same setup as the divan bench: wi = (0.48, 0.36, 0.8)/1.06 (opaque, so Dr.Jit cannot fold it),
independent uniforms, 4 wavelengths per lane drawn as Mitsuba's spectral sensors do. Inputs are
evaluated before the clock starts; each figure is the median of 7 timed launches after a
warm-up launch (JIT compilation excluded), divided by the lane count. Delta BSDFs' `eval` is a
constant 0 that Dr.Jit does not compute per lane.

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_bsdf.py [variant] [model,model,...]
"""
import statistics
import sys
import time

import drjit as dr
import mitsuba as mi

mi.set_variant(sys.argv[1] if len(sys.argv) > 1 else "llvm_ad_spectral")

N = 1 << 20
MODELS = {
    "diffuse": {"type": "diffuse"},
    "conductor_mirror": {"type": "conductor"},
    "conductor_au_spectral": {"type": "conductor", "material": "Au"},
    "dielectric": {"type": "dielectric"},
    "thindielectric": {"type": "thindielectric"},
    "plastic": {"type": "plastic"},
    "twosided_diffuse": {"type": "twosided", "b": {"type": "diffuse"}},
    "roughconductor_beckmann": {"type": "roughconductor"},
    "roughconductor_ggx_au": {"type": "roughconductor", "material": "Au", "distribution": "ggx", "alpha": 0.3},
    "roughdielectric": {"type": "roughdielectric"},
    "roughdielectric_ggx": {"type": "roughdielectric", "distribution": "ggx", "alpha": 0.3},
    "roughplastic": {"type": "roughplastic"},
    "roughplastic_ggx": {"type": "roughplastic", "distribution": "ggx", "alpha": 0.3},
    "principled": {"type": "principled"},
    "principled_full": {
        "type": "principled", "metallic": 0.3, "spec_trans": 0.2, "clearcoat": 0.5,
        "sheen": 0.5, "anisotropic": 0.5, "roughness": 0.4,
    },
    "principledthin": {"type": "principledthin"},
    "blend_mirror_diffuse": {
        "type": "blendbsdf",
        "weight": 0.5,
        "a": {"type": "conductor"},
        "b": {"type": "diffuse"},
    },
}


def launch(bsdf, what):
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(1, N)
    si = dr.zeros(mi.SurfaceInteraction3f, N)
    w = [0.48 / 1.06, 0.36 / 1.06, 0.8 / 1.06]
    si.wi = mi.Vector3f(*[dr.opaque(mi.Float, c, N) for c in w])
    si.n = mi.Normal3f(*[dr.opaque(mi.Float, c, N) for c in (0.0, 0.0, 1.0)])
    si.sh_frame = mi.Frame3f(si.n)
    # As Sensor::sample_wavelengths in spectral variants: 4 shifted samples of the visible pdf.
    si.wavelengths, _ = mi.sample_rgb_spectrum(mi.sample_shifted(sampler.next_1d()))
    ctx = mi.BSDFContext()
    u1, u2 = sampler.next_1d(), sampler.next_2d()
    dr.eval(si, u1, u2)
    dr.sync_thread()
    t0 = time.perf_counter()
    if what == "sample_eval":
        bs, weight = bsdf.sample(ctx, si, u1, u2)
        dr.eval(bs, weight, bsdf.eval(ctx, si, bs.wo))
    elif what == "sample":
        dr.eval(*bsdf.sample(ctx, si, u1, u2))
    else:
        dr.eval(bsdf.eval(ctx, si, mi.warp.square_to_cosine_hemisphere(u2)))
    dr.sync_thread()  # the LLVM backend launches kernels asynchronously
    return time.perf_counter() - t0


def scalar_launch(bsdf, what, n=20000):
    """The scalar variant has no lanes: n calls from Python. The figure includes the binding's
    per-call overhead; the `null` row (a call that does no BSDF work) measures it."""
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(1)
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(0.48 / 1.06, 0.36 / 1.06, 0.8 / 1.06)
    si.n = mi.Normal3f(0.0, 0.0, 1.0)
    si.sh_frame = mi.Frame3f(si.n)
    si.wavelengths, _ = mi.sample_rgb_spectrum(mi.sample_shifted(sampler.next_1d()))
    ctx = mi.BSDFContext()
    us = [(sampler.next_1d(), sampler.next_2d()) for _ in range(n)]
    wos = [mi.warp.square_to_cosine_hemisphere(u2) for _, u2 in us]
    t0 = time.perf_counter()
    if bsdf is None:
        for u1, u2 in us:
            mi.warp.square_to_cosine_hemisphere(u2)
    elif what == "sample_eval":
        for u1, u2 in us:
            bs, weight = bsdf.sample(ctx, si, u1, u2)
            bsdf.eval(ctx, si, bs.wo)
    elif what == "sample":
        for u1, u2 in us:
            bsdf.sample(ctx, si, u1, u2)
    else:
        for wo in wos:
            bsdf.eval(ctx, si, wo)
    return (time.perf_counter() - t0) * N / n


if mi.variant().startswith("scalar"):
    launch = scalar_launch  # noqa: F811 (same figures: ns per call)
    MODELS = {"null": None, **MODELS}

print("model\tsample_eval_ns\tsample_ns\teval_ns")
only = sys.argv[2].split(",") if len(sys.argv) > 2 else None
for name, desc in MODELS.items():
    if only and name not in only:
        continue
    bsdf = None if desc is None else mi.load_dict(desc)
    row = [name]
    for what in ("sample_eval", "sample", "eval"):
        launch(bsdf, what)
        times = [launch(bsdf, what) for _ in range(7)]
        row.append(f"{statistics.median(times) / N * 1e9:.1f}")
    print("\t".join(row), flush=True)
