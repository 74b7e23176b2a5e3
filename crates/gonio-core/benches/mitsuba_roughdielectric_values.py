"""Mitsuba 3.9.1 reference values for `roughdielectric` (issue 9 §4), written to
`testdata/mitsuba/reference/mitsuba-roughdielectric-values.json` and checked by
`crates/gonio-render/tests/mitsuba_roughdielectric_values.rs`.

For each configuration (a `<bsdf>` XML string that gonio's reader loads too): `eval` and `pdf` at
fixed query pairs in `scalar_spectral` (f without the cosine: Mitsuba's eval / |cos θo|; all four
wavelengths equal), in radiance or importance mode (alternating), at surface coordinates `uv` (the
textured configuration varies with them), and the albedo (mean sample weight over 2^19
independent samples, split into the reflected part R and the transmitted part T, also
`scalar_spectral`: the LLVM variants abort on this machine) at a few incidences from outside and
from inside, in both transport modes.

Queries: wi on either side (every third from inside); wo reflected about a normal drawn around z
(a third), refracted about such a normal (a third), or uniform on either side; plus two grazing-wi
queries.

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_roughdielectric_values.py > \
        testdata/mitsuba/reference/mitsuba-roughdielectric-values.json
"""
import json
import math
import random

import mitsuba as mi

CONFIGS = [
    ("beckmann-iso-0.1-default",
     '<bsdf version="3.0.0" type="roughdielectric"/>'),
    ("ggx-iso-0.3-water-tinted",
     '<bsdf version="3.0.0" type="roughdielectric"><string name="distribution" value="ggx"/>'
     '<float name="alpha" value="0.3"/><string name="int_ior" value="water"/>'
     '<spectrum name="specular_reflectance" value="0.6"/>'
     '<spectrum name="specular_transmittance" value="0.8"/></bsdf>'),
    ("beckmann-aniso-0.05-0.3-allnormals",
     '<bsdf version="3.0.0" type="roughdielectric"><float name="int_ior" value="1.7"/>'
     '<float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.3"/>'
     '<boolean name="sample_visible" value="false"/></bsdf>'),
    ("ggx-aniso-0.4-0.1-inverted",
     '<bsdf version="3.0.0" type="roughdielectric"><string name="distribution" value="ggx"/>'
     '<float name="alpha_u" value="0.4"/><float name="alpha_v" value="0.1"/>'
     '<float name="int_ior" value="1.0"/><float name="ext_ior" value="1.5"/></bsdf>'),
    ("ggx-textured-alpha-diamond",
     '<bsdf version="3.0.0" type="roughdielectric"><string name="distribution" value="ggx"/>'
     '<string name="int_ior" value="diamond"/><texture type="checkerboard" name="alpha">'
     '<float name="color0" value="0.08"/><float name="color1" value="0.5"/></texture></bsdf>'),
    ("ggx-iso-0.7-allnormals",
     '<bsdf version="3.0.0" type="roughdielectric"><string name="distribution" value="ggx"/>'
     '<float name="alpha" value="0.7"/><boolean name="sample_visible" value="false"/></bsdf>'),
]
WAVELENGTHS = [450.0, 550.0, 650.0]
# (θ in degrees, side): +1 outside (the normal's side), -1 inside.
ALBEDO_INCIDENCES = [(0.0, 1), (45.0, 1), (80.0, 1), (30.0, -1), (60.0, -1)]
ALBEDO_SAMPLES = 1 << 19


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def hemisphere(rng, side=1):
    z = rng.uniform(0.02, 1.0)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(1.0 - z * z)
    return [r * math.cos(phi), r * math.sin(phi), side * z]


def refract(wi, m, eta):
    """wi refracted about m (both unit, wi·m > 0 on the +m side of index 1, −m side index eta);
    None under total internal reflection."""
    c = dot(wi, m)
    if c < 0:
        m, eta, c = [-x for x in m], 1.0 / eta, -c
    s2 = (1.0 - c * c) / (eta * eta)
    if s2 >= 1.0:
        return None
    ct = math.sqrt(1.0 - s2)
    return [-w / eta + (c / eta - ct) * mm for w, mm in zip(wi, m)]


def queries(rng, eta):
    out = []
    for i in range(24):
        side = -1 if i % 3 == 2 else 1
        wi = hemisphere(rng, side)
        m = unit([rng.gauss(0, 0.12), rng.gauss(0, 0.12), 1.0])
        kind = i % 6
        wo = None
        if kind in (0, 5):
            d = dot(wi, m)
            wo = [2 * d * mc - w for mc, w in zip(m, wi)]
            if wo[2] * side <= 0.01:
                wo = None
        elif kind in (1, 2):
            wo = refract(wi, m, eta)
            if wo is not None and wo[2] * side >= -0.01:
                wo = None
        elif kind == 3:
            wo = hemisphere(rng, -side)
        if wo is None:
            wo = hemisphere(rng, side)
        out.append((wi, unit(wo), "importance" if i % 2 else "radiance"))
    # Grazing incidence from both sides.
    out.append(([0.8, 0.3, 0.05], hemisphere(rng, -1), "radiance"))
    out.append(([0.2, -0.6, -0.04], hemisphere(rng, -1), "radiance"))
    return out


def context(mode):
    ctx = mi.BSDFContext()
    if mode == "importance":
        ctx.mode = mi.TransportMode.Importance
    return ctx


def interaction(wi, uv, lam):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.uv = mi.Point2f(uv)
    si.wavelengths = mi.UnpolarizedSpectrum(lam)
    return si


def relative_eta(bsdf):
    return float(mi.traverse(bsdf)["eta"])


def eval_queries(bsdf, rng):
    rows = []
    for k, (wi, wo, mode) in enumerate(queries(rng, relative_eta(bsdf))):
        lam = WAVELENGTHS[k % 3]
        uv = [rng.random(), rng.random()]
        si = interaction(wi, uv, lam)
        ctx = context(mode)
        f = float(bsdf.eval(ctx, si, mi.Vector3f(wo))[0])
        pdf = float(bsdf.pdf(ctx, si, mi.Vector3f(wo)))
        f = f / abs(wo[2])
        rows.append({"wi": wi, "wo": wo, "uv": uv, "lambda_nm": lam, "mode": mode, "f": f,
                     "pdf": pdf})
    return rows


def albedos(bsdf, rng):
    rows = []
    for mode in ("radiance", "importance"):
        ctx = context(mode)
        for theta, side in ALBEDO_INCIDENCES:
            lam = 550.0
            t = math.radians(theta)
            wi = [math.sin(t) * math.cos(0.3), math.sin(t) * math.sin(0.3), side * math.cos(t)]
            si = interaction(wi, [0.25, 0.25], lam)
            sums = [0.0] * 6  # R, R², T, T², total, total²
            for _ in range(ALBEDO_SAMPLES):
                bs, w = bsdf.sample(ctx, si, rng.random(), mi.Point2f(rng.random(), rng.random()))
                x = float(w[0]) if bs.pdf > 0 else 0.0
                refl = float(bs.wo[2]) * wi[2] > 0
                r, tr = (x, 0.0) if refl else (0.0, x)
                for j, v in enumerate((r, tr, x)):
                    sums[2 * j] += v
                    sums[2 * j + 1] += v * v
            n = ALBEDO_SAMPLES

            def stats(j):
                mean = sums[2 * j] / n
                return mean, math.sqrt(max(sums[2 * j + 1] / n - mean * mean, 0.0) / n)

            (r, r_se), (tr, t_se), (tot, tot_se) = stats(0), stats(1), stats(2)
            rows.append({"wi": wi, "uv": [0.25, 0.25], "lambda_nm": lam, "mode": mode,
                         "R": r, "R_se": r_se, "T": tr, "T_se": t_se,
                         "total": tot, "total_se": tot_se})
    return rows


def checkerboard_eval_vs_eval_1():
    """Mitsuba 3.9.1's checkerboard answers eval (spectra) and eval_1 (floats, what a roughness
    texture uses) with opposite cells: recorded so the test can state it."""
    t = mi.load_dict({"type": "checkerboard", "color0": 0.08, "color1": 0.5})
    rows = []
    for uv in ([0.25, 0.25], [0.75, 0.25]):
        si = mi.SurfaceInteraction3f()
        si.uv = mi.Point2f(uv)
        si.wavelengths = mi.UnpolarizedSpectrum(550.0)
        rows.append({"uv": uv, "eval": float(t.eval(si)[0]), "eval_1": float(t.eval_1(si))})
    return rows


def main():
    mi.set_variant("scalar_spectral")
    rng = random.Random(9)
    out = {
        "generator": "Mitsuba 3.9.1 (crates/gonio-core/benches/mitsuba_roughdielectric_values.py): "
                     "eval/pdf and albedo (2^19 samples) in scalar_spectral",
        "conventions": "local frame, z = normal (exterior side), x = tangent (alpha_u); f excludes "
                       "the cosine; pdf per solid angle; mode = transport mode of the query; R, T = "
                       "mean sample weight leaving on wi's side / the other side, total = R + T, "
                       "each with its standard error",
        "checkerboard_color0_0.08_color1_0.5": checkerboard_eval_vs_eval_1(),
        "configs": [],
    }
    for name, xml in CONFIGS:
        bsdf = mi.load_string(xml)
        out["configs"].append({"name": name, "xml": xml, "eta": relative_eta(bsdf),
                               "eval": eval_queries(bsdf, rng), "albedo": albedos(bsdf, rng)})
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
