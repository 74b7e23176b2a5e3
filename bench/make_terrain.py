#!/usr/bin/env python3
"""Writes the mesh of the `terrain-1m` bench scene: a fractal heightfield of N x N quads split
into 2 N^2 triangles (N = 710 gives 1 008 200 triangles), binary little-endian PLY with vertex
normals, about 25 MB. The mesh is generated, not stored in git: `bench/bench.py` runs this
script when `bench/scenes/generated/terrain-1m.ply` is missing.

The height is a sum of octaves of rotated sine ridges (deterministic, no random numbers), so the
surface has detail at every scale down to a few triangles and both renderers load the same file.

Usage: python3 bench/make_terrain.py [--quads 710] [OUT.ply]
"""
import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_OUT = os.path.join(HERE, "scenes", "generated", "terrain-1m.ply")


def height(x, y):
    """Heightfield over [-1, 1]^2: octaves of rotated, phase-shifted ridges, amplitude halving."""
    z = np.zeros_like(x)
    amp, freq = 0.12, 2.0
    for k in range(9):
        a = 0.7 + 1.3 * k  # rotation of this octave's ridges
        u = x * np.cos(a) + y * np.sin(a)
        v = -x * np.sin(a) + y * np.cos(a)
        z += amp * np.sin(freq * u + 1.7 * k) * np.cos(0.8 * freq * v + 0.9 * k)
        amp *= 0.5
        freq *= 2.1
    return z


def terrain(n):
    """Vertices (float32 [(n+1)^2, 6]: position, normal) and faces (int32 [2 n^2, 3])."""
    s = np.linspace(-1.0, 1.0, n + 1)
    x, y = np.meshgrid(s, s, indexing="xy")
    z = height(x, y)
    # Normals from central differences of the heightfield (one-sided at the border).
    h = s[1] - s[0]
    dzdy, dzdx = np.gradient(z, h, h)
    nrm = np.stack([-dzdx, -dzdy, np.ones_like(z)], axis=-1)
    nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
    verts = np.concatenate([np.stack([x, y, z], axis=-1), nrm], axis=-1).reshape(-1, 6)
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    v00 = (j * (n + 1) + i).ravel()
    v10, v01 = v00 + 1, v00 + (n + 1)
    v11 = v01 + 1
    faces = np.concatenate([np.stack([v00, v10, v11], -1), np.stack([v00, v11, v01], -1)])
    return verts.astype("<f4"), faces.astype("<i4")


def write_ply(path, verts, faces):
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        "comment gonio bench/make_terrain.py\n"
        f"element vertex {len(verts)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        "property float nx\nproperty float ny\nproperty float nz\n"
        f"element face {len(faces)}\n"
        "property list uchar int vertex_indices\nend_header\n"
    )
    rec = np.empty(len(faces), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    rec["n"], rec["v"] = 3, faces
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(verts.tobytes())
        f.write(rec.tobytes())
    os.replace(tmp, path)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out", nargs="?", default=DEFAULT_OUT)
    p.add_argument("--quads", type=int, default=710)
    a = p.parse_args()
    verts, faces = terrain(a.quads)
    write_ply(a.out, verts, faces)
    print(f"{a.out}: {len(verts)} vertices, {len(faces)} triangles", file=sys.stderr)


if __name__ == "__main__":
    main()
