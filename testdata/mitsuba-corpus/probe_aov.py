#!/usr/bin/env python3
"""Prints what Mitsuba 3.9.1 `scalar_spectral` writes for the `aov` and `moment` integrators on
the known scene of `crates/gonio-render/tests/layers.rs` (a rectangle in the plane z = 1 before
a two-triangle OBJ square in the plane z = -4, a pinhole at z = 5, 6 x 4 pixels, box filter):
the channel names of several integrator set-ups, and, at 1 and 4 spp, the per-pixel AOV values
that are constant over each plane (normals, dp/du, dp/dv, duv/dx, duv/dy), the values the test
compares with.

Usage (from this folder): nice python3 probe_aov.py
"""
import os

import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")
here = os.path.dirname(os.path.abspath(__file__))
quad = os.path.join(here, "..", "..", "crates", "gonio-render", "tests", "data", "aov_quad.obj")


def scene(integrator, spp=1, fmt="rgb"):
    return f'''<scene version="3.0.0">
 {integrator}
 <sensor type="perspective"><float name="fov" value="40"/>
  <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
  <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
  <film type="hdrfilm"><integer name="width" value="6"/><integer name="height" value="4"/>
   <string name="pixel_format" value="{fmt}"/><rfilter type="box"/></film></sensor>
 <shape type="sphere"><transform name="to_world"><translate x="10"/></transform></shape>
 <shape type="rectangle"><transform name="to_world"><translate z="1"/><scale x="0.8" y="3"/></transform></shape>
 <shape type="obj"><string name="filename" value="{quad}"/>
  <transform name="to_world"><translate z="-1"/><scale value="4"/></transform></shape>
 <emitter type="constant"/>
</scene>'''


def render(integrator, spp=1, fmt="rgb"):
    s = mi.load_string(scene(integrator, spp, fmt))
    mi.render(s, spp=spp)
    b = s.sensors()[0].film().bitmap(raw=False)
    return [f.name for f in b.struct_()], np.array(b)


ALL = ("d:depth, p:position, uv:uv, ng:geo_normal, ns:sh_normal, dpdu:dp_du, dpdv:dp_dv, "
       "dx:duv_dx, dy:duv_dy, prim:prim_index, shape:shape_index")
setups = {
    "aov, direct b, path a": f'<integrator type="aov"><string name="aovs" value="{ALL}"/>'
                             '<integrator type="direct" name="b"/><integrator type="path" name="a"/></integrator>',
    "aov, unnamed path": '<integrator type="aov"><string name="aovs" value="d:depth"/><integrator type="path"/></integrator>',
    "moment, path p, depth d": '<integrator type="moment"><integrator type="path" name="p"/>'
                               '<integrator type="depth" name="d"/></integrator>',
    "moment of aov": '<integrator type="moment"><integrator type="aov" name="x"><string name="aovs" value="dd:depth"/>'
                     '<integrator type="path" name="p"/></integrator></integrator>',
    "aov of moment": '<integrator type="aov"><string name="aovs" value="dd:depth"/><integrator type="moment" name="m">'
                     '<integrator type="path" name="p"/></integrator></integrator>',
}
for k, v in setups.items():
    print(k, render(v)[0])
print("moment, rgba film", render(setups["moment, path p, depth d"], fmt="rgba")[0])

np.set_printoptions(linewidth=160, precision=5, suppress=True)
for spp in (1, 4):
    names, a = render(f'<integrator type="aov"><string name="aovs" value="{ALL}"/></integrator>', spp)
    d = a[..., names.index("d.T")]
    for plane, sel in (("rectangle (z = 1)", np.abs(d - 4.0) < 0.2), ("square (z = -4)", d > 9.0)):
        print(f"spp {spp}, {plane}: {sel.sum()} pixels")
        for n in ["ng.X", "ng.Y", "ng.Z", "ns.Z", "dpdu.X", "dpdu.Y", "dpdv.X", "dpdv.Y", "dx.U", "dx.V", "dy.U", "dy.V",
                  "prim.I"]:
            v = a[..., names.index(n)][sel]
            print(f"  {n}: min {v.min():.6f} max {v.max():.6f}")

# `sample_border` on the two-plane scene of `sample_border_feeds_the_edge_pixels_through_the_filter`:
# the mean depth of the two left columns without and with the border (the test's closed form:
# the far plane's depth minus 0.28125 and 0.03125 with it).
for border in ("false", "true"):
    s = mi.load_string(f'''<scene version="3.0.0">
 <integrator type="aov"><string name="aovs" value="dd:depth"/></integrator>
 <sensor type="orthographic">
  <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
  <sampler type="independent"><integer name="sample_count" value="1024"/></sampler>
  <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
   <boolean name="sample_border" value="{border}"/><rfilter type="tent"><float name="radius" value="2"/></rfilter></film></sensor>
 <shape type="rectangle"><transform name="to_world"><scale x="5" y="5"/><translate x="-6"/></transform></shape>
 <shape type="rectangle"><transform name="to_world"><scale x="5" y="5"/><translate x="4" z="-1"/></transform></shape>
</scene>''')
    mi.render(s, spp=1024)
    b = s.sensors()[0].film().bitmap(raw=False)
    d = np.array(b)[..., [f.name for f in b.struct_()].index("dd.T")]
    print(f"sample_border {border}: far-plane depth {d[4, 4]:.5f}, columns 0, 1: {d[:, 0].mean():.5f} {d[:, 1].mean():.5f}")
