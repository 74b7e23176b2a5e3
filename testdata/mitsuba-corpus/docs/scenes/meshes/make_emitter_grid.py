#!/usr/bin/env python3
"""Writes `emitter_grid.ply`: a 4 x 4 grid of quads (32 triangles) over [-1, 1]^2 in the
z = 0 plane, normals +z, with three attributes as Mitsuba's PLY reader names them:

* `vertex_color` (properties `color_0..2`, floats): from orange-red (x = -1) to blue (x = 1),
  green rising with y, every component inside (0.1, 0.95);
* `vertex_one` (property `one_0`): 0.75 at every vertex (a constant);
* `face_weight` (face property `weight_0`): a ramp 0.2 .. 1 over the faces.

Written here with numpy (Mitsuba 3.9.1's `Mesh.write_ply` in a spectral variant stores a colour
attribute as its spectral coefficients, which its own reader then takes for RGB).

Usage (from this folder, docs/scenes/meshes): python3 make_emitter_grid.py
"""

import numpy as np

n = 4
xs = np.linspace(-1.0, 1.0, n + 1)
v = np.array([[x, y, 0.0] for y in xs for x in xs], dtype=np.float32)
faces = []
for j in range(n):
    for i in range(n):
        a = j * (n + 1) + i
        faces += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
faces = np.array(faces, dtype=np.int32)
t = (v[:, 0] + 1) / 2
s = (v[:, 1] + 1) / 2
color = np.stack([0.9 - 0.7 * t, 0.2 + 0.5 * s, 0.2 + 0.7 * t], axis=1).astype(np.float32)
one = np.full((len(v), 1), 0.75, dtype=np.float32)
normal = np.tile(np.array([0.0, 0.0, 1.0], dtype=np.float32), (len(v), 1))
weight = np.linspace(0.2, 1.0, len(faces)).astype(np.float32)

header = "\n".join([
    "ply",
    "format binary_little_endian 1.0",
    f"element vertex {len(v)}",
    "property float x", "property float y", "property float z",
    "property float nx", "property float ny", "property float nz",
    "property float one_0",
    "property float color_0", "property float color_1", "property float color_2",
    f"element face {len(faces)}",
    "property list uchar int vertex_indices",
    "property float weight_0",
    "end_header",
]) + "\n"
with open("emitter_grid.ply", "wb") as f:
    f.write(header.encode("ascii"))
    f.write(np.hstack([v, normal, one, color]).astype("<f4").tobytes())
    for tri, w in zip(faces, weight):
        f.write(np.uint8(3).tobytes() + tri.astype("<i4").tobytes() + np.float32(w).astype("<f4").tobytes())
print(len(v), "vertices,", len(faces), "faces")
