#!/usr/bin/env python3
"""Prints Mitsuba 3.9.1's ray hits on straight test curves (`scalar_spectral`), the expected
values of `crates/gonio-render/tests/xml_mesh.rs` (`curves::*_matches_mitsuba`).

Usage: python3 probe_curves.py
"""
import os
import tempfile

import mitsuba as mi

mi.set_variant("scalar_spectral")

STRAIGHT = "0 0 0 0.1\n1 0 0 0.1\n2 0 0 0.1\n3 0 0 0.1\n4 0 0 0.1\n"
GROWING = "0 0 0 0.1\n1 0 0 0.2\n2 0 0 0.1\n"
RAYS = [
    ((1.5, 0, 5), (0, 0, -1)), ((1.5, 5, 0), (0, -1, 0)), ((1.5, 0, -5), (0, 0, 1)),
    ((0.5, 0, 5), (0, 0, -1)), ((2.5, 0, 5), (0, 0, -1)), ((1.05, 0, 5), (0, 0, -1)),
    ((0.25, 0, 5), (0, 0, -1)), ((0.75, 0, 5), (0, 0, -1)), ((1.0, 0, 5), (0, 0, -1)),
    ((-0.05, 0, 5), (0, 0, -1)), ((0.95, 0, 5), (0, 0, -1)), ((3.05, 0, 5), (0, 0, -1)),
    ((4.05, 0, 5), (0, 0, -1)), ((-5, 0, 0), (1, 0, 0)),
]

with tempfile.TemporaryDirectory() as d:
    for name, text in [("straight", STRAIGHT), ("growing", GROWING)]:
        path = os.path.join(d, name + ".txt")
        with open(path, "w") as f:
            f.write(text)
        for ty in ["linearcurve", "bsplinecurve"]:
            if ty == "bsplinecurve" and name == "growing":
                continue
            scene = mi.load_dict({"type": "scene", "c": {"type": ty, "filename": path}})
            for o, dv in RAYS:
                si = scene.ray_intersect(mi.Ray3f(mi.Point3f(*o), mi.Vector3f(*dv)))
                if si.is_valid():
                    print(f"{ty} {name} o={o} d={dv}: t={si.t:.6f} uv={list(si.uv)} n={list(si.n)}")
                else:
                    print(f"{ty} {name} o={o} d={dv}: miss")
