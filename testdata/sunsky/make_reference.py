"""Mitsuba 3.9.1's `sunsky` radiance and a render, for gonio's tests (`tests/sunsky.rs`).

Writes `mitsuba-scene-4096spp.exr`: `scene.xml` rendered by `llvm_ad_spectral` at 4096 spp
(seed 0; about two minutes on two cores); and `mitsuba-values.json`: for each configuration (the plugin's XML parameters), Mitsuba's
world sun direction (`sun_direction`, read back through `mi.traverse`) and `eval` of the emitter
(`scalar_spectral`) for a set of world directions towards the sky and four wavelengths each:
random directions over the sphere, directions near the sun (inside and outside its disk), and
wavelengths over 360-830 nm with the model's own 320-720 nm grid points among them. Mitsuba
returns NaN at exactly 720 nm (the upper neighbour of the last grid point is read one past its
table); those values are written as null.

Usage: python make_reference.py [--values-only]   (with `mitsuba==3.9.1` importable and, for
the render, DRJIT_LIBLLVM_PATH set; seeds fixed)
"""
import json
import math
import os
import sys

import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_spectral", "scalar_spectral")
HERE = os.path.dirname(os.path.abspath(__file__))


def sph(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


# (name, XML parameters as (tag, name, value) triples)
CONFIGS = [
    ("default", []),
    ("dir_low_t1", [("vector", "sun_direction", sph(85.0, 30.0)), ("float", "turbidity", 1.0)]),
    ("dir_mid_t3", [("vector", "sun_direction", sph(55.0, -120.0))]),
    ("dir_high_t6.5_a0", [("vector", "sun_direction", sph(12.0, 200.0)), ("float", "turbidity", 6.5),
                          ("float", "albedo", 0.0)]),
    ("dir_t10_a1", [("vector", "sun_direction", sph(70.0, 10.0)), ("float", "turbidity", 10.0),
                    ("float", "albedo", 1.0)]),
    ("dir_rgb_albedo", [("vector", "sun_direction", sph(40.0, 75.0)), ("rgb", "albedo", [0.1, 0.5, 0.9]),
                        ("float", "turbidity", 2.2)]),
    ("scales_aperture", [("vector", "sun_direction", sph(30.0, 45.0)), ("float", "sun_scale", 0.5),
                         ("float", "sky_scale", 2.0), ("float", "sun_aperture", 5.0)]),
    ("complex_sun", [("vector", "sun_direction", sph(60.0, 100.0)), ("boolean", "complex_sun", True),
                     ("float", "turbidity", 4.0), ("float", "sun_aperture", 3.0)]),
    ("sun_off", [("vector", "sun_direction", sph(50.0, 0.0)), ("float", "sun_scale", 0.0)]),
    ("place_time", [("float", "latitude", 48.8566), ("float", "longitude", 2.3522), ("float", "timezone", 1.0),
                    ("integer", "year", 2023), ("integer", "month", 3), ("integer", "day", 21),
                    ("float", "hour", 9.0), ("float", "minute", 30.0), ("float", "second", 15.0)]),
    ("place_time_south", [("float", "latitude", -33.86), ("float", "longitude", 151.21), ("float", "timezone", 10.0),
                          ("integer", "year", 2001), ("integer", "month", 12), ("integer", "day", 24),
                          ("float", "hour", 17.25)]),
    ("y_up", [("float", "hour", 11.0), ("transform", "to_world", "rotate x=1 angle=-90")]),
    ("sun_below_horizon", [("float", "hour", 23.0)]),
]


def xml_of(params):
    out = []
    for tag, name, value in params:
        if tag == "vector":
            out.append(f'<vector name="{name}" x="{value[0]!r}" y="{value[1]!r}" z="{value[2]!r}"/>')
        elif tag == "rgb":
            out.append(f'<rgb name="{name}" value="{value[0]}, {value[1]}, {value[2]}"/>')
        elif tag == "boolean":
            out.append(f'<boolean name="{name}" value="{str(value).lower()}"/>')
        elif tag == "transform":
            axis, angle = value.split()[1:]
            out.append(f'<transform name="{name}"><rotate {axis.replace("=", "=" + chr(34))}" '
                       f'{angle.replace("=", "=" + chr(34))}"/></transform>')
        else:
            out.append(f'<{tag} name="{name}" value="{value!r}"/>')
    return out


def emitter_of(params):
    body = "\n        ".join(xml_of(params))
    scene = f"""<scene version="3.0.0">
    <emitter type="sunsky">
        {body}
    </emitter>
</scene>"""
    s = mi.load_string(scene)
    return s.emitters()[0], body


def render():
    mi.set_variant("llvm_ad_spectral")
    scene = mi.load_file(os.path.join(HERE, "scene.xml"), spp="4096")
    img = mi.render(scene, seed=0)
    mi.Bitmap(img).write(os.path.join(HERE, "mitsuba-scene-4096spp.exr"))
    mi.set_variant("scalar_spectral")


def main():
    if "--values-only" not in sys.argv:
        render()
    mi.set_variant("scalar_spectral")
    rng = np.random.default_rng(7)
    out = {"mitsuba": mi.__version__, "variant": mi.variant(), "configs": []}
    for name, params in CONFIGS:
        em, body = emitter_of(params)
        sun = list(map(float, mi.traverse(em)["sun_direction"]))
        dirs = []
        for _ in range(40):
            v = rng.normal(size=3)
            dirs.append(list(v / np.linalg.norm(v)))
        # Near the sun: inside and outside the disk, whose half-angle is sun_aperture / 2.
        aperture = dict((n, v) for _, n, v in params).get("sun_aperture", 0.5358)
        half = math.radians(aperture / 2)
        s = np.array(sun)
        t1 = np.cross(s, [0.3, 0.5, 0.8]); t1 /= np.linalg.norm(t1)
        for f in [0.0, 0.3, 0.7, 0.95, 1.05, 1.5, 3.0]:
            ang = f * half
            d = math.cos(ang) * s + math.sin(ang) * t1
            dirs.append(list(d / np.linalg.norm(d)))
        rows = []
        for d in dirs:
            lam = list(rng.uniform(360.0, 830.0, size=4))
            if len(rows) % 5 == 0:
                lam[0] = 400.0
                lam[1] = 720.0
            si = mi.SurfaceInteraction3f()
            si.wi = -mi.Vector3f(d)
            si.wavelengths = mi.UnpolarizedSpectrum(lam)
            v = em.eval(si)
            rows.append({"d": [float(x) for x in d], "lambda": [float(x) for x in lam],
                         "value": [float(x) if math.isfinite(float(x)) else None for x in v]})
        out["configs"].append({"name": name, "xml": body, "sun_direction": sun, "rows": rows})
    with open(os.path.join(HERE, "mitsuba-values.json"), "w") as f:
        json.dump(out, f, indent=1)
    print("wrote", len(out["configs"]), "configurations")


if __name__ == "__main__":
    main()
