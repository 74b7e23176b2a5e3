#!/usr/bin/env python3
"""Relative variance per sample of next-event estimators at an unoccluded point of Mitsuba's
material-preview floor (normal +z) under `museum.exr` (the preview's `to_world`), by quadrature
over the map at 4 x 4 points per texel, the radiance interpolated bilinearly between texel
centres as gonio's lookup does. One light sample + one cosine-weighted BSDF sample.

Densities (gonio's `emitter/envmap_product.rs`, 8 x 8-texel tiles, the normal's octahedral cell
centre 2.7 degrees from +z):
  compensated : tile weight max(0, W(T) - c S(T)) * cos(tile centre), c half the cell's
                cosine-weighted mean; texel ∝ luminance * sin θ, uniform inside (what gonio does)
  exact       : tile weight W(T) * cos(tile centre), inside the tile ∝ the bilinear interpolant
                (what a bilinear warp inside each texel would add)
MIS: the power heuristic, or "whole" (the light's samples weight 1 wherever its density is
positive, the BSDF's where it is zero). Printed for the luminance and for each RGB channel (the
image's relMSE averages the channels): a density ∝ one luminance cannot follow all three
channels of a coloured map.

Usage: .venv-mitsuba/bin/python bench/envmap_floor_quadrature.py  (bench/RESULTS.md, 2026-12-05)
"""
import os
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
rgb = np.array(mi.Bitmap(os.path.join(ROOT, "testdata/mitsuba-corpus/common/textures/museum.exr")))[..., :3]
rgb = rgb.astype(np.float64)
H, W, _ = rgb.shape
# to_world of the preview's envmap: the matrix after a rotation by -180 degrees about y.
M = np.array([[-0.224951, -0.000001, -0.974370], [-0.974370, 0, 0.224951], [0, 1, -0.000001]]) @ np.diag([-1.0, 1.0, -1.0])


def dirs(u, v):
    th, ph = np.pi * v, 2 * np.pi * u
    return np.stack([np.sin(th) * np.sin(ph), np.cos(th), -np.sin(th) * np.cos(ph)], -1) @ M.T


S, TW, TH = 4, 8, 8
jj, ii = np.meshgrid(np.arange(H * S), np.arange(W * S), indexing="ij")
u, v = (ii + 0.5) / (W * S), (jj + 0.5) / (H * S)
d, sth = dirs(u, v), np.sin(np.pi * v)
x, y = u * W - 0.5, v * H - 0.5
x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
fx, fy = x - x0, y - y0


def bilinear(img):
    at = lambda i, j: img[np.clip(j, 0, H - 1), i % W]
    return at(x0, y0) * (1 - fx) * (1 - fy) + at(x0 + 1, y0) * fx * (1 - fy) + at(x0, y0 + 1) * (1 - fx) * fy + at(x0 + 1, y0 + 1) * fx * fy


lum_t = rgb @ np.array([0.2126, 0.7152, 0.0722])
dw = sth * (2 * np.pi / W) * (np.pi / H) / (S * S)
tj, ti = jj // S, ii // S
tile = (tj // TH) * (W // TW) + ti // TW
ntiles = (W // TW) * (H // TH)
gj, gi = np.meshgrid(np.arange(H), np.arange(W), indexing="ij")
sin_t = np.sin(np.pi * (gj + 0.5) / H)
w_t = lum_t * sin_t
tile_t = (gj // TH) * (W // TW) + gi // TW
Wt = np.bincount(tile_t.ravel(), w_t.ravel(), ntiles)
St = np.bincount(tile_t.ravel(), sin_t.ravel(), ntiles)
tcu = ((np.arange(ntiles) % (W // TW)) * TW + TW / 2) / W
tcv = ((np.arange(ntiles) // (W // TW)) * TH + TH / 2) / H
dT = dirs(tcu, tcv)

n = np.array([0.0, 0.0, 1.0])
nk = np.array([0.03125, 0.03125, 0.9375])
nk /= np.linalg.norm(nk)
cos = np.maximum(0, d @ n)
cosT = np.maximum(0, dT @ nk)
to_solid = 1 / (2 * np.pi**2 * np.maximum(sth, 1e-12))


def compensated():
    c = 0.5 * (Wt * cosT).sum() / (St * cosT).sum()
    PT = np.maximum(0, Wt - c * St) * cosT
    PT /= PT.sum()
    p_texel = PT[tile_t] * w_t / np.maximum(Wt[tile_t], 1e-30) * W * H
    return p_texel[tj, ti] * to_solid


def exact():
    g = bilinear(lum_t) * sth
    G = np.bincount(tile.ravel(), (g / (W * H * S * S)).ravel(), ntiles)
    PT = G * cosT
    PT /= PT.sum()
    return PT[tile] * g / np.maximum(G[tile], 1e-30) * to_solid


def relvar(f, pl, rule):
    pb = cos / np.pi
    I = (f * dw).sum()
    if rule == "power":
        wl = pl**2 / (pl**2 + pb**2 + 1e-300)
    else:
        wl = (pl > 0).astype(float)
    wb = 1 - wl
    var = 0.0
    for w, p in ((wl, pl), (wb, pb)):
        second = (np.where(p > 0, w**2 * f**2 / np.maximum(p, 1e-300), 0) * dw).sum()
        var += second - ((w * f * dw).sum()) ** 2
    return var / I**2


channels = [("luminance", bilinear(lum_t))] + [(c, bilinear(rgb[..., k])) for k, c in enumerate("RGB")]
for name, pl, rule in [("compensated, power heuristic", compensated(), "power"),
                       ("exact, power heuristic", exact(), "power"),
                       ("exact, whole", exact(), "whole")]:
    values = [relvar(L * cos / np.pi, pl, rule) for _, L in channels]
    print(f"{name:30s}" + "  ".join(f"{c} {r:.3f}" for (c, _), r in zip(channels, values)))
