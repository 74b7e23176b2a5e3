"""Mitsuba 3.9.1 values that each pin down one behaviour, written to
`testdata/mitsuba/reference/mitsuba-spot-values.json`:

* `means`, `bitmaps`, `configs`: Mitsuba's `mean()` of spectra and what it decides, the sampling
  weight between the lobes of `plastic`, `roughplastic` and `pplastic` (s_mean / (d_mean +
  s_mean)), seen in their pdf (checked by `crates/gonio-render/tests/mitsuba_bsdf_values.rs`,
  `gonio-core`'s `spectra::tests` and `gonio-render`'s `texture::tests`);
* `widening`: the pdf of an anisotropic `roughdielectric` sampled with all normals whose one
  axis is nearly smooth, which Mitsuba widens after Walter et al. (checked by
  `crates/gonio-render/tests/mitsuba_roughdielectric_values.rs`).

A spectrum given as wavelength:value pairs averages over its own range (Mitsuba's `irregular`
and `regular`), an RGB reflectance over 16 wavelengths from 360 to 830 nm (`srgb_model_mean`),
a bitmap is the average of its texels' means (`bitmaps`: linear RGB texels written to a
float EXR and read back by the `bitmap` texture; checked by gonio-render's texture tests).
pdf queries are in `scalar_spectral` with all four wavelengths equal, si.wi = wi (local frame).

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_spot_values.py > \
        testdata/mitsuba/reference/mitsuba-spot-values.json
"""
import json
import os
import tempfile

import mitsuba as mi
import numpy as np

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
BITMAPS = [
    [[0.2, 0.5, 0.8], [0.9, 0.1, 0.05]],
    [[0.2, 0.5, 0.8], [0.9, 0.1, 0.05], [0.3, 0.3, 0.3], [0.0, 0.0, 0.0]],
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


# (xml, wi, wo, nm, mode): all-normal sampling of a strongly anisotropic rough dielectric.
WIDENING = [
    ('<bsdf version="3.0.0" type="roughdielectric"><float name="alpha_u" value="0.524235"/>'
     '<float name="alpha_v" value="0.00665571"/><boolean name="sample_visible" value="false"/>'
     '<string name="int_ior" value="pet"/><float name="ext_ior" value="2.03433"/></bsdf>',
     (0.24959, 0.95726, -0.14617), (-0.25842, -0.95319, -0.15701), 500.0),
    ('<bsdf version="3.0.0" type="roughdielectric"><string name="distribution" value="ggx"/>'
     '<float name="alpha_u" value="0.004"/><float name="alpha_v" value="0.3"/>'
     '<boolean name="sample_visible" value="false"/></bsdf>',
     (0.3, -0.2, 0.9327379), (-0.25, 0.3, -0.9205976), 550.0),
]


def unit(v):
    n = sum(c * c for c in v) ** 0.5
    return [c / n for c in v]


def bitmap_mean(texels):
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "t.exr")
        mi.Bitmap(np.array([texels], dtype=np.float32)).write(path)
        return float(mi.load_dict({"type": "bitmap", "filename": path}).mean())


out = {
    "generator": "crates/gonio-core/benches/mitsuba_spot_values.py",
    "mitsuba": mi.__version__,
    "means": [{"name": n, "mean": float(mi.load_dict(d).mean())} for n, d in MEANS],
    "bitmaps": [{"texels": t, "mean": bitmap_mean(t)} for t in BITMAPS],
    "widening": [{"xml": xml, "wi": unit(wi), "wo": unit(wo), "lambda_nm": nm,
                  "pdf": pdf(mi.load_string(xml), unit(wi), unit(wo), nm)} for xml, wi, wo, nm in WIDENING],
    "configs": [
        {"name": n, "xml": xml,
         "pdf": [{"wi": list(wi), "wo": list(wo), "lambda_nm": nm,
                  "pdf": pdf(mi.load_string(xml), wi, wo, nm)} for wi, wo, nm in QUERIES]}
        for n, xml in CONFIGS
    ],
}
print(json.dumps(out, indent=1))
