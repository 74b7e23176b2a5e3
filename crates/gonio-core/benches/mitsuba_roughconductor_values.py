"""Mitsuba 3.9.1 reference values for `roughconductor` (issue 9 §4), written to
`testdata/mitsuba/reference/mitsuba-roughconductor-values.json` and checked by
`crates/gonio-render/tests/mitsuba_roughconductor_values.rs`.

For each configuration (a `<bsdf>` XML string that gonio's reader loads too): `eval` and `pdf` at
fixed query pairs in `scalar_spectral` (f without the cosine: Mitsuba's eval / cos θo; all four
wavelengths equal), at surface coordinates `uv` (the textured configuration varies with them), and
the reflected albedo (mean sample weight over 2^21 independent samples, also `scalar_spectral`:
the LLVM variants abort on this machine) at a few incidences. Queries are half near the specular lobe (wo reflected about a normal drawn
around z), half uniform on the hemisphere, plus two invalid ones (wo below, wi below).

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_roughconductor_values.py > \
        testdata/mitsuba/reference/mitsuba-roughconductor-values.json
"""
import json
import math
import random

import mitsuba as mi

CONFIGS = [
    ("beckmann-iso-0.1-eta0.2-k3.9",
     '<bsdf version="3.0.0" type="roughconductor"><spectrum name="eta" value="0.2"/>'
     '<spectrum name="k" value="3.9"/></bsdf>'),
    ("ggx-iso-0.3-Au",
     '<bsdf version="3.0.0" type="roughconductor"><string name="material" value="Au"/>'
     '<string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf>'),
    ("beckmann-aniso-0.05-0.3-allnormals",
     '<bsdf version="3.0.0" type="roughconductor"><spectrum name="eta" value="1.1"/>'
     '<spectrum name="k" value="6.8"/><float name="alpha_u" value="0.05"/>'
     '<float name="alpha_v" value="0.3"/><boolean name="sample_visible" value="false"/></bsdf>'),
    ("ggx-aniso-0.4-0.1-tinted",
     '<bsdf version="3.0.0" type="roughconductor"><string name="distribution" value="ggx"/>'
     '<float name="alpha_u" value="0.4"/><float name="alpha_v" value="0.1"/>'
     '<spectrum name="specular_reflectance" value="0.7"/></bsdf>'),
    ("ggx-textured-alpha-Cu",
     '<bsdf version="3.0.0" type="roughconductor"><string name="material" value="Cu"/>'
     '<string name="distribution" value="ggx"/><texture type="checkerboard" name="alpha">'
     '<float name="color0" value="0.08"/><float name="color1" value="0.5"/></texture></bsdf>'),
    ("beckmann-iso-0.6-none",
     '<bsdf version="3.0.0" type="roughconductor"><float name="alpha" value="0.6"/></bsdf>'),
]
WAVELENGTHS = [450.0, 550.0, 650.0]
ALBEDO_THETAS = [0.0, 45.0, 80.0]
ALBEDO_SAMPLES = 1 << 21


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def hemisphere(rng):
    z = rng.uniform(0.02, 1.0)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(1.0 - z * z)
    return [r * math.cos(phi), r * math.sin(phi), z]


def queries(rng):
    out = []
    for i in range(16):
        wi = hemisphere(rng)
        if i < 8:
            m = unit([rng.gauss(0, 0.15), rng.gauss(0, 0.15), 1.0])
            d = sum(a * b for a, b in zip(wi, m))
            wo = [2 * d * mc - w for mc, w in zip(m, wi)]
            if wo[2] <= 0.01:
                wo = hemisphere(rng)
        else:
            wo = hemisphere(rng)
        out.append((wi, unit(wo)))
    out.append((hemisphere(rng), [0.3, 0.2, -0.9327379]))
    out.append(([0.3, 0.2, -0.9327379], hemisphere(rng)))
    return out


def eval_queries(xml, rng):
    mi.set_variant("scalar_spectral")
    bsdf = mi.load_string(xml)
    ctx = mi.BSDFContext()
    rows = []
    for k, (wi, wo) in enumerate(queries(rng)):
        lam = WAVELENGTHS[k % 3]
        uv = [rng.random(), rng.random()]
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(wi)
        si.n = mi.Normal3f(0, 0, 1)
        si.sh_frame = mi.Frame3f(si.n)
        si.uv = mi.Point2f(uv)
        si.wavelengths = mi.UnpolarizedSpectrum(lam)
        f = bsdf.eval(ctx, si, mi.Vector3f(wo))[0]
        pdf = bsdf.pdf(ctx, si, mi.Vector3f(wo))
        f = f / wo[2] if wo[2] > 0 else float(f)
        rows.append({"wi": wi, "wo": wo, "uv": uv, "lambda_nm": lam, "f": float(f), "pdf": float(pdf)})
    return rows


def albedos(xml, rng):
    # The LLVM variants abort on this machine's CPU ("Cannot select: fmaximum"), so the albedo is
    # estimated in scalar_spectral, one sample at a time.
    mi.set_variant("scalar_spectral")
    bsdf = mi.load_string(xml)
    ctx = mi.BSDFContext()
    rows = []
    for theta in ALBEDO_THETAS:
        lam = 550.0
        t = math.radians(theta)
        wi = [math.sin(t) * math.cos(0.3), math.sin(t) * math.sin(0.3), math.cos(t)]
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(wi)
        si.n = mi.Normal3f(0, 0, 1)
        si.sh_frame = mi.Frame3f(si.n)
        si.uv = mi.Point2f(0.25, 0.25)
        si.wavelengths = mi.UnpolarizedSpectrum(lam)
        s1 = s2 = 0.0
        for _ in range(ALBEDO_SAMPLES):
            bs, w = bsdf.sample(ctx, si, rng.random(), mi.Point2f(rng.random(), rng.random()))
            x = float(w[0]) if bs.pdf > 0 else 0.0
            s1 += x
            s2 += x * x
        mean = s1 / ALBEDO_SAMPLES
        var = max(s2 / ALBEDO_SAMPLES - mean * mean, 0.0)
        rows.append({"wi": wi, "uv": [0.25, 0.25], "lambda_nm": lam, "R": mean,
                     "std_error": math.sqrt(var / ALBEDO_SAMPLES)})
    return rows


def checkerboard_eval_vs_eval_1():
    """Mitsuba 3.9.1's checkerboard answers eval (spectra) and eval_1 (floats, what a roughness
    texture uses) with opposite cells: recorded so the test can state it."""
    mi.set_variant("scalar_spectral")
    t = mi.load_dict({"type": "checkerboard", "color0": 0.08, "color1": 0.5})
    rows = []
    for uv in ([0.25, 0.25], [0.75, 0.25]):
        si = mi.SurfaceInteraction3f()
        si.uv = mi.Point2f(uv)
        si.wavelengths = mi.UnpolarizedSpectrum(550.0)
        rows.append({"uv": uv, "eval": float(t.eval(si)[0]), "eval_1": float(t.eval_1(si))})
    return rows


def main():
    rng = random.Random(9)
    out = {
        "generator": "Mitsuba 3.9.1 (crates/gonio-core/benches/mitsuba_roughconductor_values.py): "
                     "eval/pdf and albedo (2^21 samples) in scalar_spectral",
        "conventions": "local frame, z = normal, x = tangent (alpha_u); f excludes the cosine; pdf per "
                       "solid angle; R = mean sample weight (reflected albedo) with its standard error",
        "checkerboard_color0_0.08_color1_0.5": checkerboard_eval_vs_eval_1(),
        "configs": [],
    }
    for name, xml in CONFIGS:
        out["configs"].append({"name": name, "xml": xml, "eval": eval_queries(xml, rng),
                               "albedo": albedos(xml, rng)})
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
