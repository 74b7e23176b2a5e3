"""Reference data for gonio's `measured_polarized` BSDF (Baek et al. 2020 pBRDF; Mitsuba 3
`src/bsdfs/measured_polarized.cpp`), made with Mitsuba 3.9.1.

What it makes (next to this script, in `testdata/measured_polarized/`):

* `synthetic.pbsdf`: a small synthetic pBRDF in Mitsuba's TensorFile format (the format of the
  KAIST pBRDF dataset files that `measured_polarized` reads);
* `mitsuba-values.json`: Mitsuba 3.9.1 `eval`/`pdf`/`sample` results for four `<bsdf>`
  configurations using that file, plus a few rows from the unpolarized `scalar_spectral` variant.

Run (needs `pip install mitsuba==3.9.1 numpy`; takes a few seconds):

    python3 testdata/measured_polarized/make_reference.py

It also prints a self-check (see below) and exits non-zero if it fails.

TensorFile layout (verified: our writer's bytes equal `mitsuba.tensor_io.write(..., align=8)` and
`mi.TensorFile` reports the dtypes/offsets/shapes we wrote; all integers little-endian):

    offset 0   12 bytes  magic  b"tensor_file\\0"
    offset 12  u8, u8    version 1, 0  (Mitsuba 3.9.1 only rejects a non-zero second byte)
    offset 14  u32       number of fields
    then per field, in file order (no padding inside the header):
               u16 name length, the UTF-8 name (no terminator), u16 ndim,
               u8 dtype (Mitsuba `Struct::Type`: UInt8=1 Int8=2 UInt16=3 Int16=4 UInt32=5
               Int32=6 UInt64=7 Int64=8 Float16=9 Float32=10 Float64=11),
               u64 absolute byte offset of the data, ndim x u64 shape
    then each field's data, C order (row-major), at its offset, each offset rounded up to a
    multiple of 8 (zero padding between fields).

Fields read by `measured_polarized` (field order in the file does not matter; we write
theta_h, theta_d, phi_d, wvls, M):
`theta_h`, `theta_d`, `phi_d`: float32, shape [1, N] (radians, increasing);
`wvls`: uint16, shape [5] (nm; the plugin always reads exactly 5 values);
`M`: float32, shape [n_phi_d, n_theta_d, n_theta_h, 5, 4, 4]; `M[..., i, j]` is the Mueller
element row i, column j. The plugin interpolates it with `Marginal2D<Float, 4, true>` whose 4
parameters are (phi_d, theta_d, theta_h, wavelength), phi_d outermost, and reads element (i, j)
at Point2f(j/3, i/3) of the 4x4 slice (x = column).

Rusinkiewicz convention of the plugin: with wo_hat = wo, wi_hat = si.wi in radiance mode (swapped
in importance mode), both rotated about z by -phi(wi_hat), h = normalize(wo_hat + wi_hat),
theta_h = acos(h.z), theta_d = acos(h . wo_hat), b = normalize(z x h), t = normalize(b x h),
phi_d = atan2(b . p, t . p) with p = the part of wo_hat orthogonal to h, normalized. (So the
"incident" direction of the parameterization is wo_hat, the direction light arrives from.)
`rusinkiewicz_to_dirs` below inverts this.

The synthetic grid (see `GRID_*`): phi_d 9 uniform nodes over [-pi, pi]; theta_d 7 non-uniform
nodes (0 12 25 40 55 70 90 deg); theta_h 7 non-uniform nodes denser near 0 (0 2.5 10 22.5 40
62.5 90 deg); wavelengths 450 500 550 600 650. Data per node (float64, stored float32):

    M = 0.25 * D_ggx(theta_h; alpha_w) * F(theta_d; eta_w + i k_w)        conductor Fresnel Mueller
        + kd_w / pi in M00 only                                            depolarizing diffuse
        + phi_d terms, all proportional to sin(theta_h) (so they vanish where phi_d is degenerate)
          and 2*pi-periodic (so the +-pi nodes hold equal values): M00 += 0.04 s (1+cos phi_d)
          (1+0.1w), M01 += 0.03 s sin phi_d, M10 += 0.015 s sin(2 phi_d), M12 += 0.02 s cos phi_d
        + asymmetry: M03 += 0.01 + 0.005 w, M20 += 0.006 sin(theta_d)
        + every element (i, j) += 0.001 (4 i + j + 1) (1 + 0.2 w)   so no two elements are equal
    F = [[a, b, 0, 0], [b, a, 0, 0], [0, 0, c, d], [0, 0, -d, c]] with a = (|rs|^2+|rp|^2)/2,
        b = (|rs|^2-|rp|^2)/2, c = Re(rs conj rp), d = Im(rs conj rp)   (Mitsuba's convention)

(w = wavelength index 0..4). Special nodes:
* NaN (whole 4x4 matrix, every wavelength, every phi_d), like the dataset's unreachable
  configurations: theta_d = 90 deg with theta_h >= 40 deg, and theta_h = 90 deg with
  theta_d >= 55 deg;
* negative M00 = -0.2 at theta_d = 90 deg and theta_h in {2.5, 10, 22.5} deg (every phi_d and
  wavelength; the other 15 elements keep the formula), to exercise the clamp M00 >= 0.

JSON layout and conventions: as `crates/gonio-core/benches/mitsuba_polarized_values.py`.
`configs` is a list of `{name, xml, rows, unpolarized_rows}`; the xml refers to the data as
`<string name="filename" value="synthetic.pbsdf"/>`, relative to this directory.
* eval rows `{kind: "eval", mode, wi, wo, lambda_nm, M, pdf, note}`: M = `bsdf.eval(ctx, si, wo)` /
  |cos theta_o| (a 4x4 Mueller matrix at one wavelength, `M[r][c]`, row r column c), pdf =
  `bsdf.pdf(ctx, si, wo)`; local frame, normal +z (si.sh_frame = identity). Bases: the implicit
  Mitsuba Stokes bases `stokes_basis(-wo_hat)` (input) and `stokes_basis(wi_hat)` (output).
  `note` says why the row exists ("random", "near-specular", "rus(...)" = built from
  Rusinkiewicz angles in degrees, "nan-touch", "m00-clamp", "below-horizon", ...).
* sample rows `{kind: "sample", mode, wi, lambda_nm, sample1, sample2, wo, pdf, M}`: from
  `bsdf.sample(ctx, si, sample1, sample2)`, M the sample weight (eval / pdf, cosine included).
  Rows whose sampled pdf is 0 (GGX reflection below the horizon) are left out.
* unpolarized rows `{mode, wi, wo, lambda_nm, value, note}`: the `scalar_spectral` variant's
  `bsdf.eval(ctx, si, wo)[0] / |cos theta_o|` (it interpolates only M00 and clamps it >= 0 but has
  no NaN -> 0 rule: where the polarized variant gives 0 because of NaN, this one returns NaN,
  stored as `null`).
All si.wavelengths are set to lambda_nm (Mitsuba carries 4 wavelengths; they are equal here).
Input directions are rounded to float32 first and stored as the shortest decimal of that float32,
and Mitsuba is evaluated at exactly those values (parse them as f32 to reproduce its inputs bit
for bit). Matrix entries, pdfs and values have 8 significant digits.

Behaviour worth knowing (seen in these runs, Mitsuba 3.9.1):
* wavelengths outside [450, 650] clamp to the end nodes (420 nm == 450 nm, 700 nm == 650 nm);
* a NaN node poisons the interpolation even with weight 0 (NaN * 0 = NaN), e.g. a NaN at the
  500 nm node also zeroes 450 nm and 550 nm queries (tried with a scratch file, not this one);
* exact mirror directions (wo.xy == -wi.xy exactly) give h = +z exactly, b = normalize(0) = NaN,
  phi_d = NaN, so the polarized variant returns the zero matrix and the unpolarized one NaN
  (rows "exact-mirror*"); a 1e-7 perturbation gives the normal, finite value;
* in-plane configurations have phi_d = 0 or +-pi; which sign of pi Mitsuba computes depends on
  rounding (+pi with wi_hat exactly at phi = 0, -pi for other azimuths), so the synthetic data
  is 2*pi-periodic in phi_d (the -pi and +pi nodes hold identical values).

Self-check (printed; verified when the files were made): (1) our bytes equal
`mitsuba.tensor_io.write(..., align=8)`, and `mi.TensorFile` reports the dtype codes, offsets and
shapes written and returns the float32 arrays bit for bit; (2) at 555 evaluations whose
directions are built to land on grid nodes (radiance mode, node wavelengths, interiors of the
phi_d/theta_d/theta_h axes), Mitsuba's matrix rotated back from the implicit Stokes bases to the
plugin's own frames (`xo_hat`/`xi_hat` of the source, re-derived here) equals the stored table
(M00 clamped >= 0) to 1e-5 relative (worst 3e-6); (3) for 135 in-plane node evaluations (wi_hat
and wo_hat in the xz plane, wi_hat at phi = 0, phi_d = 0 or +-pi) Mitsuba's matrix, without any
un-rotation, equals diag(1,-1,-1,1) M_table diag(1,-1,-1,1) (the plugin's in-plane x axes and
Mitsuba's implicit bases differ by 90 degrees there); (4) the unpolarized variant returns the
stored M00 at 260 node evaluations.
"""
import json
import math
import os
import random
import struct
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PBSDF = os.path.join(HERE, "synthetic.pbsdf")
JSON_OUT = os.path.join(HERE, "mitsuba-values.json")

# ---------------------------------------------------------------------------------------------
# Synthetic data
# ---------------------------------------------------------------------------------------------
DEG = math.pi / 180.0
GRID_PHI_D = np.linspace(-math.pi, math.pi, 9)
GRID_THETA_D = np.array([0.0, 12.0, 25.0, 40.0, 55.0, 70.0, 90.0]) * DEG
GRID_THETA_H = np.array([0.0, 2.5, 10.0, 22.5, 40.0, 62.5, 90.0]) * DEG
WVLS = np.array([450, 500, 550, 600, 650], dtype=np.uint16)
# Gold-like conductor constants, roughness and diffuse albedo per wavelength node.
ETA = [1.38, 0.94, 0.43, 0.25, 0.17]
KAPPA = [1.92, 1.84, 2.45, 2.98, 3.50]
ALPHA = [0.22, 0.25, 0.28, 0.31, 0.34]
KD = [0.05, 0.08, 0.12, 0.18, 0.25]


def fresnel_mueller(cos_i, eta, k):
    n = complex(eta, k)
    sin2 = 1.0 - cos_i * cos_i
    root = np.sqrt(n * n - sin2)
    rs = (cos_i - root) / (cos_i + root)
    rp = (n * n * cos_i - root) / (n * n * cos_i + root)
    a = 0.5 * (abs(rs) ** 2 + abs(rp) ** 2)
    b = 0.5 * (abs(rs) ** 2 - abs(rp) ** 2)
    x = rs * np.conj(rp)
    c, d = x.real, x.imag
    return np.array([[a, b, 0, 0], [b, a, 0, 0], [0, 0, c, d], [0, 0, -d, c]], dtype=np.float64)


def ggx_d(theta_h, alpha):
    c2, s2 = math.cos(theta_h) ** 2, math.sin(theta_h) ** 2
    return alpha * alpha / (math.pi * (alpha * alpha * c2 + s2) ** 2)


def make_table():
    npd, ntd, nth, nw = len(GRID_PHI_D), len(GRID_THETA_D), len(GRID_THETA_H), len(WVLS)
    m = np.zeros((npd, ntd, nth, nw, 4, 4), dtype=np.float64)
    for a, pd in enumerate(GRID_PHI_D):
        for b, td in enumerate(GRID_THETA_D):
            for c, th in enumerate(GRID_THETA_H):
                for w in range(nw):
                    s = math.sin(th)
                    v = 0.25 * ggx_d(th, ALPHA[w]) * fresnel_mueller(math.cos(td), ETA[w], KAPPA[w])
                    v[0, 0] += KD[w] / math.pi
                    v[0, 0] += 0.04 * s * (1 + math.cos(pd)) * (1 + 0.1 * w)
                    v[0, 1] += 0.03 * s * math.sin(pd)
                    v[1, 0] += 0.015 * s * math.sin(2 * pd)
                    v[1, 2] += 0.02 * s * math.cos(pd)
                    v[0, 3] += 0.01 + 0.005 * w
                    v[2, 0] += 0.006 * math.sin(td)
                    v += 0.001 * (np.arange(16).reshape(4, 4) + 1) * (1 + 0.2 * w)
                    m[a, b, c, w] = v
    # Negative intensity (measurement noise) at grazing theta_d: the plugin clamps M00 >= 0.
    m[:, 6, 1:4, :, 0, 0] = -0.2
    # Unreachable configurations: whole matrix NaN.
    m[:, 6, 4:, :, :, :] = np.nan
    m[:, 4:, 6, :, :, :] = np.nan
    return m.astype(np.float32)


def grids():
    return {
        "theta_h": GRID_THETA_H.astype(np.float32).reshape(1, -1),
        "theta_d": GRID_THETA_D.astype(np.float32).reshape(1, -1),
        "phi_d": GRID_PHI_D.astype(np.float32).reshape(1, -1),
        "wvls": WVLS,
        "M": make_table(),
    }


# ---------------------------------------------------------------------------------------------
# TensorFile writer (independent of mitsuba.tensor_io; checked against it below)
# ---------------------------------------------------------------------------------------------
DTYPE_CODE = {np.dtype(np.uint8): 1, np.dtype(np.int8): 2, np.dtype(np.uint16): 3,
              np.dtype(np.int16): 4, np.dtype(np.uint32): 5, np.dtype(np.int32): 6,
              np.dtype(np.uint64): 7, np.dtype(np.int64): 8, np.dtype(np.float16): 9,
              np.dtype(np.float32): 10, np.dtype(np.float64): 11}
ALIGN = 8


def tensor_file_bytes(fields):
    fields = {k: np.ascontiguousarray(v) for k, v in fields.items()}
    header = bytearray(b"tensor_file\0")
    header += struct.pack("<BBI", 1, 0, len(fields))
    offset_pos = {}
    for name, v in fields.items():
        label = name.encode("utf8")
        header += struct.pack("<H", len(label)) + label
        header += struct.pack("<HB", v.ndim, DTYPE_CODE[v.dtype])
        offset_pos[name] = len(header)
        header += struct.pack("<Q", 0)
        header += struct.pack("<" + "Q" * v.ndim, *v.shape)
    out = header
    for name, v in fields.items():
        pos = (len(out) + ALIGN - 1) // ALIGN * ALIGN
        out += b"\0" * (pos - len(out))
        struct.pack_into("<Q", out, offset_pos[name], pos)
        out += v.astype(v.dtype.newbyteorder("<")).tobytes(order="C")
    return bytes(out)


# ---------------------------------------------------------------------------------------------
# Directions
# ---------------------------------------------------------------------------------------------
def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def rusinkiewicz_to_dirs(phi_d, theta_d, theta_h, phi_h=0.0):
    """(wo_hat, wi_hat) whose plugin Rusinkiewicz angles are (phi_d, theta_d, theta_h)."""
    h = [math.sin(theta_h) * math.cos(phi_h), math.sin(theta_h) * math.sin(phi_h), math.cos(theta_h)]
    if theta_h == 0.0:
        b = [-math.sin(phi_h), math.cos(phi_h), 0.0]
    else:
        b = unit(cross([0.0, 0.0, 1.0], h))
    t = unit(cross(b, h))
    a = [math.cos(theta_d) * hc + math.sin(theta_d) * (math.cos(phi_d) * tc + math.sin(phi_d) * bc)
         for hc, tc, bc in zip(h, t, b)]
    a = unit(a)
    o = unit([2 * dot(a, h) * hc - ac for hc, ac in zip(h, a)])
    return a, o


def rows_dirs(mode, wo_hat, wi_hat):
    """JSON (wi, wo) for a mode, given the plugin's (wo_hat, wi_hat)."""
    return (wi_hat, wo_hat) if mode == "radiance" else (wo_hat, wi_hat)


def sphere_dir(rng, zmin, zmax):
    z = rng.uniform(zmin, zmax)
    phi = rng.uniform(0.0, 2.0 * math.pi)
    r = math.sqrt(max(0.0, 1.0 - z * z))
    return [r * math.cos(phi), r * math.sin(phi), z]


# ---------------------------------------------------------------------------------------------
# Mitsuba
# ---------------------------------------------------------------------------------------------
def load_mitsuba(variant):
    import mitsuba as mi
    mi.set_variant(variant)
    if HERE not in [str(p) for p in mi.file_resolver()]:
        mi.file_resolver().append(HERE)
    return mi


def interaction(mi, wi, lam):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(wi)
    si.n = mi.Normal3f(0, 0, 1)
    si.sh_frame = mi.Frame3f(si.n)
    si.uv = mi.Point2f(0.5, 0.5)
    si.wavelengths = mi.UnpolarizedSpectrum(lam)
    return si


def ctx_for(mi, mode):
    ctx = mi.BSDFContext()
    if mode == "importance":
        ctx.mode = mi.TransportMode.Importance
    return ctx


def g8(x):
    """~8 significant digits; NaN (only the unpolarized variant returns it) becomes null."""
    return None if math.isnan(x) else float("%.8g" % x)


def matrix(m, scale=1.0):
    return [[g8(float(m[r, c][0]) * scale) for c in range(4)] for r in range(4)]


def f32(x):
    """The float32 value Mitsuba's scalar variants compute with, as its shortest decimal."""
    return float(str(np.float32(x)))


def vec(v):
    """Directions are stored as float32 shortest decimals, and Mitsuba is given exactly these."""
    return [f32(c) for c in v]


X = '<bsdf version="3.0.0" type="measured_polarized"><string name="filename" value="synthetic.pbsdf"/>{}</bsdf>'
CONFIGS = [
    ("default", X.format("")),
    ("alpha_sample-0.02", X.format('<float name="alpha_sample" value="0.02"/>')),
    ("wavelength-550", X.format('<float name="wavelength" value="550"/>')),
    ("wavelength-575", X.format('<float name="wavelength" value="575"/>')),
]
EVAL_WAVELENGTHS = [450.0, 475.0, 520.0, 600.0, 650.0, 420.0, 700.0]


def eval_queries(rng):
    """(note, mode, wi, wo) list, the same for every config (wavelengths are added later)."""
    q = []
    modes = ["radiance", "radiance", "importance"]
    for k in range(6):  # near the specular direction
        wi = sphere_dir(rng, 0.15, 1.0)
        m = unit([rng.gauss(0, 0.12), rng.gauss(0, 0.12), 1.0])
        d = dot(wi, m)
        wo = unit([2 * d * mc - w for mc, w in zip(m, wi)])
        if wo[2] <= 0.05:
            wo = sphere_dir(rng, 0.05, 1.0)
        q.append(("near-specular", modes[k % 3], wi, wo))
    for k in range(6):  # random upper hemisphere
        q.append(("random", modes[(k + 1) % 3], sphere_dir(rng, 0.05, 1.0), sphere_dir(rng, 0.05, 1.0)))
    # Built from Rusinkiewicz angles (degrees): interior points, random azimuth of h.
    rus = [
        ("rus", "radiance", 37.0, 33.0, 6.0),
        ("rus", "importance", -120.0, 50.0, 30.0),
        ("rus", "radiance", 170.0, 20.0, 15.0),
        ("rus", "importance", -65.0, 47.0, 1.5),
        # interpolation touches a NaN node -> whole matrix 0
        ("nan-touch", "radiance", 90.0, 80.0, 30.0),     # theta_d in [70,90], theta_h in [22.5,40]
        ("nan-touch", "importance", 95.0, 60.0, 70.0),  # theta_h in [62.5,90], theta_d in [55,70]
        ("nan-touch", "radiance", -88.0, 70.5, 30.0),   # tiny weight on the theta_d = 90 nodes
        # next to the NaN nodes but not touching them
        ("nan-near", "radiance", 90.0, 69.0, 30.0),
        ("nan-near", "importance", 92.0, 60.0, 60.0),
        # interpolated M00 < 0 -> clamped to 0, the other 15 elements are not
        ("m00-clamp", "radiance", 90.0, 85.0, 15.0),
        ("m00-clamp", "importance", -90.0, 86.0, 8.0),
    ]
    for note, mode, pd, td, th in rus:
        wo_hat, wi_hat = rusinkiewicz_to_dirs(pd * DEG, td * DEG, th * DEG, rng.uniform(0, 2 * math.pi))
        wi, wo = rows_dirs(mode, wo_hat, wi_hat)
        q.append(("%s(phi_d=%g,theta_d=%g,theta_h=%g)" % (note, pd, td, th), mode, wi, wo))
    # Exact mirror configuration with wi in the xz plane: h = +z exactly, phi_d degenerate.
    s, c = math.sin(35 * DEG), math.cos(35 * DEG)
    q.append(("exact-mirror-in-plane", "radiance", [s, 0.0, c], [-s, 0.0, c]))
    wi = [0.5 * s, -math.sqrt(0.75) * s, c]
    q.append(("exact-mirror", "importance", wi, [-wi[0], -wi[1], wi[2]]))
    # In-plane, not mirror (phi_d = +-pi or 0).
    q.append(("in-plane", "importance", [0.6, 0.0, 0.8], [-0.28, 0.0, 0.96]))
    # Normal incidence (phi(wi_hat) = atan2(0, 0) = 0).
    q.append(("normal-incidence", "radiance", [0.0, 0.0, 1.0], unit([0.2, -0.3, 0.9])))
    # Below the horizon: eval and pdf are 0.
    q.append(("below-horizon-wi", "radiance", [0.3, 0.2, -0.932737905], unit([-0.3, -0.2, 0.9])))
    q.append(("below-horizon-wo", "importance", unit([0.1, 0.5, 0.7]), [-0.1, -0.5, -0.860232527]))
    return [(note, mode, vec(wi), vec(wo)) for note, mode, wi, wo in q]


def eval_rows(mi, bsdf, queries):
    rows = []
    for k, (note, mode, wi, wo) in enumerate(queries):
        lam = EVAL_WAVELENGTHS[k % len(EVAL_WAVELENGTHS)]
        si = interaction(mi, wi, lam)
        ctx = ctx_for(mi, mode)
        m = bsdf.eval(ctx, si, mi.Vector3f(wo))
        pdf = bsdf.pdf(ctx, si, mi.Vector3f(wo))
        rows.append({"kind": "eval", "mode": mode, "wi": vec(wi), "wo": vec(wo), "lambda_nm": lam,
                     "M": matrix(m, 1.0 / abs(wo[2])), "pdf": g8(float(pdf)), "note": note})
    return rows


def sample_rows(mi, bsdf, rng):
    rows = []
    sample2s = [[0.3, 0.7], [0.81, 0.12], [0.5, 0.5], [0.05, 0.95]]
    thetas = [0.0, 20.0, 45.0, 60.0, 75.0, 85.0]
    k = 0
    for th in thetas:
        t = th * DEG
        phi = rng.uniform(0, 2 * math.pi)
        wi = vec([math.sin(t) * math.cos(phi), math.sin(t) * math.sin(phi), math.cos(t)])
        for s1 in (0.04, 0.6):
            s2 = sample2s[k % len(sample2s)]
            mode = "importance" if k % 3 == 2 else "radiance"
            lam = EVAL_WAVELENGTHS[k % len(EVAL_WAVELENGTHS)]
            k += 1
            si = interaction(mi, wi, lam)
            bs, w = bsdf.sample(ctx_for(mi, mode), si, s1, mi.Point2f(s2))
            if not bs.pdf > 0:
                continue
            rows.append({"kind": "sample", "mode": mode, "wi": vec(wi), "lambda_nm": lam,
                         "sample1": s1, "sample2": s2, "wo": vec([float(c) for c in bs.wo]),
                         "pdf": g8(float(bs.pdf)), "M": matrix(w)})
    return rows


def unpolarized_rows(mi, bsdf, queries):
    rows = []
    for k, (note, mode, wi, wo) in enumerate(queries):
        if k % 2 == 1 and not note.startswith(("nan", "m00", "exact", "below")):
            continue
        lam = EVAL_WAVELENGTHS[(k + 3) % len(EVAL_WAVELENGTHS)]
        si = interaction(mi, wi, lam)
        v = bsdf.eval(ctx_for(mi, mode), si, mi.Vector3f(wo))
        rows.append({"mode": mode, "wi": vec(wi), "wo": vec(wo), "lambda_nm": lam,
                     "value": g8(float(v[0]) / abs(wo[2])), "note": note})
    return rows


# ---------------------------------------------------------------------------------------------
# Self-check
# ---------------------------------------------------------------------------------------------
def plugin_frames(wo_hat, wi_hat):
    """xo_hat, xi_hat of the plugin source (Stokes reference vectors of the table's matrix)."""
    phi_std = math.atan2(wi_hat[1], wi_hat[0])
    if phi_std < 0:
        phi_std += 2 * math.pi

    def rot(v, ang):
        cs, sn = math.cos(ang), math.sin(ang)
        return [v[0] * cs - v[1] * sn, v[0] * sn + v[1] * cs, v[2]]

    wo_std, wi_std = rot(wo_hat, -phi_std), rot(wi_hat, -phi_std)
    zo = [-c for c in wo_std]
    to = unit(cross([a - b for a, b in zip(wo_std, wi_std)], zo))
    yo = unit(cross(to, zo))
    xo = cross(yo, zo)
    zi = wi_std
    ti = unit(cross([a - b for a, b in zip(wi_std, wo_std)], zi))
    yi = unit(cross(ti, zi))
    xi = cross(yi, zi)
    return rot(xo, phi_std), rot(xi, phi_std)


def expected_node(table, a, b, c, w, polarized=True):
    v = table[a, b, c, w].astype(np.float64).copy()
    if np.isnan(v[0, 0]):
        return np.zeros((4, 4)) if polarized else None
    v[0, 0] = max(v[0, 0], 0.0)
    return v


def self_check(table):
    mi = load_mitsuba("scalar_spectral_polarized")
    bsdf = mi.load_string(CONFIGS[0][1])
    ok = True
    worst = 0.0
    n = 0
    ctx = mi.BSDFContext()
    # General nodes: un-rotate Mitsuba's result into the plugin's own frames.
    for a in range(1, len(GRID_PHI_D) - 1):
        for b in (1, 2, 3, 4):
            for c in (1, 2, 3, 4):
                wo_hat, wi_hat = rusinkiewicz_to_dirs(GRID_PHI_D[a], GRID_THETA_D[b], GRID_THETA_H[c],
                                                      0.3 + a + b + c)
                if wo_hat[2] < 0.05 or wi_hat[2] < 0.05:
                    continue
                xo, xi = plugin_frames(wo_hat, wi_hat)
                for w in range(5):
                    si = interaction(mi, wi_hat, float(WVLS[w]))
                    m = bsdf.eval(ctx, si, mi.Vector3f(wo_hat))
                    mw = mi.Vector3f(-np.array(wo_hat))
                    wi_v = mi.Vector3f(wi_hat)
                    back = mi.mueller.rotate_mueller_basis(
                        m, mw, mi.mueller.stokes_basis(mw), mi.Vector3f(xo),
                        wi_v, mi.mueller.stokes_basis(wi_v), mi.Vector3f(xi))
                    got = np.array([[float(back[r, col][0]) for col in range(4)] for r in range(4)]) / wo_hat[2]
                    exp = expected_node(table, a, b, c, w)
                    err = np.max(np.abs(got - exp)) / max(1.0, np.max(np.abs(exp)))
                    worst = max(worst, err)
                    n += 1
                    if err > 1e-5:
                        ok = False
                        print("MISMATCH node", a, b, c, w, err)
    print("self-check: %d node evaluations (un-rotated to the table's frames), worst rel. error %.2e" % (n, worst))
    # In-plane nodes: wi_hat in the xz plane at phi = 0, wo_hat in the xz plane.
    worst_ip = 0.0
    n_ip = 0
    flip = np.diag([1.0, -1.0, -1.0, 1.0])
    patterns = {"identity": 0, "rows/columns 1,2 negated": 0}
    for b in (1, 2, 3):
        for c in (1, 2, 3):
            for pd_index in (0, 4, 8):  # phi_d = -pi, 0, pi
                wo_hat, wi_hat = rusinkiewicz_to_dirs(GRID_PHI_D[pd_index], GRID_THETA_D[b], GRID_THETA_H[c], 0.0)
                rot_z = -math.atan2(wi_hat[1], wi_hat[0])  # put wi_hat at phi = 0 exactly
                cs, sn = math.cos(rot_z), math.sin(rot_z)
                wo_hat = [wo_hat[0] * cs - wo_hat[1] * sn, 0.0, wo_hat[2]]
                wi_hat = [wi_hat[0] * cs - wi_hat[1] * sn, 0.0, wi_hat[2]]
                if wo_hat[2] < 0.05 or wi_hat[2] < 0.05:
                    continue
                for w in range(5):
                    si = interaction(mi, wi_hat, float(WVLS[w]))
                    m = bsdf.eval(ctx, si, mi.Vector3f(wo_hat))
                    got = np.array([[float(m[r, col][0]) for col in range(4)] for r in range(4)]) / wo_hat[2]
                    exp = expected_node(table, pd_index, b, c, w)
                    # The in-plane basis change is a rotation by 0 or 90 degrees on both sides:
                    # identity, or rows and columns 1 and 2 negated.
                    scale = max(1.0, np.max(np.abs(exp)))
                    e_id = np.max(np.abs(got - exp)) / scale
                    e_fl = np.max(np.abs(got - flip @ exp @ flip)) / scale
                    patterns["identity" if e_id <= e_fl else "rows/columns 1,2 negated"] += 1
                    err = min(e_id, e_fl)
                    worst_ip = max(worst_ip, err)
                    n_ip += 1
                    if err > 1e-5:
                        ok = False
                        print("MISMATCH in-plane node", pd_index, b, c, w, err)
    print("self-check: %d in-plane node evaluations (no un-rotation), worst rel. error %.2e; "
          "basis change seen: %s" % (n_ip, worst_ip, patterns))
    same_pi = np.array_equal(table[0], table[-1], equal_nan=True)
    print("self-check: table at phi_d = -pi equals table at phi_d = +pi: %s" % same_pi)
    ok = ok and same_pi
    # Unpolarized variant: M00 at nodes.
    mi = load_mitsuba("scalar_spectral")
    bsdf = mi.load_string(CONFIGS[0][1])
    ctx = mi.BSDFContext()
    worst_u = 0.0
    n_u = 0
    for a in range(1, len(GRID_PHI_D) - 1):
        for b in (1, 3, 5):
            for c in (1, 3, 5):
                wo_hat, wi_hat = rusinkiewicz_to_dirs(GRID_PHI_D[a], GRID_THETA_D[b], GRID_THETA_H[c], 1.0 + a)
                if wo_hat[2] < 0.05 or wi_hat[2] < 0.05:
                    continue
                for w in range(5):
                    si = interaction(mi, wi_hat, float(WVLS[w]))
                    got = float(bsdf.eval(ctx, si, mi.Vector3f(wo_hat))[0]) / wo_hat[2]
                    exp = expected_node(table, a, b, c, w, polarized=False)
                    if exp is None:
                        continue
                    err = abs(got - exp[0, 0]) / max(1.0, abs(exp[0, 0]))
                    worst_u = max(worst_u, err)
                    n_u += 1
                    if err > 1e-5:
                        ok = False
                        print("MISMATCH unpolarized node", a, b, c, w, got, exp[0, 0])
    print("self-check: %d unpolarized node evaluations, worst rel. error %.2e" % (n_u, worst_u))
    return ok


# ---------------------------------------------------------------------------------------------
def main():
    fields = grids()
    data = tensor_file_bytes(fields)
    with open(PBSDF, "wb") as f:
        f.write(data)

    # Format check 1: byte-identical with Mitsuba's own Python writer.
    import tempfile
    import mitsuba as mi
    mi.set_variant("scalar_spectral_polarized")
    with tempfile.TemporaryDirectory() as tmp:
        ref = os.path.join(tmp, "ref.pbsdf")
        import contextlib
        import io
        with contextlib.redirect_stdout(io.StringIO()):
            mi.tensor_io.write(ref, align=ALIGN, **fields)
        with open(ref, "rb") as f:
            same = f.read() == data
    print("format check: bytes identical to mitsuba.tensor_io.write: %s" % same)
    # Format check 2: Mitsuba's C++ reader.
    tf = mi.TensorFile(PBSDF)
    for name, v in fields.items():
        fld = tf[name]
        # Field.shape() has no Python conversion in 3.9.1: read the shape from repr().
        shape_txt = repr(fld).split("shape = [")[1].split("]")[0]
        shape = [int(x) for x in shape_txt.split(",")]
        good = shape == list(v.shape) and fld.dtype.value == DTYPE_CODE[v.dtype]
        if v.dtype == np.float32:  # data as the C++ reader sees it
            back = np.array(fld.to(mi.ScalarTensorXf))
            good = good and np.array_equal(back, v, equal_nan=True)
        print("format check: %-7s dtype=%s (code %d) offset=%d shape=%s %s"
              % (name, fld.dtype, fld.dtype.value, fld.offset, shape, "ok" if good else "BAD"))
        same = same and good
    del tf

    ok = self_check(fields["M"]) and same

    rng = random.Random(2020)
    queries = eval_queries(rng)
    out = {
        "generator": "Mitsuba 3.9.1 scalar_spectral_polarized and scalar_spectral "
                     "(testdata/measured_polarized/make_reference.py)",
        "conventions": "local frame, normal +z; M[row][col]; eval rows are f without the cosine "
                       "(eval / |cos theta_o|), pdf = bsdf.pdf; sample rows: M = sample weight; "
                       "bases: implicit Stokes bases of -wo_hat (input) and wi_hat (output); "
                       "directions are float32 values; unpolarized value null = Mitsuba NaN; "
                       "filename relative to testdata/measured_polarized/",
        "configs": [],
    }
    mi = load_mitsuba("scalar_spectral_polarized")
    for name, xml in CONFIGS:
        bsdf = mi.load_string(xml)
        rows = eval_rows(mi, bsdf, queries)
        rows += sample_rows(mi, bsdf, random.Random(7))
        out["configs"].append({"name": name, "xml": xml, "rows": rows})
    mi = load_mitsuba("scalar_spectral")
    for cfg, (name, xml) in zip(out["configs"], CONFIGS):
        bsdf = mi.load_string(xml)
        cfg["unpolarized_rows"] = unpolarized_rows(mi, bsdf, queries)

    # One row per line: small diffs when regenerated.
    configs = out.pop("configs")
    head = json.dumps(out, indent=1)[:-2]
    parts = []
    for c in configs:
        rows = ",\n   ".join(json.dumps(r) for r in c["rows"])
        urows = ",\n   ".join(json.dumps(r) for r in c["unpolarized_rows"])
        parts.append('  {"name": %s, "xml": %s, "rows": [\n   %s],\n  "unpolarized_rows": [\n   %s]}'
                     % (json.dumps(c["name"]), json.dumps(c["xml"]), rows, urows))
    with open(JSON_OUT, "w") as f:
        f.write(head + ',\n "configs": [\n' + ",\n".join(parts) + "\n ]\n}\n")
    print("wrote %s (%d bytes) and %s (%d bytes)"
          % (PBSDF, os.path.getsize(PBSDF), JSON_OUT, os.path.getsize(JSON_OUT)))
    if not ok:
        print("SELF-CHECK FAILED")
        sys.exit(1)


if __name__ == "__main__":
    main()
