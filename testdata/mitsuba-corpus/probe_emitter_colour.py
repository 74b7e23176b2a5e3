#!/usr/bin/env python3
"""Prints the linear sRGB colour Mitsuba 3.9.1 assigns to the emission spectrum of its
`integrator_depth_*` scenes (`400:0, 500:8, 600:15.6, 700:18.4`, 0 outside): the CIE 1931
integral of the spectrum (Mitsuba's `cie1931_xyz`, 1 nm steps over 360-830 nm) divided by the
integral of y, then XYZ -> linear sRGB. This is the value a converged render shows where the
emitter fills a pixel; `tests/corpus_scenes.rs` (`directly_seen_emitter_is_its_cie_colour`)
compares gonio with it.

Usage: python3 probe_emitter_colour.py
"""
import mitsuba as mi
import numpy as np

mi.set_variant("scalar_spectral")
lam = np.arange(360, 831, 1.0)
s = np.interp(lam, [400, 500, 600, 700], [0, 8, 15.6, 18.4], left=0, right=0)
xyz = np.array([[float(c) for c in mi.cie1931_xyz(float(l))] for l in lam])
XYZ = (xyz * s[:, None]).sum(0) / xyz[:, 1].sum()
M = np.array([[3.240479, -1.537150, -0.498535],
              [-0.969256, 1.875991, 0.041556],
              [0.055648, -0.204043, 1.057311]])
print("linear sRGB", M @ XYZ)
