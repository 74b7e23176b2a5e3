"""Mitsuba 3.9.1 reference values for `roughplastic` (issue 9 §2–§4), written to
`testdata/mitsuba/reference/mitsuba-roughplastic-values.json` and checked by
`crates/gonio-render/tests/mitsuba_roughplastic_values.rs`.

For each configuration (a `<bsdf>` XML string that gonio's reader loads too): `eval` and `pdf` at
fixed query pairs in `scalar_spectral` (f without the cosine: Mitsuba's eval / cos θo; all four
wavelengths equal), at surface coordinates `uv` (the textured configuration varies with them), and
the reflected albedo (mean sample weight over 2^19 independent samples, also `scalar_spectral`:
the LLVM variants abort on this machine) at a few incidences. Queries are half near the coat's
specular lobe (wo reflected about a normal drawn around z), half uniform on the hemisphere, plus two
invalid ones (wo below, wi below).

`energy` holds the albedo of a white base (ρ = 1, Mitsuba's other defaults) at 0°, 45° and 80° for
α = 0.1, 0.5 and 1 with both distributions: what the coat's precomputed averages do to energy.

    pip install mitsuba==3.9.1
    nice python3 crates/gonio-core/benches/mitsuba_roughplastic_values.py > \
        testdata/mitsuba/reference/mitsuba-roughplastic-values.json
"""
import json
import math
import random

import mitsuba as mi

CONFIGS = [
    ("beckmann-0.1-defaults",
     '<bsdf version="3.0.0" type="roughplastic"/>'),
    ("ggx-0.3-nonlinear-rho0.8-ior1.5",
     '<bsdf version="3.0.0" type="roughplastic"><string name="distribution" value="ggx"/>'
     '<float name="alpha" value="0.3"/><boolean name="nonlinear" value="true"/>'
     '<spectrum name="diffuse_reflectance" value="0.8"/><float name="int_ior" value="1.5"/>'
     '<float name="ext_ior" value="1.0"/></bsdf>'),
    ("beckmann-0.5-allnormals-nonlinear-tinted-bk7",
     '<bsdf version="3.0.0" type="roughplastic"><float name="alpha" value="0.5"/>'
     '<boolean name="sample_visible" value="false"/><boolean name="nonlinear" value="true"/>'
     '<spectrum name="specular_reflectance" value="0.7"/><string name="int_ior" value="bk7"/>'
     '<spectrum name="diffuse_reflectance" value="0.3"/></bsdf>'),
    ("ggx-0.05-textured-diffuse",
     '<bsdf version="3.0.0" type="roughplastic"><string name="distribution" value="ggx"/>'
     '<float name="alpha" value="0.05"/><texture type="checkerboard" name="diffuse_reflectance">'
     '<float name="color0" value="0.2"/><float name="color1" value="0.9"/></texture></bsdf>'),
    ("beckmann-1.0-white-nonlinear",
     '<bsdf version="3.0.0" type="roughplastic"><float name="alpha" value="1.0"/>'
     '<spectrum name="diffuse_reflectance" value="1.0"/><boolean name="nonlinear" value="true"/></bsdf>'),
]
ENERGY_ALPHAS = [0.1, 0.5, 1.0]
ENERGY_DISTRIBUTIONS = ["beckmann", "ggx"]
WAVELENGTHS = [450.0, 550.0, 650.0]
ALBEDO_THETAS = [0.0, 45.0, 80.0]
ALBEDO_SAMPLES = 1 << 19


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


def interaction(wi, uv, lam):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.uv = mi.Point2f(uv)
    si.wavelengths = mi.UnpolarizedSpectrum(lam)
    return si


def eval_queries(xml, rng):
    bsdf = mi.load_string(xml)
    ctx = mi.BSDFContext()
    rows = []
    for k, (wi, wo) in enumerate(queries(rng)):
        lam = WAVELENGTHS[k % 3]
        uv = [rng.random(), rng.random()]
        si = interaction(wi, uv, lam)
        f = bsdf.eval(ctx, si, mi.Vector3f(wo))[0]
        pdf = bsdf.pdf(ctx, si, mi.Vector3f(wo))
        f = f / wo[2] if wo[2] > 0 else float(f)
        rows.append({"wi": wi, "wo": wo, "uv": uv, "lambda_nm": lam, "f": float(f), "pdf": float(pdf)})
    return rows


def albedos(xml, rng):
    # The LLVM variants abort on this machine's CPU ("Cannot select: fmaximum"), so the albedo is
    # estimated in scalar_spectral, one sample at a time.
    bsdf = mi.load_string(xml)
    ctx = mi.BSDFContext()
    rows = []
    for theta in ALBEDO_THETAS:
        lam = 550.0
        t = math.radians(theta)
        wi = [math.sin(t) * math.cos(0.3), math.sin(t) * math.sin(0.3), math.cos(t)]
        si = interaction(wi, [0.25, 0.25], lam)
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


def energy_xml(distribution, alpha):
    return ('<bsdf version="3.0.0" type="roughplastic"><string name="distribution" value="%s"/>'
            '<float name="alpha" value="%g"/><spectrum name="diffuse_reflectance" value="1.0"/></bsdf>'
            % (distribution, alpha))


def main():
    mi.set_variant("scalar_spectral")
    rng = random.Random(9)
    out = {
        "generator": "Mitsuba 3.9.1 (crates/gonio-core/benches/mitsuba_roughplastic_values.py): "
                     "eval/pdf and albedo (2^19 samples) in scalar_spectral",
        "conventions": "local frame, z = normal; f excludes the cosine; pdf per solid angle; "
                       "R = mean sample weight (reflected albedo) with its standard error",
        "configs": [],
        "energy": [],
    }
    for name, xml in CONFIGS:
        out["configs"].append({"name": name, "xml": xml, "eval": eval_queries(xml, rng),
                               "albedo": albedos(xml, rng)})
    for distribution in ENERGY_DISTRIBUTIONS:
        for alpha in ENERGY_ALPHAS:
            xml = energy_xml(distribution, alpha)
            out["energy"].append({"name": "%s-%g-white" % (distribution, alpha), "xml": xml,
                                  "albedo": albedos(xml, rng)})
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
