"""Mitsuba 3.9.1's renders of `scene.xml` and `inward.xml` (its `ptracer`, the only Mitsuba
integrator that sees a `directionalarea` emitter), the references of
`crates/gonio-render/tests/directional_area.rs`.

    python make_reference.py [variant] [spp] [seed] [output] [scene]

Defaults: `scalar_spectral`, 16384 spp, seed 7, `mitsuba-ptracer-16384spp.exr` of `scene.xml`
(about a minute on one core); `inward.xml`'s is `mitsuba-inward-ptracer-16384spp.exr` (the same
settings, `... 16384 7 mitsuba-inward-ptracer-16384spp.exr inward.xml`). Seeds 1 and 2 at 64 spp
give Mitsuba's own noise level (block relMSE 7.6e-6 against the reference at 16384 spp).
"""
import sys
import time
from pathlib import Path

import mitsuba as mi

here = Path(__file__).resolve().parent
variant = sys.argv[1] if len(sys.argv) > 1 else "scalar_spectral"
spp = int(sys.argv[2]) if len(sys.argv) > 2 else 16384
seed = int(sys.argv[3]) if len(sys.argv) > 3 else 7
out = sys.argv[4] if len(sys.argv) > 4 else str(here / f"mitsuba-ptracer-{spp}spp.exr")
scene_file = sys.argv[5] if len(sys.argv) > 5 else "scene.xml"

mi.set_variant(variant)
scene = mi.load_file(str(here / scene_file), spp=spp, integrator="ptracer")
start = time.time()
image = mi.render(scene, seed=seed)
print(f"{spp} spp in {time.time() - start:.1f} s")
mi.Bitmap(image).write(out)
