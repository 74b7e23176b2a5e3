"""Randomized sweep: gonio `bsdf eval` vs Mitsuba 3.9.1 (scalar_spectral) BSDF eval/pdf, on
random parameter sets of every BSDF plugin both have (beyond the fixed configurations the tests
keep), to find disagreements. Prints, per plugin, the number of queries, the largest relative
errors of f and pdf and how many exceed 1e-3; writes every query to --out. Not a test: the
known, documented departures (roughdielectric's widening below alpha 1e-2, spectra outside
their range for eta/k, our RGB uplifting table, float cancellation at grazing angles) show up
in it, and each large row is a place to look. Found on 2026-12-04: the mean() of pair
spectra (fixed) and principled's pdf inside an opaque material (documented).

    cargo build --release -p gonio
    nice .venv-mitsuba/bin/python crates/gonio-core/benches/mitsuba_sweep.py [--seed N]
        [--configs 20] [--pairs 50] [--only plugin,plugin] [--gonio target/release/gonio]
        [--out mitsuba-sweep.json]

Conventions (as crates/gonio-core/benches/mitsuba_*_values.py): Mitsuba si.wi = gonio wi, both in
the local frame (z = normal); f = Mitsuba eval / |cos θo| (gonio prints f without cosine); pdf per
solid angle; all four Mitsuba wavelengths set to the query's λ (gonio: SampledWavelengths::fixed);
transport mode alternates radiance / importance per query (gonio: --mode).
Directions are rounded to float32 and normalized (in double) before being sent to both.
plastic and roughplastic elements get `coat_averages="mitsuba"` in gonio's XML only.
"""
import argparse
import json
import math
import random
import subprocess
import sys

import numpy as np
import mitsuba as mi

GONIO = "target/release/gonio"  # --gonio
WAVELENGTHS = [380.0, 420.0, 500.0, 589.0, 650.0, 720.0, 780.0]
METALS = ["Au", "Cu", "Al", "Ag", "Cr", "none", "W", "Ni_palik", "TiN", "a-C", "Cu_palik", "Hg"]
NAMED_IOR = ["water", "bk7", "diamond", "acrylic glass", "polypropylene", "air", "ethanol", "pet", "sodium chloride"]


# ---------------------------------------------------------------- XML building
class B:
    """A bsdf element: type, list of (tag, name, value) params, nested children."""

    def __init__(self, type_, params=None, children=None):
        self.type = type_
        self.params = params or []
        self.children = children or []

    def xml(self, gonio, root=True):
        attrs = ' version="3.0.0"' if root else ""
        body = "".join('<%s name="%s" value="%s"/>' % p for p in self.params)
        if gonio and self.type in ("plastic", "roughplastic"):
            body += '<string name="coat_averages" value="mitsuba"/>'
        body += "".join(c.xml(gonio, False) for c in self.children)
        return '<bsdf%s type="%s">%s</bsdf>' % (attrs, self.type, body)


def fnum(x):
    return "%.6g" % x


def spec_value(rng, lo=0.0, hi=1.0):
    """A constant (float) spectrum, or sometimes a piecewise-linear spectrum (no uplifting)."""
    if rng.random() < 0.8:
        return ("spectrum", fnum(rng.uniform(lo, hi)))
    pts = [(l, rng.uniform(lo, hi)) for l in (400, 500, 600, 700)]
    return ("spectrum", ", ".join("%d:%s" % (l, fnum(v)) for l, v in pts))


def ior_pair(rng, allow_inverted=True, named=True):
    params = []
    if named and rng.random() < 0.3:
        params.append(("string", "int_ior", rng.choice([n for n in NAMED_IOR if n != "air"])))
    else:
        params.append(("float", "int_ior", fnum(rng.uniform(1.05, 2.5))))
    r = rng.random()
    if r < 0.3:
        pass  # default ext_ior (air)
    elif allow_inverted and r < 0.6:
        # ext_ior > int_ior (an inverted interface) or equal-ish
        params.append(("float", "ext_ior", fnum(rng.uniform(1.0, 2.8))))
    else:
        params.append(("float", "ext_ior", fnum(rng.uniform(1.0, 1.4))))
    return params


def alpha_params(rng, aniso_ok=True):
    def a():
        r = rng.random()
        if r < 0.15:
            return rng.uniform(0.005, 0.03)
        if r < 0.85:
            return rng.uniform(0.03, 0.7)
        return rng.uniform(0.7, 1.5)

    if aniso_ok and rng.random() < 0.5:
        return [("float", "alpha_u", fnum(a())), ("float", "alpha_v", fnum(a()))]
    if rng.random() < 0.15:
        return []  # default 0.1
    return [("float", "alpha", fnum(a()))]


def metal_params(rng):
    if rng.random() < 0.6:
        return [("string", "material", rng.choice(METALS))]
    p = []
    if rng.random() < 0.7:
        p.append(("spectrum", "eta", fnum(rng.uniform(0.05, 3.5))))
        p.append(("spectrum", "k", fnum(rng.uniform(0.0, 8.0))))
    else:
        p.append(("spectrum", "eta", "400:%s, 550:%s, 700:%s" % tuple(fnum(rng.uniform(0.1, 3)) for _ in range(3))))
        p.append(("spectrum", "k", "400:%s, 550:%s, 700:%s" % tuple(fnum(rng.uniform(0.5, 7)) for _ in range(3))))
    return p


def maybe(rng, p, item):
    return [item] if rng.random() < p else []


def gen_diffuse(rng):
    return B("diffuse", [("spectrum", "reflectance") + (spec_value(rng)[1],)] if rng.random() < 0.9 else [])


def gen_conductor(rng):
    return B("conductor", metal_params(rng) + maybe(rng, 0.3, ("spectrum", "specular_reflectance", fnum(rng.uniform(0.2, 1)))))


def gen_dielectric(rng):
    return B("dielectric", ior_pair(rng) + maybe(rng, 0.3, ("spectrum", "specular_reflectance", fnum(rng.uniform(0.2, 1))))
             + maybe(rng, 0.3, ("spectrum", "specular_transmittance", fnum(rng.uniform(0.2, 1)))))


def gen_thindielectric(rng):
    return B("thindielectric", ior_pair(rng) + maybe(rng, 0.3, ("spectrum", "specular_reflectance", fnum(rng.uniform(0.2, 1))))
             + maybe(rng, 0.3, ("spectrum", "specular_transmittance", fnum(rng.uniform(0.2, 1)))))


def gen_plastic(rng):
    p = [("spectrum", "diffuse_reflectance", spec_value(rng)[1])]
    p += ior_pair(rng, allow_inverted=False)
    p += maybe(rng, 0.5, ("boolean", "nonlinear", rng.choice(["true", "false"])))
    p += maybe(rng, 0.3, ("spectrum", "specular_reflectance", fnum(rng.uniform(0.2, 1))))
    return B("plastic", p)


def gen_roughconductor(rng):
    p = [("string", "distribution", rng.choice(["beckmann", "ggx"]))]
    p += alpha_params(rng)
    p += [("boolean", "sample_visible", rng.choice(["true", "false"]))]
    p += metal_params(rng)
    p += maybe(rng, 0.3, ("spectrum", "specular_reflectance", fnum(rng.uniform(0.2, 1))))
    return B("roughconductor", p)


def gen_roughdielectric(rng):
    p = [("string", "distribution", rng.choice(["beckmann", "ggx"]))]
    p += alpha_params(rng)
    p += [("boolean", "sample_visible", rng.choice(["true", "false"]))]
    p += ior_pair(rng, named=True)
    p += maybe(rng, 0.3, ("spectrum", "specular_reflectance", fnum(rng.uniform(0.2, 1))))
    p += maybe(rng, 0.3, ("spectrum", "specular_transmittance", fnum(rng.uniform(0.2, 1))))
    # avoid int_ior == ext_ior exactly (Mitsuba then has eta = 1)
    return B("roughdielectric", p)


def gen_roughplastic(rng):
    p = [("string", "distribution", rng.choice(["beckmann", "ggx"]))]
    p += alpha_params(rng, aniso_ok=False)
    p += [("boolean", "sample_visible", rng.choice(["true", "false"]))]
    p += [("boolean", "nonlinear", rng.choice(["true", "false"]))]
    p += [("spectrum", "diffuse_reflectance", spec_value(rng)[1])]
    p += ior_pair(rng, allow_inverted=False)
    p += maybe(rng, 0.3, ("spectrum", "specular_reflectance", fnum(rng.uniform(0.2, 1))))
    return B("roughplastic", p)


def gen_principled(rng):
    p = []
    if rng.random() < 0.8:
        p.append(("spectrum", "base_color", spec_value(rng)[1]))
    for name in ["roughness", "anisotropic", "metallic", "spec_trans", "spec_tint", "sheen",
                 "sheen_tint", "flatness", "clearcoat", "clearcoat_gloss"]:
        r = rng.random()
        if r < 0.15:
            continue  # default
        if r < 0.25:
            p.append(("float", name, rng.choice(["0", "1"])))
        else:
            p.append(("float", name, fnum(rng.uniform(0, 1))))
    r = rng.random()
    if r < 0.4:
        p.append(("float", "eta", fnum(rng.uniform(1.05, 2.5))))
    elif r < 0.55:
        p.append(("float", "eta", fnum(rng.uniform(0.5, 0.95))))
    elif r < 0.85:
        p.append(("float", "specular", fnum(rng.uniform(0.0, 1.5))))
    for name in ["diffuse_reflectance_sampling_rate", "main_specular_sampling_rate", "clearcoat_sampling_rate"]:
        if rng.random() < 0.4:
            p.append(("float", name, fnum(rng.uniform(0, 3))))
    return B("principled", p)


def gen_principledthin(rng):
    p = []
    if rng.random() < 0.8:
        p.append(("spectrum", "base_color", spec_value(rng)[1]))
    for name in ["roughness", "anisotropic", "spec_trans", "spec_tint", "sheen", "sheen_tint", "flatness"]:
        r = rng.random()
        if r < 0.15:
            continue
        if r < 0.25:
            p.append(("float", name, rng.choice(["0", "1"])))
        else:
            p.append(("float", name, fnum(rng.uniform(0, 1))))
    if rng.random() < 0.8:
        p.append(("float", "diff_trans", fnum(rng.uniform(0, 2))))
    if rng.random() < 0.8:
        p.append(("float", "eta", fnum(rng.uniform(1.05, 2.5) if rng.random() < 0.8 else rng.uniform(0.6, 1.0))))
    for name in ["diffuse_reflectance_sampling_rate", "specular_reflectance_sampling_rate",
                 "specular_transmittance_sampling_rate", "diffuse_transmittance_sampling_rate"]:
        if rng.random() < 0.4:
            p.append(("float", name, fnum(rng.uniform(0, 3))))
    return B("principledthin", p)




def gen_principled_reflective(rng):
    b = gen_principled(rng)
    b.params = [p for p in b.params if p[1] != "spec_trans"]
    return b


def gen_twosided(rng):
    pool = [gen_diffuse, gen_roughconductor, gen_roughplastic, gen_plastic, gen_principled_reflective]
    n = rng.choice([1, 2])
    return B("twosided", [], [rng.choice(pool)(rng) for _ in range(n)])


def gen_blendbsdf(rng):
    pool = [gen_diffuse, gen_roughconductor, gen_roughplastic, gen_plastic, gen_roughdielectric,
            gen_principled, gen_principledthin]
    w = rng.choice([fnum(rng.uniform(0, 1)), fnum(rng.uniform(0, 1)), "0", "1"])
    return B("blendbsdf", [("float", "weight", w)], [rng.choice(pool)(rng), rng.choice(pool)(rng)])


GENERATORS = {
    "diffuse": gen_diffuse, "conductor": gen_conductor, "dielectric": gen_dielectric,
    "thindielectric": gen_thindielectric, "plastic": gen_plastic,
    "roughconductor": gen_roughconductor, "roughdielectric": gen_roughdielectric,
    "roughplastic": gen_roughplastic, "principled": gen_principled,
    "principledthin": gen_principledthin, "twosided": gen_twosided, "blendbsdf": gen_blendbsdf,
}


# ---------------------------------------------------------------- directions
def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def sphere_dir(rng, zlo, zhi, side=1):
    z = rng.uniform(zlo, zhi)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(max(0.0, 1.0 - z * z))
    return [r * math.cos(phi), r * math.sin(phi), side * z]


def refract(wi, m, eta):
    c = dot(wi, m)
    if c < 0:
        m, eta, c = [-x for x in m], 1.0 / eta, -c
    s2 = (1.0 - c * c) / (eta * eta)
    if s2 >= 1.0:
        return None
    ct = math.sqrt(1.0 - s2)
    return [-w / eta + (c / eta - ct) * mm for w, mm in zip(wi, m)]


def f32dir(v):
    v = unit(v)
    a = np.array(v, dtype=np.float32)
    return [float(x) for x in a]


def make_pairs(rng, n, eta_guess, transmissive_wi):
    out = []
    for i in range(n):
        # wi: mostly upper, grazing sometimes, lower for transmitting/two-sided models (and a few
        # for one-sided ones, which must give 0)
        r = rng.random()
        side = 1
        if rng.random() < (0.35 if transmissive_wi else 0.08):
            side = -1
        if r < 0.15:
            wi = sphere_dir(rng, 1e-4, 0.03, side)
        else:
            wi = sphere_dir(rng, 0.03, 1.0, side)
        kind = rng.random()
        spread = rng.choice([0.02, 0.1, 0.3])
        m = unit([rng.gauss(0, spread), rng.gauss(0, spread), 1.0])
        wo = None
        if kind < 0.3:
            d = dot(wi, m)
            wo = [2 * d * mc - w for mc, w in zip(m, wi)]
        elif kind < 0.45:
            wo = refract(wi, m, eta_guess)
        elif kind < 0.55:
            wo = sphere_dir(rng, 1e-4, 0.03, rng.choice([1, -1]))  # grazing wo
        elif kind < 0.7:
            wo = sphere_dir(rng, 0.0, 1.0, -side)  # other side
        if wo is None or abs(unit(wo)[2]) < 1e-5:
            wo = sphere_dir(rng, 0.0, 1.0, side)
        out.append((f32dir(wi), f32dir(wo)))
    return out


# ---------------------------------------------------------------- evaluation
def mitsuba_eval(bsdf, wi, wo, lam, mode):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.uv = mi.Point2f(0.5, 0.5)
    si.wavelengths = mi.UnpolarizedSpectrum(lam)
    ctx = mi.BSDFContext()
    if mode == "importance":
        ctx.mode = mi.TransportMode.Importance
    f = float(bsdf.eval(ctx, si, mi.Vector3f(wo))[0])
    pdf = float(bsdf.pdf(ctx, si, mi.Vector3f(wo)))
    c = abs(float(np.float32(wo[2])))
    f = f / c if c > 0 else f
    return f, pdf


def gonio_eval(xml, queries, mode):
    inp = "".join("%.9g %.9g %.9g %.9g %.9g %.9g %g\n" % (*wi, *wo, lam) for wi, wo, lam in queries)
    p = subprocess.run(["nice", GONIO, "bsdf", "eval", "--mode", mode, xml], input=inp,
                       capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError("gonio failed: %s\n%s" % (xml, p.stderr))
    rows = [tuple(float(x) for x in l.split()) for l in p.stdout.splitlines()]
    assert len(rows) == len(queries)
    return rows


def rel(g, m):
    if math.isnan(g) or math.isnan(m):
        return float("inf") if not (math.isnan(g) and math.isnan(m)) else 0.0
    return abs(g - m) / max(abs(m), 1e-6)


def eta_guess(b):
    for t, n, v in b.params:
        if n == "int_ior":
            try:
                return float(v)
            except ValueError:
                return 1.5
        if n == "eta":
            try:
                return float(v)
            except ValueError:
                pass
    return 1.5


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--configs", type=int, default=20)
    ap.add_argument("--pairs", type=int, default=50)
    ap.add_argument("--only", default="")
    ap.add_argument("--out", default="mitsuba-sweep.json")
    ap.add_argument("--gonio", default=GONIO)
    args = ap.parse_args()
    globals()["GONIO"] = args.gonio
    mi.set_variant("scalar_spectral")
    plugins = args.only.split(",") if args.only else list(GENERATORS)
    results = []
    for plugin in plugins:
        rng = random.Random("%d-%s" % (args.seed, plugin))
        for ci in range(args.configs):
            b = GENERATORS[plugin](rng)
            mxml, gxml = b.xml(False), b.xml(True)
            try:
                bsdf = mi.load_string(mxml)
            except Exception as e:
                print("mitsuba rejects %s: %s" % (mxml, str(e).splitlines()[-1][:200]), file=sys.stderr)
                continue
            transmissive = plugin in ("roughdielectric", "principled", "principledthin", "twosided",
                                      "blendbsdf", "dielectric", "thindielectric")
            pairs = make_pairs(rng, args.pairs, eta_guess(b), transmissive)
            queries = {"radiance": [], "importance": []}
            for k, (wi, wo) in enumerate(pairs):
                for lam in rng.sample(WAVELENGTHS, 2):
                    mode = "importance" if (k % 2) else "radiance"
                    queries[mode].append((wi, wo, lam))
            for mode, qs in queries.items():
                if not qs:
                    continue
                try:
                    grows = gonio_eval(gxml, qs, mode)
                except RuntimeError as e:
                    print(str(e), file=sys.stderr)
                    break
                for (wi, wo, lam), (gf, gp) in zip(qs, grows):
                    mf, mp = mitsuba_eval(bsdf, wi, wo, lam, mode)
                    results.append({"plugin": plugin, "config": ci, "mitsuba_xml": mxml, "gonio_xml": gxml,
                                    "wi": wi, "wo": wo, "lambda_nm": lam, "mode": mode,
                                    "f_mitsuba": mf, "f_gonio": gf, "pdf_mitsuba": mp, "pdf_gonio": gp,
                                    "rel_f": rel(gf, mf), "rel_pdf": rel(gp, mp)})
        print("done", plugin, file=sys.stderr)
    with open(args.out, "w") as f:
        json.dump(results, f)
    print("%-16s %6s %10s %10s %7s %7s" % ("plugin", "n", "max rel f", "max rel pdf", "f>1e-3", "pdf>1e-3"))
    for plugin in plugins:
        rs = [r for r in results if r["plugin"] == plugin]
        if rs:
            print("%-16s %6d %10.3g %10.3g %7d %7d" % (
                plugin, len(rs), max(r["rel_f"] for r in rs), max(r["rel_pdf"] for r in rs),
                sum(r["rel_f"] > 1e-3 for r in rs), sum(r["rel_pdf"] > 1e-3 for r in rs)))


if __name__ == "__main__":
    main()
