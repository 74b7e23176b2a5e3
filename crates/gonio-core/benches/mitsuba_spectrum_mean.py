"""Mitsuba 3.9.1's `mean()` of spectra and what it decides: the sampling weight between the
lobes of `plastic`, `roughplastic` and `pplastic` (s_mean / (d_mean + s_mean)), seen in their
pdf. Written to `testdata/mitsuba/reference/mitsuba-spectrum-mean.json`, checked by
`crates/gonio-render/tests/mitsuba_bsdf_values.rs` (the pdfs) and `gonio-core`'s
`spectra::tests` (the means).

A spectrum given as wavelength:value pairs averages over its own range (Mitsuba's `irregular`
and `regular`), an RGB reflectance over 16 wavelengths from 360 to 830 nm (`srgb_model_mean`).
pdf queries are in `scalar_spectral` with all four wavelengths equal, si.wi = wi (local frame).

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_spectrum_mean.py > \
        testdata/mitsuba/reference/mitsuba-spectrum-mean.json
"""
import json

import mitsuba as mi

mi.set_variant("scalar_spectral")

PAIRS = "400:0.393418, 500:0.27199, 600:0.83903, 700:0.507508"
MEANS = [
    ("irregular", {"type": "irregular", "wavelengths": "400, 500, 600, 700",
                   "values": "0.393418, 0.27199, 0.83903, 0.507508"}),
    ("srgb-0.2-0.5-0.8", {"type": "srgb", "color": [0.2, 0.5, 0.8]}),
    ("srgb-0.9-0.1-0.05", {"type": "srgb", "color": [0.9, 0.1, 0.05]}),
]
SPECTRUM = f'<spectrum name="diffuse_reflectance" value="{PAIRS}"/>'
CONFIGS = [
    ("plastic", f'<bsdf version="3.0.0" type="plastic">{SPECTRUM}'
                '<float name="int_ior" value="2.04542"/><float name="ext_ior" value="1.29404"/></bsdf>'),
    ("roughplastic", f'<bsdf version="3.0.0" type="roughplastic">{SPECTRUM}'
                     '<string name="distribution" value="ggx"/><float name="alpha" value="0.3"/></bsdf>'),
    ("pplastic", f'<bsdf version="3.0.0" type="pplastic">{SPECTRUM}'
                 '<float name="alpha" value="0.2"/></bsdf>'),
]
# (wi, wo, nm): one oblique incidence, and a direction in the diffuse lobe away from the specular peak.
QUERIES = [((-0.99094, 0.13303, 0.018459), (0.78348, -0.011990, 0.62130), 500.0),
           ((0.3, 0.1, 0.9486833), (-0.5, 0.4, 0.7681146), 620.0)]


def pdf(bsdf, wi, wo, nm):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi)
    si.wavelengths = mi.Spectrum([nm] * 4)
    si.uv = mi.Point2f(0.5, 0.5)
    return float(bsdf.pdf(mi.BSDFContext(), si, mi.Vector3f(wo)))


out = {
    "generator": "crates/gonio-core/benches/mitsuba_spectrum_mean.py",
    "mitsuba": mi.__version__,
    "means": [{"name": n, "mean": float(mi.load_dict(d).mean())} for n, d in MEANS],
    "configs": [
        {"name": n, "xml": xml,
         "pdf": [{"wi": list(wi), "wo": list(wo), "lambda_nm": nm,
                  "pdf": pdf(mi.load_string(xml), wi, wo, nm)} for wi, wo, nm in QUERIES]}
        for n, xml in CONFIGS
    ],
}
print(json.dumps(out, indent=1))
