#!/usr/bin/env python3
"""Mitsuba 3.9.1 values of the `normalmap` adapter, for gonio's test
(`crates/gonio-render/tests/mitsuba_perturbed_values.rs`): writes `reference/mitsuba-perturbed-values.json`.

A `normalmap` on a rectangle (its shading frame the world axes: s = x, t = y, n = z) with a
constant map (an 8 x 8 `raw` PNG of one texel value, written to `reference/perturbed/`), around a nested `diffuse` (reflectance 0.5)
or an anisotropic GGX `roughconductor` (material none, alpha_u 0.25, alpha_v 0.05), with
`flip_invalid_normals` and `use_shadowing_function` each on and off. For pairs (wi, wo) of local
directions, Mitsuba's `eval` (which includes the cosine, as Mitsuba's BSDFs do: f * cos, the cosine
taken in the nested BSDF's perturbed frame) and `pdf`. Run once:

    .venv-mitsuba/bin/python testdata/mitsuba/make_perturbed_values.py
"""
import json, os
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
HERE = os.path.dirname(os.path.abspath(__file__))
TEXELS = {"tilt-x": [0.7, 0.5, 0.9], "tilt-xy": [0.25, 0.8, 0.75], "steep": [0.95, 0.3, 0.55]}
NESTED = {
    "diffuse": {"type": "diffuse", "reflectance": {"type": "spectrum", "value": 0.5}},
    "roughconductor-aniso": {"type": "roughconductor", "material": "none", "distribution": "ggx",
                             "alpha_u": 0.25, "alpha_v": 0.05},
}
rng = np.random.default_rng(7)


def direction(z_min, z_max):
    z = rng.uniform(z_min, z_max)
    phi = rng.uniform(0, 2 * np.pi)
    r = np.sqrt(max(0.0, 1 - z * z))
    return [float(r * np.cos(phi)), float(r * np.sin(phi)), float(z)]


pairs = [(direction(0.05, 1.0), direction(0.05, 1.0)) for _ in range(24)]
pairs += [(direction(0.02, 0.25), direction(0.05, 1.0)) for _ in range(8)]  # grazing views: flips
configs = []
tmp = os.path.join(HERE, "reference", "perturbed")
os.makedirs(tmp, exist_ok=True)
if True:
    for tname, rgb in TEXELS.items():
        png = os.path.join(tmp, tname + ".png")
        texel = np.array([round(c * 255) for c in rgb], dtype=np.uint8)
        mi.Bitmap(np.tile(texel, (8, 8, 1))).write(png)
        stored = [int(c) / 255 for c in texel]
        for nname, nested in NESTED.items():
            for flip in (True, False):
                for shadow in (True, False):
                    scene = mi.load_dict({"type": "scene", "r": {"type": "rectangle", "bsdf": {
                        "type": "normalmap", "flip_invalid_normals": flip, "use_shadowing_function": shadow,
                        "normalmap": {"type": "bitmap", "filename": png, "raw": True, "filter_type": "nearest"},
                        "nested": nested}}})
                    si = scene.ray_intersect(mi.Ray3f(mi.Point3f(0.1, 0.2, 1), mi.Vector3f(0, 0, -1)))
                    assert np.allclose(np.array(si.sh_frame.n), [0, 0, 1]) and np.allclose(np.array(si.sh_frame.s), [1, 0, 0])
                    bsdf = si.bsdf()
                    ctx = mi.BSDFContext()
                    values = []
                    for wi, wo in pairs:
                        si.wi = mi.Vector3f(*wi)
                        v = bsdf.eval(ctx, si, mi.Vector3f(*wo))
                        p = bsdf.pdf(ctx, si, mi.Vector3f(*wo))
                        values.append({"wi": wi, "wo": wo, "eval_cos": float(v[0]), "pdf": float(p)})
                    configs.append({"texel": stored, "png": tname + ".png", "nested": nname, "flip_invalid_normals": flip,
                                    "use_shadowing_function": shadow, "values": values})
out = {"generator": "Mitsuba 3.9.1 scalar_rgb, testdata/mitsuba/make_perturbed_values.py",
       "conventions": "local frame of the unperturbed shading frame (s = x, t = y, n = z); eval_cos is Mitsuba's eval: f times the cosine in the perturbed frame, times the terminator's shadowing when on; pdf per solid angle; texel is the stored 8-bit map value / 255",
       "nested": {k: json.dumps(v) for k, v in NESTED.items()},
       "configs": configs}
with open(os.path.join(HERE, "reference", "mitsuba-perturbed-values.json"), "w") as f:
    json.dump(out, f, separators=(",", ":"))
print(len(configs), "configs,", len(pairs), "pairs each")
