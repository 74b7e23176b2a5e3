"""Mitsuba 3.9.1 reference values for `principled` and `principledthin` (issue 9 §4), written to
`testdata/mitsuba/reference/mitsuba-principled-values.json` and checked by
`crates/gonio-render/tests/mitsuba_principled_values.rs`.

For each configuration (a `<bsdf>` XML string that gonio's reader loads too): `eval` and `pdf` at
fixed query pairs in `scalar_spectral` (f without the cosine: Mitsuba's eval / |cos θo|; four
distinct wavelengths per query, so the tints' spectral luminance is a mean over them), at surface
coordinates `uv` (textured configurations vary with them), from outside and, where the material
transmits, from inside; and the albedo (mean sample weight, reflection and transmission, over
2^20 independent samples at 550 nm) at a few incidences. Queries: a third near the specular
reflection (wo reflected about a normal drawn around z), a third near the refraction (where the
material transmits; for `principledthin`, near the reflection mirrored through the sheet), the
rest uniform on the sphere. `principledthin` is queried from both sides.

Configurations whose float parameters (roughness, metallic, ...) are checkerboards are marked
`eval_1_swapped`: Mitsuba 3.9.1's checkerboard answers `eval_1` with the other cell than `eval`
(see `mitsuba-roughconductor-values.json`); the test compares them at the uv shifted by half a
period in u. Base colours are read with `eval`, so their checkerboards need no shift.

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_principled_values.py > \
        testdata/mitsuba/reference/mitsuba-principled-values.json
"""
import json
import math
import random
import sys

import mitsuba as mi

SPEC = '<spectrum name="base_color" value="400:0.15, 480:0.7, 560:0.45, 640:0.9, 720:0.3"/>'

# (name, xml, transmits, eval_1_swapped)
CONFIGS = [
    ("principled-default", '<bsdf version="3.0.0" type="principled"/>', False, False),
    ("principled-metal-anisotropic",
     '<bsdf version="3.0.0" type="principled">' + SPEC +
     '<float name="metallic" value="1"/><float name="roughness" value="0.35"/>'
     '<float name="anisotropic" value="0.7"/></bsdf>', False, False),
    ("principled-glass",
     '<bsdf version="3.0.0" type="principled"><spectrum name="base_color" value="0.9"/>'
     '<float name="spec_trans" value="1"/><float name="roughness" value="0.25"/>'
     '<float name="eta" value="1.45"/></bsdf>', True, False),
    ("principled-clearcoat-sheen",
     '<bsdf version="3.0.0" type="principled">' + SPEC +
     '<float name="roughness" value="0.6"/><float name="spec_tint" value="0.4"/>'
     '<float name="sheen" value="0.7"/><float name="sheen_tint" value="0.5"/>'
     '<float name="clearcoat" value="0.8"/><float name="clearcoat_gloss" value="0.5"/>'
     '<float name="flatness" value="0.4"/></bsdf>', False, False),
    ("principled-everything-rates",
     '<bsdf version="3.0.0" type="principled">' + SPEC +
     '<float name="metallic" value="0.3"/><float name="specular" value="0.6"/>'
     '<float name="roughness" value="0.2"/><float name="spec_tint" value="0.4"/>'
     '<float name="anisotropic" value="0.5"/><float name="sheen" value="0.3"/>'
     '<float name="sheen_tint" value="0.2"/><float name="clearcoat" value="0.6"/>'
     '<float name="clearcoat_gloss" value="0.3"/><float name="spec_trans" value="0.4"/>'
     '<float name="main_specular_sampling_rate" value="2"/>'
     '<float name="clearcoat_sampling_rate" value="0.5"/>'
     '<float name="diffuse_reflectance_sampling_rate" value="0.7"/></bsdf>', True, False),
    ("principled-textured-base-color",
     '<bsdf version="3.0.0" type="principled"><texture type="checkerboard" name="base_color">'
     '<spectrum name="color0" value="400:0.9, 700:0.1"/><spectrum name="color1" value="0.3"/>'
     '</texture><float name="spec_tint" value="0.6"/><float name="sheen" value="1"/>'
     '<float name="sheen_tint" value="1"/><float name="roughness" value="0.4"/></bsdf>',
     False, False),
    ("principled-textured-roughness-metallic-transmission",
     '<bsdf version="3.0.0" type="principled"><spectrum name="base_color" value="0.8"/>'
     '<texture type="checkerboard" name="roughness"><float name="color0" value="0.1"/>'
     '<float name="color1" value="0.6"/></texture>'
     '<texture type="checkerboard" name="metallic"><float name="color0" value="0.7"/>'
     '<float name="color1" value="0.0"/></texture>'
     '<float name="spec_trans" value="0.6"/><float name="anisotropic" value="0.4"/></bsdf>',
     True, True),
    ("principledthin-default", '<bsdf version="3.0.0" type="principledthin"/>', True, False),
    ("principledthin-anisotropic-spec-trans",
     '<bsdf version="3.0.0" type="principledthin">' + SPEC +
     '<float name="roughness" value="0.15"/><float name="spec_tint" value="0.1"/>'
     '<float name="anisotropic" value="0.5"/><float name="spec_trans" value="0.8"/>'
     '<float name="diff_trans" value="0.3"/><float name="eta" value="1.33"/></bsdf>', True, False),
    ("principledthin-diff-trans-sheen-rates",
     '<bsdf version="3.0.0" type="principledthin">' + SPEC +
     '<float name="roughness" value="0.7"/><float name="spec_trans" value="0.3"/>'
     '<float name="diff_trans" value="1.2"/><float name="sheen" value="0.6"/>'
     '<float name="sheen_tint" value="0.5"/><float name="flatness" value="0.5"/>'
     '<float name="eta" value="1.6"/>'
     '<float name="diffuse_reflectance_sampling_rate" value="0.5"/>'
     '<float name="specular_reflectance_sampling_rate" value="2"/>'
     '<float name="specular_transmittance_sampling_rate" value="1.5"/>'
     '<float name="diffuse_transmittance_sampling_rate" value="0.8"/></bsdf>', True, False),
    ("principledthin-textured-base-color",
     '<bsdf version="3.0.0" type="principledthin"><texture type="checkerboard" name="base_color">'
     '<spectrum name="color0" value="400:0.9, 700:0.1"/><spectrum name="color1" value="0.3"/>'
     '</texture><float name="spec_trans" value="0.5"/><float name="spec_tint" value="0.5"/>'
     '<float name="diff_trans" value="0.5"/></bsdf>', True, False),
    ("principledthin-textured-roughness-eta-diff-trans",
     '<bsdf version="3.0.0" type="principledthin"><spectrum name="base_color" value="0.8"/>'
     '<texture type="checkerboard" name="roughness"><float name="color0" value="0.1"/>'
     '<float name="color1" value="0.6"/></texture>'
     '<texture type="checkerboard" name="eta"><float name="color0" value="1.2"/>'
     '<float name="color1" value="1.7"/></texture>'
     '<texture type="checkerboard" name="diff_trans"><float name="color0" value="1.5"/>'
     '<float name="color1" value="0.2"/></texture>'
     '<float name="spec_trans" value="0.6"/><float name="anisotropic" value="0.3"/></bsdf>',
     True, True),
]
ALBEDO_THETAS = [0.0, 45.0, 80.0]
ALBEDO_SAMPLES = int(__import__("os").environ.get("ALBEDO_SAMPLES", 1 << 20))


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def sphere(rng, lo=0.02):
    """A direction with |z| ≥ lo, uniform otherwise."""
    while True:
        z = rng.uniform(-1.0, 1.0)
        if abs(z) >= lo:
            break
    phi = rng.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(1.0 - z * z)
    return [r * math.cos(phi), r * math.sin(phi), z]


def near_normal(rng, sigma):
    return unit([rng.gauss(0, sigma), rng.gauss(0, sigma), 1.0])


def refract(wi, m, eta):
    """wi refracted through the facet m (m on wi's side), relative index eta = n_t/n_i."""
    c = sum(a * b for a, b in zip(wi, m))
    s2 = (1.0 - c * c) / (eta * eta)
    if s2 >= 1.0:
        return None
    ct = math.sqrt(1.0 - s2)
    return unit([-w / eta + (c / eta - ct) * mc for w, mc in zip(wi, m)])


def eta_of(xml):
    """η of a `principled` configuration (`principledthin` queries do not need it)."""
    if 'name="eta" value="' in xml:
        return float(xml.split('name="eta" value="')[1].split('"')[0])
    spec = 0.5
    if 'name="specular"' in xml:
        spec = float(xml.split('name="specular" value="')[1].split('"')[0])
    return 2.0 / (1.0 - math.sqrt(0.08 * spec)) - 1.0


def queries(rng, transmits, eta, thin):
    out = []
    n = 24
    for i in range(n):
        wi = sphere(rng)
        if not transmits and wi[2] < 0 and i % 6 != 5:
            wi[2] = -wi[2]
        side = 1.0 if wi[2] > 0 else -1.0
        m = [side * c for c in near_normal(rng, 0.2)]
        kind = i % 3
        wo = None
        if kind == 0:
            d = sum(a * b for a, b in zip(wi, m))
            wo = [2 * d * mc - w for mc, w in zip(m, wi)]
            if wo[2] * side <= 0.01:
                wo = None
        elif kind == 1 and thin:
            # A thin sheet transmits along the reflection mirrored through it.
            d = sum(a * b for a, b in zip(wi, m))
            wo = [2 * d * mc - w for mc, w in zip(m, wi)]
            wo[2] = -wo[2]
            if wo[2] * side >= -0.01:
                wo = None
        elif kind == 1 and transmits:
            rel = eta if side > 0 else 1.0 / eta
            wo = refract(wi, m, rel)
            if wo is not None and wo[2] * side >= -0.01:
                wo = None
        if wo is None:
            wo = sphere(rng)
        out.append((wi, unit(wo)))
    return out


def interaction(wi, uv, lams):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.uv = mi.Point2f(uv)
    si.wavelengths = mi.UnpolarizedSpectrum(lams)
    return si


def eval_queries(xml, transmits, rng):
    bsdf = mi.load_string(xml)
    ctx = mi.BSDFContext()
    rows = []
    for wi, wo in queries(rng, transmits, eta_of(xml), "principledthin" in xml):
        lams = sorted(rng.uniform(380.0, 780.0) for _ in range(4))
        uv = [rng.random(), rng.random()]
        si = interaction(wi, uv, lams)
        v = bsdf.eval(ctx, si, mi.Vector3f(wo))
        pdf = bsdf.pdf(ctx, si, mi.Vector3f(wo))
        f = [float(v[k]) / abs(wo[2]) for k in range(4)]
        rows.append({"wi": wi, "wo": wo, "uv": uv, "lambdas_nm": lams, "f": f, "pdf": float(pdf)})
    return rows


def albedos(xml, transmits, rng):
    bsdf = mi.load_string(xml)
    ctx = mi.BSDFContext()
    rows = []
    sides = [1.0, -1.0] if transmits else [1.0]
    for side in sides:
        for theta in ALBEDO_THETAS:
            t = math.radians(theta)
            wi = [math.sin(t) * math.cos(0.3), math.sin(t) * math.sin(0.3), side * math.cos(t)]
            si = interaction(wi, [0.25, 0.25], [550.0] * 4)
            s1 = s2 = 0.0
            for _ in range(ALBEDO_SAMPLES):
                bs, w = bsdf.sample(ctx, si, rng.random(), mi.Point2f(rng.random(), rng.random()))
                x = float(w[0]) if bs.pdf > 0 else 0.0
                s1 += x
                s2 += x * x
            mean = s1 / ALBEDO_SAMPLES
            var = max(s2 / ALBEDO_SAMPLES - mean * mean, 0.0)
            rows.append({"wi": wi, "uv": [0.25, 0.25], "lambda_nm": 550.0, "albedo": mean,
                         "std_error": math.sqrt(var / ALBEDO_SAMPLES)})
            print(f"{theta} {side}: {mean}", file=sys.stderr)
    return rows


def main():
    mi.set_variant("scalar_spectral")
    rng = random.Random(465)
    out = {
        "generator": "Mitsuba 3.9.1 (crates/gonio-core/benches/mitsuba_principled_values.py): "
                     "eval/pdf at four wavelengths and albedo (2^20 samples, 550 nm) in scalar_spectral",
        "conventions": "local frame, z = normal, x = tangent; f excludes |cos θo|; pdf per solid "
                       "angle; albedo = mean sample weight (reflection + transmission) with its "
                       "standard error",
        "configs": [],
    }
    for name, xml, transmits, swapped in CONFIGS:
        print(name, file=sys.stderr)
        out["configs"].append({"name": name, "xml": xml, "transmits": transmits,
                               "eval_1_swapped": swapped,
                               "eval": eval_queries(xml, transmits, rng),
                               "albedo": albedos(xml, transmits, rng)})
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
