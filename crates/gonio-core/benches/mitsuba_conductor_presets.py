"""Mitsuba 3.9.1 reflectance of every `conductor` `material` preset it loads, written to
`testdata/mitsuba/reference/mitsuba-conductor-presets.json` and checked by
`crates/gonio-core/tests/spectral.rs` (`every_mitsuba_conductor_preset_reflects_as_in_mitsuba`).

For each preset in Mitsuba's `data/ior` folder: the smooth conductor's sample weight (its Fresnel
reflectance, `scalar_spectral`) at incidence angles 0°, 60° and 85°, at wavelengths inside the
preset's table (Mitsuba evaluates wavelengths outside it to NaN) and inside 360–830 nm. Presets
that Mitsuba refuses to load (k ≡ 0: "no probability mass found") are listed as such.

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_conductor_presets.py > \
        testdata/mitsuba/reference/mitsuba-conductor-presets.json
"""
import json
import math
import os

import mitsuba as mi

mi.set_variant("scalar_spectral")
DIR = os.path.join(os.path.dirname(mi.__file__), "data", "ior")
ANGLES = [0.0, 60.0, 85.0]


def table_range(name):
    xs = []
    for line in open(os.path.join(DIR, name + ".eta.spd")):
        line = line.strip()
        if line and line[0] not in "#;":
            xs.append(float(line.split()[0]))
    return xs[0], xs[-1]


out = {"mitsuba": mi.__version__, "variant": "scalar_spectral", "angles_deg": ANGLES,
       "presets": {}, "refused": []}
for name in sorted({f.split(".")[0] for f in os.listdir(DIR)}, key=str.lower):
    try:
        bsdf = mi.load_dict({"type": "conductor", "material": name})
    except RuntimeError:
        out["refused"].append(name)
        continue
    lo, hi = table_range(name)
    lo, hi = max(lo, 360.0), min(hi, 830.0)
    lambdas = [lo + (hi - lo) * t for t in (0.0, 0.31, 0.57, 0.83, 1.0)]
    rows = []
    for l in lambdas:
        for a in ANGLES:
            si = mi.SurfaceInteraction3f()
            si.sh_frame = mi.Frame3f([0, 0, 1])
            si.wi = [math.sin(math.radians(a)), 0.0, math.cos(math.radians(a))]
            si.wavelengths = [l, l, l, l]
            _, w = bsdf.sample(mi.BSDFContext(), si, 0.5, [0.5, 0.5])
            rows.append([l, a, float(w[0])])
    out["presets"][name] = rows
print(json.dumps(out, indent=1))
