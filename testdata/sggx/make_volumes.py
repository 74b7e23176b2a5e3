"""Writes the six-channel `.vol` grids of `scene.xml` (the matrices of its two `sggx` media).

`flakes.vol`: 2 × 2 × 2 samples of one matrix, diag(0.05, 0.05, 1) turned 30 degrees about x
(flakes facing about +z: a surface-like medium). `fibres.vol`: 4 × 4 × 4 samples going along
x from fibres along y, S = I − 0.95·y yᵀ, to flakes facing x, S = diag(1, 0.05, 0.05), by
linear blending of the matrices (positive definite throughout). `density.vol`: 2 × 2 × 2
samples of 4, the heterogeneous medium's extinction (a number would do for gonio, but Mitsuba's
heterogeneous medium exists only inside the box of its `sigma_t` volume, for a number the unit
cube). `indefinite.vol`: one sample of diag(2, -1, -1) (determinant 2 > 0, but no SGGX
matrix), which gonio refuses. Every other eigenvalue is at most 1,
where Mitsuba 3.9.1's media and gonio's agree (see `plugins/phase/sggx.rs`).
"""
import math
import struct
from pathlib import Path

here = Path(__file__).resolve().parent


def write_vol(path, res, samples):
    nx, ny, nz = res
    channels = len(samples[0])
    with open(path, "wb") as f:
        f.write(b"VOL" + bytes([3]))
        f.write(struct.pack("<iiiii", 1, nx, ny, nz, channels))
        f.write(struct.pack("<6f", 0, 0, 0, 1, 1, 1))
        for s in samples:
            f.write(struct.pack(f"<{channels}f", *s))


def entries(m):
    return [m[0][0], m[1][1], m[2][2], m[0][1], m[0][2], m[1][2]]


def rotate_x(m, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    r = [[1, 0, 0], [0, c, -s], [0, s, c]]
    rt = [list(col) for col in zip(*r)]
    mul = lambda a, b: [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return mul(mul(r, m), rt)


flakes = entries(rotate_x([[0.05, 0, 0], [0, 0.05, 0], [0, 0, 1.0]], 30))
write_vol(here / "flakes.vol", (2, 2, 2), [flakes] * 8)

fibre_y = [[1, 0, 0], [0, 0.05, 0], [0, 0, 1]]
facing_x = [[1, 0, 0], [0, 0.05, 0], [0, 0, 0.05]]
samples = []
for k in range(4):
    for j in range(4):
        for i in range(4):
            t = i / 3
            m = [[(1 - t) * fibre_y[a][b] + t * facing_x[a][b] for b in range(3)] for a in range(3)]
            samples.append(entries(m))
write_vol(here / "fibres.vol", (4, 4, 4), samples)

write_vol(here / "density.vol", (2, 2, 2), [[4.0]] * 8)
write_vol(here / "indefinite.vol", (1, 1, 1), [[2.0, -1.0, -1.0, 0.0, 0.0, 0.0]])
