"""Mitsuba 3.9.1 `scalar_spectral_polarized` reference Mueller matrices (issue 12 §4), written to
`testdata/mitsuba/reference/mitsuba-polarized-values.json` and checked by
`crates/gonio-render/tests/mitsuba_polarized_values.rs` (a module of `mitsuba_bsdf_values.rs`).

For each configuration (a `<bsdf>` XML string gonio's reader loads too) and query:

* `eval` rows: Mitsuba's `bsdf.eval(ctx, si, wo)` divided by |cos θo| (f without the cosine), a
  4x4 Mueller matrix at one wavelength, in the local frame (si.sh_frame = identity, normal +z);
* `sample` rows: `bsdf.sample(ctx, si, sample1, sample2)`: the direction, pdf and Mueller weight.

`polarizer`, `retarder` and `circular` are straight-through filters (wo = -wi), sampled from
both sides. Mitsuba returns BSDF Mueller matrices from the implicit Stokes basis of the incident beam
(`mueller.stokes_basis(-wo_hat)`) to that of the outgoing one (`stokes_basis(wi_hat)`), with
light arriving along -wo_hat and leaving along wi_hat (wo_hat = wo, wi_hat = wi in radiance mode,
swapped in importance mode). gonio's `eval_mueller`/`sample_mueller` use the same bases, so
matrices compare element by element. `M[r][c]` is row r, column c.

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_polarized_values.py > \
        testdata/mitsuba/reference/mitsuba-polarized-values.json
"""
import json
import math
import random

import mitsuba as mi

mi.set_variant("scalar_spectral_polarized")

X = '<bsdf version="3.0.0" type="{}">{}</bsdf>'
CONFIGS = [
    ("conductor-eta0.2-k3.9", X.format("conductor", '<spectrum name="eta" value="0.2"/><spectrum name="k" value="3.9"/>'), "sample"),
    ("conductor-Au", X.format("conductor", '<string name="material" value="Au"/>'), "sample"),
    ("conductor-none-tinted", X.format("conductor", '<spectrum name="specular_reflectance" value="0.6"/>'), "sample"),
    ("dielectric-1.5", X.format("dielectric", '<float name="int_ior" value="1.5"/>'), "sample"),
    ("dielectric-1.33-tinted", X.format("dielectric", '<float name="int_ior" value="1.33"/><spectrum name="specular_transmittance" value="0.7"/>'), "sample"),
    ("dielectric-2.4-ext1.2", X.format("dielectric", '<float name="int_ior" value="2.4"/><float name="ext_ior" value="1.2"/>'), "sample"),
    ("diffuse-0.5", X.format("diffuse", '<spectrum name="reflectance" value="0.5"/>'), "eval"),
    ("diffuse-0.9", X.format("diffuse", '<spectrum name="reflectance" value="0.9"/>'), "eval"),
    ("diffuse-0.2", X.format("diffuse", '<spectrum name="reflectance" value="0.2"/>'), "eval"),
    ("roughconductor-beckmann-0.1", X.format("roughconductor", '<spectrum name="eta" value="0.2"/><spectrum name="k" value="3.9"/>'), "eval"),
    ("roughconductor-ggx-0.3-Au", X.format("roughconductor", '<string name="material" value="Au"/><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/>'), "eval"),
    ("roughconductor-ggx-aniso", X.format("roughconductor", '<string name="distribution" value="ggx"/><float name="alpha_u" value="0.4"/><float name="alpha_v" value="0.1"/><spectrum name="eta" value="1.1"/><spectrum name="k" value="6.8"/>'), "eval"),
    ("roughdielectric-beckmann-0.1", X.format("roughdielectric", '<float name="int_ior" value="1.5"/><float name="alpha" value="0.1"/>'), "eval"),
    ("roughdielectric-ggx-0.3", X.format("roughdielectric", '<float name="int_ior" value="1.33"/><string name="distribution" value="ggx"/><float name="alpha" value="0.3"/>'), "eval"),
    ("roughdielectric-ggx-0.5-tinted", X.format("roughdielectric", '<float name="int_ior" value="1.7"/><string name="distribution" value="ggx"/><float name="alpha" value="0.5"/><spectrum name="specular_transmittance" value="0.8"/>'), "eval"),
    ("plastic-default", X.format("plastic", ''), "both"),
    ("plastic-1.9-red", X.format("plastic", '<float name="int_ior" value="1.9"/><spectrum name="diffuse_reflectance" value="0.3"/>'), "both"),
    ("plastic-nonlinear", X.format("plastic", '<boolean name="nonlinear" value="true"/><spectrum name="diffuse_reflectance" value="0.8"/>'), "both"),
    ("roughplastic-beckmann-0.1", X.format("roughplastic", '<float name="alpha" value="0.1"/>'), "eval"),
    ("roughplastic-ggx-0.3", X.format("roughplastic", '<string name="distribution" value="ggx"/><float name="alpha" value="0.3"/><spectrum name="diffuse_reflectance" value="0.2"/>'), "eval"),
    ("polarizer-0", X.format("polarizer", ''), "sample"),
    ("polarizer-30-t0.7", X.format("polarizer", '<float name="theta" value="30"/><spectrum name="transmittance" value="0.7"/>'), "sample"),
    ("polarizer-nonpolarizing", X.format("polarizer", '<float name="theta" value="60"/><boolean name="polarizing" value="false"/>'), "sample"),
    ("retarder-quarter-wave", X.format("retarder", ''), "sample"),
    ("retarder-45-half-wave", X.format("retarder", '<float name="theta" value="45"/><float name="delta" value="180"/>'), "sample"),
    ("retarder-30-60", X.format("retarder", '<float name="theta" value="-30"/><float name="delta" value="60"/><spectrum name="transmittance" value="0.9"/>'), "sample"),
    ("circular-right", X.format("circular", ''), "sample"),
    ("circular-left-0.8", X.format("circular", '<boolean name="left_handed" value="true"/><spectrum name="transmittance" value="0.8"/>'), "sample"),
    ("roughplastic-ggx-0.05-1.6", X.format("roughplastic", '<string name="distribution" value="ggx"/><float name="alpha" value="0.05"/><float name="int_ior" value="1.6"/>'), "eval"),
    ("pplastic-default", X.format("pplastic", ''), "both"),
    ("pplastic-ggx-0.3-1.6", X.format("pplastic", '<string name="distribution" value="ggx"/><float name="alpha" value="0.3"/><float name="int_ior" value="1.6"/><spectrum name="diffuse_reflectance" value="0.2"/>'), "eval"),
    ("pplastic-beckmann-aniso-tinted", X.format("pplastic", '<float name="alpha_u" value="0.3"/><float name="alpha_v" value="0.05"/><spectrum name="specular_reflectance" value="0.7"/><spectrum name="diffuse_reflectance" value="0.8"/>'), "eval"),
    ("pplastic-ggx-0.05-all-normals", X.format("pplastic", '<string name="distribution" value="ggx"/><float name="alpha" value="0.05"/><boolean name="sample_visible" value="false"/><float name="ext_ior" value="1.33"/>'), "both"),
]
WAVELENGTHS = [450.0, 550.0, 650.0]


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def sphere_dir(rng, zmin, zmax):
    z = rng.uniform(zmin, zmax)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(max(0.0, 1.0 - z * z))
    return [r * math.cos(phi), r * math.sin(phi), z]


def interaction(wi, lam):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.uv = mi.Point2f(0.5, 0.5)
    si.wavelengths = mi.UnpolarizedSpectrum(lam)
    return si


def matrix(m, scale=1.0):
    return [[float("%.8g" % (float(m[r, c][0]) * scale)) for c in range(4)] for r in range(4)]


def ctx_for(mode):
    ctx = mi.BSDFContext()
    if mode == "importance":
        ctx.mode = mi.TransportMode.Importance
    return ctx


def eval_rows(bsdf, name, rng):
    rows = []
    transmissive = name.startswith("roughdielectric")
    for k in range(8):
        wi = sphere_dir(rng, 0.05, 1.0)
        if transmissive and k >= 4:
            if k >= 6:
                wi[2] = -wi[2]  # incidence from inside
            wo = sphere_dir(rng, -1.0, -0.05) if wi[2] > 0 else sphere_dir(rng, 0.05, 1.0)
        elif k < 4:
            # near the specular lobe
            m = unit([rng.gauss(0, 0.15), rng.gauss(0, 0.15), 1.0])
            d = sum(a * b for a, b in zip(wi, m))
            wo = unit([2 * d * mc - w for mc, w in zip(m, wi)])
            if wo[2] <= 0.05:
                wo = sphere_dir(rng, 0.05, 1.0)
        else:
            wo = sphere_dir(rng, 0.05, 1.0)
        mode = "importance" if k % 3 == 2 else "radiance"
        lam = WAVELENGTHS[k % 3]
        si = interaction(wi, lam)
        ctx = ctx_for(mode)
        m = bsdf.eval(ctx, si, mi.Vector3f(wo))
        rows.append({"kind": "eval", "mode": mode, "wi": wi, "wo": wo, "lambda_nm": lam,
                     "M": matrix(m, 1.0 / abs(wo[2]))})
    return rows


def sample_rows(bsdf, name, rng):
    rows = []
    thetas = [0.0, 30.0, 56.3, 75.0, 89.0]
    for k, th in enumerate(thetas + [20.0, 45.0, 60.0, 80.0]):
        t = math.radians(th)
        phi = rng.uniform(0, 2 * math.pi)
        wi = [math.sin(t) * math.cos(phi), math.sin(t) * math.sin(phi), math.cos(t)]
        if k >= len(thetas):
            wi[2] = -wi[2]  # from inside (dielectrics: TIR beyond the critical angle)
            if not name.startswith(("dielectric", "polarizer", "retarder", "circular")):
                continue
        for s1 in (0.01, 0.99):
            mode = "importance" if (k + int(s1 > 0.5)) % 3 == 2 else "radiance"
            lam = WAVELENGTHS[k % 3]
            si = interaction(wi, lam)
            bs, w = bsdf.sample(ctx_for(mode), si, s1, mi.Point2f(0.3, 0.7))
            if bs.pdf <= 0:
                continue
            rows.append({"kind": "sample", "mode": mode, "wi": wi, "lambda_nm": lam, "sample1": s1,
                         "sample2": [0.3, 0.7], "wo": [float(c) for c in bs.wo],
                         "pdf": float(bs.pdf), "M": matrix(w)})
    return rows


def main():
    rng = random.Random(12)
    out = {
        "generator": "Mitsuba 3.9.1 scalar_spectral_polarized "
                     "(crates/gonio-core/benches/mitsuba_polarized_values.py)",
        "conventions": "local frame, normal +z; M[row][col]; eval rows are f without the cosine; "
                       "bases: implicit Stokes bases of -wo_hat (input) and wi_hat (output)",
        "configs": [],
    }
    for name, xml, kind in CONFIGS:
        bsdf = mi.load_string(xml)
        rows = []
        if kind in ("eval", "both"):
            rows += eval_rows(bsdf, name, rng)
        if kind in ("sample", "both"):
            rows += sample_rows(bsdf, name, rng)
        out["configs"].append({"name": name, "xml": xml, "rows": rows})
    # One row per line: small diffs when regenerated.
    configs = out.pop("configs")
    head = json.dumps(out, indent=1)[:-2]
    parts = []
    for c in configs:
        rows = ",\n   ".join(json.dumps(r) for r in c["rows"])
        parts.append('  {"name": %s, "xml": %s, "rows": [\n   %s]}' % (json.dumps(c["name"]), json.dumps(c["xml"]), rows))
    print(head + ',\n "configs": [\n' + ",\n".join(parts) + "\n ]\n}")


if __name__ == "__main__":
    main()
