"""Reference data for gonio's `measured` BSDF (Dupuy & Jakob 2018, "An Adaptive Parameterization
for Efficient Material Acquisition and Rendering"; Mitsuba 3 `src/bsdfs/measured.cpp`), made with
Mitsuba 3.9.1, plus direct tests of the `Marginal2D<Float, D, true>` warps it is built on.

What it makes (next to this script, in `testdata/measured/`):

* `iso.bsdf`, `aniso.bsdf`: two small synthetic RGL material files (spectral format, Mitsuba's
  TensorFile container), filled from an analytic GGX model;
* `mitsuba-values.json`: Mitsuba 3.9.1 `scalar_spectral` eval / pdf / sample results for
  `<bsdf type="measured">` with each file;
* `marginal2d-values.json`: `mi.MarginalContinuous2D0/2/3` eval / sample / invert results on
  small tables.

Run (needs `pip install mitsuba==3.9.1 numpy`; a few seconds; deterministic):

    python3 testdata/measured/make_reference.py

It prints a self-check and exits non-zero if it fails. The self-check includes an independent
float64 re-implementation of Marginal2D (continuous) and of measured.cpp's eval/pdf/sample
(`PyMarginal2D`, `PyMeasured` below), compared with Mitsuba on every stored row; reading them is
the quickest way to see every convention.

TensorFile: the layout documented in `testdata/measured_polarized/make_reference.py` (writer
copied from there; bytes checked equal to `mitsuba.tensor_io.write(..., align=8)`).

RGL file fields (what measured.cpp reads and checks; field order in the file is free):
  description  uint8 [n]             free text
  jacobian     uint8 [1]             1: eval multiplies by ndf(u_m) / (4 sigma(u_wi))
  theta_i      float32 [n_theta_i]   radians, increasing (param 1 of vndf/luminance/spectra)
  phi_i        float32 [n_phi_i]     radians, increasing (param 0, slowest); <= 2 entries means
                                     isotropic (then phi_m is stored relative to phi_i)
  ndf          float32 [H_n, W_n]    D(m) over u_m: row index = u_phi, column index = u_theta
  sigma        float32 [H_n, W_n]    projected area sigma(wi) over u_wi, same axes
  vndf         float32 [n_phi_i, n_theta_i, H_v, W_v]  density over u_m (same axes), per incidence
  luminance    float32 [n_phi_i, n_theta_i, N, N]       density over the vndf's primary sample
                                                        space (x = column, y = row)
  spectra      float32 [n_phi_i, n_theta_i, n_wl, N, N] per wavelength, over the same space
  wavelengths  float32 [n_wl]        nm, increasing (param 2 of spectra)
Unit-square parameterization: theta = u_theta^2 pi/2, phi = (2 u_phi - 1) pi; a grid of n nodes
has node k at u = k/(n-1). Every 2-D grid is Marginal2D data of size (x = W = last axis,
y = H = second-to-last axis). Constructors used by measured.cpp (Mitsuba `Marginal2D(data, size,
param_res, param_values, normalize, enable_sampling)`):
  ndf, sigma:  Marginal2D<0>(.., normalize=false, enable_sampling=false)
  vndf, luminance: Marginal2D<2>(.., params (phi_i, theta_i), normalize=true, sampling on)
  spectra:     Marginal2D<3>(.., params (phi_i, theta_i, wavelengths), normalize=false, no sampling)
The two files deliberately use different grid sizes for ndf/sigma, vndf and luminance/spectra
(and non-square ndf/sigma/vndf grids) so that swapped axes or shared sizes show up; only
luminance/spectra must be square and equal (checked by measured.cpp); vndf may differ.

Synthetic data (see `make_material`): GGX D (alpha_u along x, alpha_v along y), sigma = cos(theta)
(1 + Lambda) = (cos theta + sqrt(cos^2 theta + alpha(phi)^2 sin^2 theta)) / 2, vndf = 2 pi^2 u_theta
sin(theta_m) <wi, m>+ D(m) / sigma(wi) (the RGL / Falcor acquisition formula), and at primary
sample-space node s, with u_m = vndf.sample(s) (Mitsuba's own warp built from our table) and wo the
reflection of wi about m:  spectra = (F_schlick(lambda, <wi, m>) G1(wo) + floor(lambda))
* (1 + 0.2 (s_y - 0.5)), G1 evaluated with wo.z clamped to >= 0.02 (so values stay positive when
wo is below the horizon). The (1 + 0.2 (s_y - 0.5)) tilt deliberately breaks the mirror symmetry
of the data so that mirror-image configurations give different values (sign conventions show up).
luminance = the wavelength average of spectra weighted by exp(-((lambda - 555)/70)^2 / 2).
With jacobian = 1, eval = spectra * D / (4 sigma) ~ F G1(wi) G1(wo) D / (4 cos theta_i), i.e. a
GGX-like f cos(theta_o).

mitsuba-values.json: {generator, conventions, configs: [{name: "iso" | "aniso", xml, rows}]}, one
row per line. The xml is `<bsdf version="3.0.0" type="measured"><string name="filename"
value="iso.bsdf"/></bsdf>` (filename relative to this directory). Rows, local frame (normal +z):
* `{kind: "eval", mode, wi, wo, lambda_nm, value, pdf, note}` (30 per config): value =
  `bsdf.eval(ctx, si, wo)[0]` as Mitsuba returns it, i.e. f * cos(theta_o) (the RGL data is
  defined with the cosine; measured.cpp does not multiply by it, and we do not divide by it);
  pdf = `bsdf.pdf(ctx, si, wo)`;
* `{kind: "sample", mode, wi, lambda_nm, sample1, sample2, wo, pdf, value, note}` (23 per config):
  `bsdf.sample(ctx, si, sample1, sample2)`, value = the weight (spec / pdf, or 0 when the sampled
  wo is below the horizon; pdf and wo are still reported then).
All 4 si.wavelengths = lambda_nm (Mitsuba's 4 samples, all equal; the 4 results are checked
equal). Directions are float32 values written as shortest decimals (parse as f32; -0.0 appears
and matters). `mode` has no effect on this plugin. 8 significant digits.

marginal2d-values.json: {generator, conventions, tables: [{name, class, dimension, size = [W, H],
param_res, param_values, normalize, data_shape = [param_res..., H, W], data (flat, row-major),
eval: [{pos, param, value}], sample: [{u, param, point, pdf}], invert: [{point, param, u, pdf}]}]}
(7 tables x 10 eval / 10 sample / 10 invert rows). Constructed with
`mi.MarginalContinuous2D0(data[H, W], [], normalize=...)` and
`mi.MarginalContinuous2D{2,3}(data, param_values, normalize)` (enable_sampling = true), which is
the C++ `Marginal2D<Float, D, true>(data, size = (W, H), param_res = data_shape[:D],
param_values, normalize, true)`.

Mitsuba 3.9.1 behaviour found here (all reproduced by PyMeasured / PyMarginal2D):
* Mirroring. m_reduction = rint(2 pi / (phi_i[-1] - phi_i[0])) for anisotropic files. If >= 2:
  sy = wi.y, sx = (m_reduction == 4 ? wi.x : sy), and wi.x, wi.y, wo.x, wo.y are replaced by
  mulsign_neg(., sx / sy), which flips the sign unless the SIGN BIT of sx / sy is set: +0 flips,
  -0 does not. So reduction 4 maps wi into x <= 0, y <= 0: phi_i must cover [-pi, -pi/2] (any
  other quarter is accepted silently, but then (almost) every lookup clamps to an end node of
  phi_i). Any other value >= 2 (2, 3, 5, ...) uses sx = sy: a 180-degree rotation unless wi.y
  has its sign bit set, i.e. into y <= 0 ([-pi, 0]); 0 or 1 do nothing. wo of sample() is
  mapped back with the same signs.
* For isotropic files (phi_i has <= 2 entries) m_reduction is never initialized (undefined
  behaviour). Instances behave either as "no mirroring" or as "rotate wi and wo by 180 degrees"
  (which one changes from load to load; a 4-fold mirror was never seen). The two agree to ~1e-7
  except at wi = (+0, +0, 1) exactly (phi_i = atan2(-0, -0) = 0 but wo rotated), and, for a file
  with 2 phi_i entries, everywhere. The stored rows come from a "no mirroring" instance and
  avoid wi = (+0, +0, 1) for iso; gonio should not mirror isotropic data.
* Dr.Jit's atan2 ignores the sign of zero: atan2(+-0, x < 0) = +pi, atan2(+-0, +-0) = 0. After
  the reduction-4 mirror, wi with y = 0 gets phi_i = +pi, which clamps to the LAST phi_i node
  (-pi/2), not to -pi; normal incidence gets phi_i = 0, also clamped to the last node.
* Isotropic files: phi_m is stored relative to phi_i (u_m.y = phi2u(phi_m - phi_i), wrapped by
  u - floor(u)); phi_i itself is still a Marginal2D parameter (ignored with 1 node).
* eval: wi, wo mirrored; m = normalize(wi + wo); theta via elevation() = 2 asin(|d - z| / 2);
  sample = vndf.invert(u_m, (phi_i, theta_i)); value = spectra.eval(sample, (phi_i, theta_i,
  lambda)) * ndf.eval(u_m) / (4 sigma.eval(u_wi)) (jacobian = 1). Parameters outside the node
  range clamp to the end node: wavelengths (350 nm gives exactly the 360 nm value, 1100 nm the
  1000 nm value), theta_i above 80 degrees (the u_m, u_wi lookups still use the true angles).
* pdf = vndf_pdf * luminance.eval(sample) / (max(2 pi^2 u_m.x sin(theta_m), 1e-6) * 4 <wi, m>).
  For the exact mirror direction (m = +z) u_m.x = 0 and the vndf density there is 0 (its
  u_theta = 0 column is 0), so pdf = 0 while eval is large.
* sample: sample1 is ignored; the 2-D sample is used as (sample2.y, sample2.x); luminance.sample
  then vndf.sample (both clamp their input to [2^-24, 1 - 2^-24]); the pdf can come out slightly
  negative when the interpolated vndf puts mass on back-facing m (<wi, m> < 0); the weight is
  then 0 because wo is below the horizon.
* No NaN in any stored row. Below-horizon wi or wo: eval 0, pdf 0; sample returns wo = 0,
  pdf 0, weight 0.
"""
import contextlib
import io
import json
import math
import os
import random
import struct
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
VALUES_JSON = os.path.join(HERE, "mitsuba-values.json")
MARGINAL_JSON = os.path.join(HERE, "marginal2d-values.json")
PI = math.pi
DEG = PI / 180.0


# ---------------------------------------------------------------------------------------------
# TensorFile writer and the query helpers (interaction, context): the ones of
# testdata/measured_polarized/make_reference.py
# ---------------------------------------------------------------------------------------------
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "measured_polarized"))
from make_reference import ALIGN, DTYPE_CODE, ctx_for, interaction, tensor_file_bytes  # noqa: E402


# ---------------------------------------------------------------------------------------------
# Small helpers
# ---------------------------------------------------------------------------------------------
def f32(x):
    """The float32 value Mitsuba's scalar variants compute with, as its shortest decimal."""
    return float(str(np.float32(x)))


def vec(v):
    return [f32(c) for c in v]


def g8(x):
    """~8 significant digits; NaN becomes null."""
    x = float(x)
    return None if math.isnan(x) else float("%.8g" % x)


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def sph(theta, phi):
    return [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]


def u2theta(u):
    return u * u * PI / 2


def u2phi(u):
    return (2 * u - 1) * PI


def theta2u(t):
    return math.sqrt(t * (2 / PI))


def phi2u(p):
    return (p + PI) / (2 * PI)


def sphere_dir(rng, zmin, zmax):
    z = rng.uniform(zmin, zmax)
    phi = rng.uniform(0.0, 2.0 * PI)
    r = math.sqrt(max(0.0, 1.0 - z * z))
    return [r * math.cos(phi), r * math.sin(phi), z]


def load_mitsuba():
    import mitsuba as mi
    mi.set_variant("scalar_spectral")
    return mi


@contextlib.contextmanager
def resolver_dir(mi, path):
    fr = mi.file_resolver()
    saved = [str(p) for p in fr]
    fr.prepend(path)
    try:
        yield
    finally:
        fr.clear()
        for p in saved:
            fr.append(p)


# ---------------------------------------------------------------------------------------------
# Independent re-implementation of Marginal2D<Float, D, Continuous=true> (float64 arithmetic on
# Mitsuba's float32 tables). data: ndarray [p0, ..., p_{D-1}, H, W]; params slowest-first.
# ---------------------------------------------------------------------------------------------
class PyMarginal2D:
    def __init__(self, data, param_values=(), normalize=True):
        data = np.asarray(data, dtype=np.float32)
        self.dim = data.ndim - 2
        self.h, self.w = data.shape[-2:]
        self.pv = [np.asarray(p, dtype=np.float32).astype(np.float64) for p in param_values]
        assert len(self.pv) == self.dim
        self.normalized = normalize
        h, w = self.h, self.w
        # strides (in slices) per parameter: last parameter fastest; 0 for a single node
        self.strides = [0] * self.dim
        slices = 1
        for i in range(self.dim - 1, -1, -1):
            self.strides[i] = slices if len(self.pv[i]) > 1 else 0
            slices *= len(self.pv[i])
        self.slices = slices
        sl = data.reshape(slices, h, w)
        sx, sy = 0.5 / (w - 1), 0.5 / (h - 1)
        self.data = np.zeros((slices, h * w), np.float32)
        self.marg = np.zeros((slices, h - 1), np.float32)
        self.cond = np.zeros((slices, h * (w - 1)), np.float32)
        for s in range(slices):
            d = sl[s].astype(np.float64)
            cond = np.zeros((h, w - 1), np.float32)
            rowsum = np.zeros(h)
            for y in range(h):
                acc = 0.0
                for x in range(w - 1):
                    acc += sx * (d[y, x] + d[y, x + 1])
                    cond[y, x] = acc
                rowsum[y] = acc
            marg = np.zeros(h - 1, np.float32)
            acc = 0.0
            for y in range(h - 1):
                acc += sy * (rowsum[y] + rowsum[y + 1])
                marg[y] = acc
            norm = np.float32(1.0 / acc) if normalize else np.float32(1.0)
            self.cond[s] = (cond * norm).reshape(-1)
            self.marg[s] = marg * norm
            self.data[s] = (sl[s] * norm).reshape(-1)
        self.data = self.data.reshape(-1).astype(np.float64)
        self.marg = self.marg.reshape(-1).astype(np.float64)
        self.cond = self.cond.reshape(-1).astype(np.float64)

    def _weights(self, param):
        """[(slice index, weight)] over the 2^D corners, as interpolate_weights + lookup."""
        corners = [(0, 1.0)]
        for d in range(self.dim):
            vals = self.pv[d]
            if len(vals) == 1:
                continue  # weight (1, 0), stride 0
            n = len(vals)
            # find_interval: first i in [1, n-1] with !(vals[i] < p), minus 1
            i = 1
            while i < n - 1 and vals[i] < param[d]:
                i += 1
            idx = i - 1
            p0, p1 = vals[idx], vals[idx + 1]
            w1 = min(max((param[d] - p0) / (p1 - p0), 0.0), 1.0)
            corners = [(s + self.strides[d] * (idx + b), wt * (w1 if b else 1.0 - w1))
                       for s, wt in corners for b in (0, 1)]
        return corners

    def _look(self, table, per_slice, corners, idx):
        return sum(wt * table[s * per_slice + idx] for s, wt in corners)

    def eval(self, pos, param=()):
        h, w = self.h, self.w
        c = self._weights(param)
        x = min(max(pos[0], 0.0), 1.0) * (w - 1)
        y = min(max(pos[1], 0.0), 1.0) * (h - 1)
        ox, oy = min(int(x), w - 2), min(int(y), h - 2)
        x -= ox
        y -= oy
        i = ox + oy * w
        L = lambda k: self._look(self.data, h * w, c, i + k)  # noqa: E731
        v00, v10, v01, v11 = L(0), L(1), L(w), L(w + 1)
        return (1 - y) * ((1 - x) * v00 + x * v10) + y * ((1 - x) * v01 + x * v11)

    @staticmethod
    def _sample_segment(s, inv_width, v0, v1):
        non_const = abs(v0 - v1) > 1e-4 * (v0 + v1)
        divisor = (v0 - v1) if non_const else (v0 + v1)
        s *= 2 * inv_width
        if non_const:
            s = v0 - math.sqrt(max(v0 * v0 + s * (v1 - v0), 0.0))
        if divisor != 0:
            s /= divisor
        return s

    @staticmethod
    def _invert_segment(s, width, v0, v1):
        return s * (v0 + (v1 - v0) * 0.5 * s) * width

    def sample(self, u, param=()):
        h, w = self.h, self.w
        c = self._weights(param)
        eps = 2.0 ** -24
        sx = min(max(u[0], eps), 1 - eps)
        sy = min(max(u[1], eps), 1 - eps)
        n_marg, n_cond = h - 1, h * (w - 1)
        fm = lambda k: self._look(self.marg, n_marg, c, k)  # noqa: E731
        if not self.normalized:
            sy *= fm(n_marg - 1)
        row = 0
        while row < n_marg - 1 and fm(row) < sy:
            row += 1
        if row > 0:
            sy -= fm(row - 1)
        oc = row * (w - 1)
        r0 = self._look(self.cond, n_cond, c, oc + (w - 1) - 1)
        r1 = self._look(self.cond, n_cond, c, oc + 2 * (w - 1) - 1)
        sy = self._sample_segment(sy, h - 1, r0, r1)
        sx *= r0 + (r1 - r0) * sy

        def fc(k):
            a = self._look(self.cond, n_cond, c, oc + k)
            b = self._look(self.cond, n_cond, c, oc + k + w - 1)
            return a + (b - a) * sy
        col = 0
        while col < w - 1 and fc(col) < sx:
            col += 1
        if col > 0:
            sx -= fc(col - 1)
        od = row * w + col
        L = lambda k: self._look(self.data, h * w, c, od + k)  # noqa: E731
        v00, v10, v01, v11 = L(0), L(1), L(w), L(w + 1)
        c0 = v00 + (v01 - v00) * sy
        c1 = v10 + (v11 - v10) * sy
        sx = self._sample_segment(sx, w - 1, c0, c1)
        return ((col + sx) / (w - 1), (row + sy) / (h - 1)), c0 + (c1 - c0) * sx

    def invert(self, p, param=()):
        h, w = self.h, self.w
        c = self._weights(param)
        x = min(max(p[0], 0.0), 1.0) * (w - 1)
        y = min(max(p[1], 0.0), 1.0) * (h - 1)
        px, py = min(int(x), w - 2), min(int(y), h - 2)
        x -= px
        y -= py
        od = py * w + px
        L = lambda k: self._look(self.data, h * w, c, od + k)  # noqa: E731
        v00, v10, v01, v11 = L(0), L(1), L(w), L(w + 1)
        c0 = v00 + (v01 - v00) * y
        c1 = v10 + (v11 - v10) * y
        pdf = c0 + (c1 - c0) * x
        x = self._invert_segment(x, 1.0 / (w - 1), c0, c1)
        n_marg, n_cond = h - 1, h * (w - 1)
        oc = py * (w - 1)

        def fc(k):
            a = self._look(self.cond, n_cond, c, oc + k)
            b = self._look(self.cond, n_cond, c, oc + k + w - 1)
            return a + (b - a) * y
        if px > 0:
            x += fc(px - 1)
        r0 = self._look(self.cond, n_cond, c, oc + (w - 1) - 1)
        r1 = self._look(self.cond, n_cond, c, oc + 2 * (w - 1) - 1)
        x /= r0 + (r1 - r0) * y
        y = self._invert_segment(y, 1.0 / (h - 1), r0, r1)
        if py > 0:
            y += self._look(self.marg, n_marg, c, py - 1)
        if not self.normalized:
            y /= self._look(self.marg, n_marg, c, n_marg - 1)
        return (x, y), pdf


# ---------------------------------------------------------------------------------------------
# Independent re-implementation of measured.cpp (eval, pdf, sample), float64
# ---------------------------------------------------------------------------------------------
def mulsign_neg(a, b):
    """Dr.Jit: flip a's sign unless b's sign bit is set (so b = +0 flips, b = -0 does not)."""
    return a if math.copysign(1.0, b) < 0 else -a


def dr_atan2(y, x):
    """Dr.Jit's atan2 (used by Mitsuba's scalar variants): signs of zeros are ignored, so
    atan2(+-0, x < 0) = +pi (not -pi) and atan2(+-0, +-0) = 0."""
    if x == 0 and y == 0:
        return 0.0
    t = math.atan2(abs(y), abs(x))
    if x < 0:
        t = PI - t
    return -t if y < 0 else t


def elevation(d):
    dist = math.sqrt(d[0] ** 2 + d[1] ** 2 + (d[2] - 1) ** 2)
    return 2 * math.asin(min(1.0, 0.5 * dist))


class PyMeasured:
    def __init__(self, f, reduction=None):
        self.iso = f["phi_i"].shape[0] <= 2
        self.jac = bool(f["jacobian"][0])
        if reduction is None:
            reduction = 0 if self.iso else int(np.rint(2 * np.float32(PI) /
                                                       (f["phi_i"][-1] - f["phi_i"][0])))
        self.reduction = reduction
        pv2 = [f["phi_i"], f["theta_i"]]
        self.ndf = PyMarginal2D(f["ndf"], (), normalize=False)
        self.sigma = PyMarginal2D(f["sigma"], (), normalize=False)
        self.vndf = PyMarginal2D(f["vndf"], pv2, normalize=True)
        self.lum = PyMarginal2D(f["luminance"], pv2, normalize=True)
        self.spectra = PyMarginal2D(f["spectra"], pv2 + [f["wavelengths"]], normalize=False)

    def _mirror(self, wi, wo):
        wi, wo = list(wi), list(wo) if wo is not None else None
        sx = sy = -1.0
        if self.reduction >= 2:
            sy = wi[1]
            sx = wi[0] if self.reduction == 4 else sy
            wi[0], wi[1] = mulsign_neg(wi[0], sx), mulsign_neg(wi[1], sy)
            if wo is not None:
                wo[0], wo[1] = mulsign_neg(wo[0], sx), mulsign_neg(wo[1], sy)
        return wi, wo, sx, sy

    def _common(self, wi, wo):
        wi, wo, _, _ = self._mirror(wi, wo)
        m = unit([a + b for a, b in zip(wi, wo)])
        ti, pi_ = elevation(wi), dr_atan2(wi[1], wi[0])
        tm, pm = elevation(m), dr_atan2(m[1], m[0])
        u_wi = (theta2u(ti), phi2u(pi_))
        um_y = phi2u(pm - pi_ if self.iso else pm)
        u_m = (theta2u(tm), um_y - math.floor(um_y))
        return wi, m, ti, pi_, u_wi, u_m

    def eval(self, wi, wo, lam):
        if not (wi[2] > 0 and wo[2] > 0):
            return 0.0
        wi, m, ti, pi_, u_wi, u_m = self._common(wi, wo)
        s, _ = self.vndf.invert(u_m, (pi_, ti))
        spec = self.spectra.eval(s, (pi_, ti, lam))
        if self.jac:
            spec *= self.ndf.eval(u_m) / (4 * self.sigma.eval(u_wi))
        return spec

    def pdf(self, wi, wo):
        if not (wi[2] > 0 and wo[2] > 0):
            return 0.0
        wi, m, ti, pi_, u_wi, u_m = self._common(wi, wo)
        s, vndf_pdf = self.vndf.invert(u_m, (pi_, ti))
        lum = self.lum.eval(s, (pi_, ti))
        sin_m = math.sqrt(m[0] ** 2 + m[1] ** 2)
        jac = max(2 * PI * PI * u_m[0] * sin_m, 1e-6) * 4 * dot(wi, m)
        return vndf_pdf * lum / jac

    def sample(self, wi, sample2, lam):
        """(wo, pdf, weight); sample1 is not used by measured.cpp."""
        if not wi[2] > 0:
            return [0.0, 0.0, 0.0], 0.0, 0.0
        wi, _, sx, sy = self._mirror(wi, None)
        ti, pi_ = elevation(wi), dr_atan2(wi[1], wi[0])
        u_wi = (theta2u(ti), phi2u(pi_))
        s = (sample2[1], sample2[0])  # note the swap
        s, lum_pdf = self.lum.sample(s, (pi_, ti))
        u_m, ndf_pdf = self.vndf.sample(s, (pi_, ti))
        pm, tm = u2phi(u_m[1]), u2theta(u_m[0])
        if self.iso:
            pm += pi_
        m = sph(tm, pm)
        jac = max(2 * PI * PI * u_m[0] * math.sin(tm), 1e-6) * 4 * dot(wi, m)
        wo = [2 * dot(m, wi) * mc - w for mc, w in zip(m, wi)]
        pdf = ndf_pdf * lum_pdf / jac
        spec = self.spectra.eval(s, (pi_, ti, lam))
        if self.jac:
            spec *= self.ndf.eval(u_m) / (4 * self.sigma.eval(u_wi))
        wo[0], wo[1] = mulsign_neg(wo[0], sx), mulsign_neg(wo[1], sy)
        weight = spec / pdf if wo[2] > 0 else 0.0
        return wo, pdf, weight


# ---------------------------------------------------------------------------------------------
# Synthetic materials
# ---------------------------------------------------------------------------------------------
WAVELENGTHS = np.array([360, 420, 480, 550, 620, 700, 830, 1000], dtype=np.float32)
THETA_I_DEG = [0.0, 15.0, 30.0, 45.0, 60.0, 80.0]

ISO = dict(name="iso", description="gonio synthetic isotropic GGX test material (not a measurement)",
           alpha=(0.25, 0.25), phi_i=[0.0], ndf_hw=(2, 16), vndf_hw=(13, 11), n=12,
           f0=lambda lam: 0.55 + 0.35 * math.tanh((lam - 560.0) / 90.0))
ANISO = dict(name="aniso", description="gonio synthetic anisotropic GGX test material, "
                                       "4-fold azimuthal reduction (not a measurement)",
             alpha=(0.15, 0.4), phi_i=[-PI, -5 * PI / 6, -2 * PI / 3, -PI / 2],
             ndf_hw=(10, 12), vndf_hw=(13, 11), n=12,
             f0=lambda lam: 0.6 + 0.25 * math.cos((lam - 380.0) / 210.0))


def ggx_alpha2(phi, ax, ay):
    c, s = math.cos(phi), math.sin(phi)
    return c * c * ax * ax + s * s * ay * ay


def ggx_d(theta, phi, ax, ay):
    c, s = math.cos(phi), math.sin(phi)
    k = c * c / (ax * ax) + s * s / (ay * ay)
    ct2, st2 = math.cos(theta) ** 2, math.sin(theta) ** 2
    return 1.0 / (PI * ax * ay * (ct2 + k * st2) ** 2)


def ggx_sigma(theta, phi, ax, ay):
    ct, st = math.cos(theta), math.sin(theta)
    return 0.5 * (ct + math.sqrt(ct * ct + ggx_alpha2(phi, ax, ay) * st * st))


def ggx_g1(w, ax, ay):
    z = max(w[2], 0.02)
    r2 = w[0] ** 2 + w[1] ** 2
    if r2 == 0:
        return 1.0
    a2 = (w[0] ** 2 * ax * ax + w[1] ** 2 * ay * ay) / r2
    tan2 = r2 / (z * z)
    return 2.0 / (1.0 + math.sqrt(1.0 + a2 * tan2))


def lum_weight(lam):
    return math.exp(-0.5 * ((lam - 555.0) / 70.0) ** 2)


def make_material(cfg, mi):
    ax, ay = cfg["alpha"]
    iso = len(cfg["phi_i"]) <= 2
    phi_i = np.array(cfg["phi_i"], dtype=np.float32)
    theta_i = (np.array(THETA_I_DEG) * DEG).astype(np.float32)
    hn, wn = cfg["ndf_hw"]
    ndf = np.zeros((hn, wn))
    sigma = np.zeros((hn, wn))
    for y in range(hn):
        for x in range(wn):
            t, p = u2theta(x / (wn - 1)), u2phi(y / (hn - 1))
            ndf[y, x] = ggx_d(t, p, ax, ay)
            sigma[y, x] = ggx_sigma(t, p, ax, ay)
    hv, wv = cfg["vndf_hw"]
    n_p, n_t, n = len(phi_i), len(theta_i), cfg["n"]
    vndf = np.zeros((n_p, n_t, hv, wv))
    for a in range(n_p):
        for b in range(n_t):
            ti, pi_ = float(theta_i[b]), float(phi_i[a])
            wi = sph(ti, 0.0 if iso else pi_)
            sig = ggx_sigma(ti, pi_, ax, ay)
            for y in range(hv):
                for x in range(wv):
                    ux = x / (wv - 1)
                    t, p = u2theta(ux), u2phi(y / (hv - 1))
                    m = sph(t, p)
                    vndf[a, b, y, x] = (2 * PI * PI * ux * math.sin(t) * max(dot(wi, m), 0.0)
                                        * ggx_d(t, p, ax, ay) / sig)
    vndf = vndf.astype(np.float32)
    warp = mi.MarginalContinuous2D2(vndf, [phi_i.tolist(), theta_i.tolist()], normalize=True)
    spectra = np.zeros((n_p, n_t, len(WAVELENGTHS), n, n))
    for a in range(n_p):
        for b in range(n_t):
            ti, pi_ = float(theta_i[b]), float(phi_i[a])
            wi = sph(ti, pi_)
            for y in range(n):
                for x in range(n):
                    s = (x / (n - 1), y / (n - 1))
                    u_m, _ = warp.sample(mi.Point2f(s), [pi_, ti])
                    pm = u2phi(float(u_m[1])) + (pi_ if iso else 0.0)
                    m = sph(u2theta(float(u_m[0])), pm)
                    cos_d = max(dot(wi, m), 0.0)
                    wo = [2 * cos_d * mc - w for mc, w in zip(m, wi)]
                    g1 = ggx_g1(wo, ax, ay)
                    tilt = 1.0 + 0.2 * (s[1] - 0.5)
                    for k, lam in enumerate(WAVELENGTHS):
                        f0 = cfg["f0"](float(lam))
                        fres = f0 + (1 - f0) * (1 - cos_d) ** 5
                        floor = 0.02 + 0.03 * (float(lam) - 360.0) / 640.0
                        spectra[a, b, k, y, x] = (fres * g1 + floor) * tilt
    wl = np.array([lum_weight(float(l)) for l in WAVELENGTHS])
    luminance = np.tensordot(spectra, wl / wl.sum(), axes=([2], [0]))
    return {
        "description": np.frombuffer(cfg["description"].encode(), dtype=np.uint8).copy(),
        "jacobian": np.array([1], dtype=np.uint8),
        "theta_i": theta_i,
        "phi_i": phi_i,
        "ndf": ndf.astype(np.float32),
        "sigma": sigma.astype(np.float32),
        "vndf": vndf,
        "luminance": luminance.astype(np.float32),
        "spectra": spectra.astype(np.float32),
        "wavelengths": WAVELENGTHS.copy(),
    }


def check_tensor_file(mi, path, fields):
    ok = True
    with tempfile.TemporaryDirectory() as tmp:
        ref = os.path.join(tmp, "ref.bsdf")
        with contextlib.redirect_stdout(io.StringIO()):
            mi.tensor_io.write(ref, align=ALIGN, **fields)
        with open(ref, "rb") as f, open(path, "rb") as g:
            ok = f.read() == g.read()
    tf = mi.TensorFile(path)
    for name, v in fields.items():
        fld = tf[name]
        shape_txt = repr(fld).split("shape = [")[1].split("]")[0]
        shape = [int(x) for x in shape_txt.split(",")]
        good = shape == list(v.shape) and fld.dtype.value == DTYPE_CODE[v.dtype]
        if v.dtype == np.float32:
            good = good and np.array_equal(np.array(fld.to(mi.ScalarTensorXf)), v)
        ok = ok and good
    del tf
    return ok


# ---------------------------------------------------------------------------------------------
# Queries
# ---------------------------------------------------------------------------------------------
LOADS = 200      # at most this many plugin instances per config
LOADS_MIN = 12   # at least this many
EVAL_WAVELENGTHS = [400.0, 455.5, 550.0, 700.0, 830.0, 350.0, 1100.0]


def reflect_about(wi, m):
    d = dot(wi, m)
    return unit([2 * d * mc - w for mc, w in zip(m, wi)])


def eval_queries(rng, iso):
    q = []
    for k in range(9 if iso else 8):
        q.append(("random", sphere_dir(rng, 0.05, 1.0), sphere_dir(rng, 0.05, 1.0)))
    for k in range(8):
        wi = sphere_dir(rng, 0.15, 1.0)
        m = unit([rng.gauss(0, 0.15), rng.gauss(0, 0.15), 1.0])
        wo = reflect_about(wi, m)
        if wo[2] <= 0.05:
            wo = sphere_dir(rng, 0.05, 1.0)
        q.append(("near-specular", wi, wo))
    s, c = math.sin(40 * DEG), math.cos(40 * DEG)
    wi = [0.6 * s, -0.8 * s, c]
    q.append(("exact-mirror (h = +z)", wi, [-wi[0], -wi[1], wi[2]]))
    # Normal incidence. wi = (0, -0, 1) behaves the same for every value of the (for isotropic
    # files uninitialized) m_reduction seen; wi = (+0, +0, 1) does not, so only aniso gets it.
    q.append(("normal incidence wi = (0, -0, 1)", [0.0, -0.0, 1.0], unit([0.25, -0.4, 0.9]), 700.0))
    if not iso:
        q.append(("normal incidence wi = (+0, +0, 1)", [0.0, 0.0, 1.0], unit([0.25, -0.4, 0.9]), 700.0))
    q.append(("near-normal wi", unit([0.01, 0.02, 1.0]), unit([-0.3, 0.1, 0.9])))
    q.append(("near-normal wi, near-specular", unit([-0.03, 0.015, 1.0]), unit([0.05, -0.01, 1.0])))
    t = 85 * DEG
    q.append(("grazing wi 85 deg (theta_i beyond the last node)", sph(t, 0.7), sph(50 * DEG, 0.7 + PI)))
    q.append(("grazing wi 85 deg, near-specular", sph(t, 2.0), reflect_about(sph(t, 2.0), unit([0.05, 0.02, 1.0]))))
    q.append(("grazing wi and wo 85 deg", sph(t, -1.2), sph(t, -1.2 + 2.5)))
    # On the axes: mulsign_neg of +-0 (anisotropic reduction)
    q.append(("wi.x = +0", [0.0, -math.sin(35 * DEG), math.cos(35 * DEG)], unit([0.3, 0.35, 0.8]), 550.0))
    q.append(("wi.x = -0", [-0.0, -math.sin(35 * DEG), math.cos(35 * DEG)], unit([0.3, 0.35, 0.8]), 550.0))
    q.append(("wi.y = +0", [math.sin(50 * DEG), 0.0, math.cos(50 * DEG)], unit([-0.5, 0.2, 0.7]), 455.5))
    q.append(("wi.y = -0", [math.sin(50 * DEG), -0.0, math.cos(50 * DEG)], unit([-0.5, 0.2, 0.7]), 455.5))
    q.append(("below-horizon wi", [0.3, 0.2, -0.932737905], unit([-0.3, -0.2, 0.9])))
    q.append(("below-horizon wo", unit([0.1, 0.5, 0.7]), [-0.1, -0.5, -0.860232527]))
    return [(e[0], vec(e[1]), vec(e[2]), e[3] if len(e) > 3 else None) for e in q]


def sample_queries(rng):
    q = []
    s2s = [[0.3, 0.7], [0.81, 0.12], [0.5, 0.5], [0.05, 0.95], [0.66, 0.41]]
    k = 0
    for th in [0.0, 20.0, 45.0, 60.0, 75.0, 85.0]:
        wi = vec(sph(th * DEG, rng.uniform(0, 2 * PI)))
        if th == 0.0:
            wi = [0.0, -0.0, 1.0]  # see eval_queries
        for j in range(3):
            q.append(("theta_i=%g" % th, wi, [0.04, 0.6, 0.93][j], s2s[k % len(s2s)]))
            k += 1
    wi = vec(sph(38 * DEG, 2.2))
    q.append(("same as next but sample1 differs (sample1 is ignored)", wi, 0.1, [0.27, 0.83], 550.0))
    q.append(("same as previous but sample1 differs", wi, 0.9, [0.27, 0.83], 550.0))
    q.append(("sample2 components swapped w.r.t. previous", wi, 0.9, [0.83, 0.27], 550.0))
    q.append(("sample2 at the corners (clamped to [eps, 1-eps]); ill-conditioned", wi, 0.5, [0.0, 1.0]))
    q.append(("below-horizon wi: pdf 0, wo 0", vec([0.3, 0.2, -0.932737905]), 0.5, [0.5, 0.5]))
    return [e if len(e) > 4 else e + (None,) for e in q]


def mirror_probe(mi, bsdf, fields):
    """How a plugin instance treats wi = (+0, +0, 1): "no mirroring" (isotropic files with
    m_reduction < 2, and anisotropic ones where m_reduction is set) or "180-degree rotation"."""
    wi, wo = [0.0, 0.0, 1.0], vec(unit([0.25, -0.4, 0.9]))
    v = float(bsdf.eval(mi.BSDFContext(), interaction(mi, wi, 550.0), mi.Vector3f(wo))[0])
    if fields["phi_i"].shape[0] > 2:
        return "no mirroring"
    e0 = PyMeasured(fields, 0).eval(wi, wo, 550.0)
    e2 = PyMeasured(fields, 2).eval(wi, wo, 550.0)
    assert abs(e0 - e2) > 1e-3 * e0
    return "no mirroring" if abs(v - e0) < abs(v - e2) else "180-degree rotation"


def eval_rows(mi, bsdf, py, queries):
    rows, worst = [], 0.0
    for k, (note, wi, wo, lam) in enumerate(queries):
        lam = lam or EVAL_WAVELENGTHS[k % len(EVAL_WAVELENGTHS)]
        mode = "importance" if k % 4 == 3 else "radiance"
        si = interaction(mi, wi, lam)
        ctx = ctx_for(mi, mode)
        v = bsdf.eval(ctx, si, mi.Vector3f(wo))
        vals = [float(v[i]) for i in range(4)]
        assert all(x == vals[0] or (math.isnan(x) and math.isnan(vals[0])) for x in vals)
        pdf = float(bsdf.pdf(ctx, si, mi.Vector3f(wo)))
        ev, ep = py.eval(wi, wo, lam), py.pdf(wi, wo)
        worst = max(worst, abs(ev - vals[0]) / max(abs(ev), 1e-3), abs(ep - pdf) / max(abs(ep), 1e-3))
        rows.append({"kind": "eval", "mode": mode, "wi": wi, "wo": wo, "lambda_nm": lam,
                     "value": g8(vals[0]), "pdf": g8(pdf), "note": note})
    return rows, worst


def sample_rows(mi, bsdf, py, queries):
    rows, worst = [], 0.0
    for k, (note, wi, s1, s2, lam) in enumerate(queries):
        lam = lam or EVAL_WAVELENGTHS[(k + 2) % len(EVAL_WAVELENGTHS)]
        mode = "importance" if k % 4 == 1 else "radiance"
        si = interaction(mi, wi, lam)
        bs, w = bsdf.sample(ctx_for(mi, mode), si, s1, mi.Point2f(s2))
        wo = [float(c) for c in bs.wo]
        pwo, ppdf, pw = py.sample(wi, s2, lam)
        err = max(max(abs(a - b) for a, b in zip(wo, pwo)),
                  abs(ppdf - float(bs.pdf)) / max(ppdf, 1e-3),
                  abs(pw - float(w[0])) / max(abs(pw), 1e-3))
        if "ill-conditioned" in note:
            err = min(err, 1e-6) if err < 5e-3 else err  # float32 vs float64: wo moves ~1e-3
        worst = max(worst, err)
        rows.append({"kind": "sample", "mode": mode, "wi": wi, "lambda_nm": lam, "sample1": s1,
                     "sample2": s2, "wo": vec(wo), "pdf": g8(float(bs.pdf)), "value": g8(float(w[0])),
                     "note": note})
    return rows, worst


# ---------------------------------------------------------------------------------------------
# Experiments (scratch files in a temporary directory; printed, summarized in README.md)
# ---------------------------------------------------------------------------------------------
def experiments(mi, cfg_iso, cfg_aniso):
    """Scratch files in a temporary directory; findings are printed (and summarized in README)."""
    ok = True
    rng = random.Random(5)
    qs = [(vec(sphere_dir(rng, 0.1, 1.0)), vec(sphere_dir(rng, 0.1, 1.0))) for _ in range(40)]
    qs.append(([0.0, 0.0, 1.0], vec(unit([0.25, -0.4, 0.9]))))  # tells "rotation" from "none"
    ctx = mi.BSDFContext()

    def classify(fields, reductions, loads):
        """For each fresh plugin instance: which model reductions reproduce it (rel. 2e-3)."""
        models = {r: PyMeasured(fields, r) for r in reductions}
        kinds = {}
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(tmp, "x.bsdf"), "wb") as f:
                f.write(tensor_file_bytes(fields))
            for _ in range(loads):
                with resolver_dir(mi, tmp):
                    b = mi.load_string('<bsdf version="3.0.0" type="measured">'
                                       '<string name="filename" value="x.bsdf"/></bsdf>')
                vals = [float(b.eval(ctx, interaction(mi, wi, 550.0), mi.Vector3f(wo))[0])
                        for wi, wo in qs]
                match = []
                for r, py in models.items():
                    err = max(abs(v - py.eval(wi, wo, 550.0)) / max(py.eval(wi, wo, 550.0), 1e-3)
                              for v, (wi, wo) in zip(vals, qs))
                    if err < 2e-3:
                        match.append(r)
                key = "reduction " + "/".join(map(str, match)) if match else "no model"
                kinds[key] = kinds.get(key, 0) + 1
        return kinds

    print("experiment: azimuth range of phi_i (anisotropic, 4 nodes; 41 eval queries; which "
          "model reduction reproduces Mitsuba; share of queries whose mirrored phi_i lies outside "
          "the node range, i.e. is clamped to an end node)")
    base = make_material(cfg_aniso, mi)
    for label, lo, hi in [("[-pi, -pi/2]", -PI, -PI / 2), ("[0, pi/2]", 0.0, PI / 2),
                          ("[-pi/2, 0]", -PI / 2, 0.0), ("[pi/2, pi]", PI / 2, PI),
                          ("[-pi, 0]", -PI, 0.0), ("[-pi, pi]", -PI, PI)]:
        f = dict(base)
        f["phi_i"] = np.linspace(lo, hi, 4).astype(np.float32)
        red = int(np.rint(2 * np.float32(PI) / (f["phi_i"][-1] - f["phi_i"][0])))
        kinds = classify(f, [red], 2)
        py = PyMeasured(f, red)
        clamped = 0
        for wi, wo in qs:
            mw = py._mirror(wi, wo)[0]
            p = dr_atan2(mw[1], mw[0])
            clamped += not (float(f["phi_i"][0]) <= p <= float(f["phi_i"][-1]))
        print("  phi_i over %-13s -> m_reduction %d; instances: %s; clamped: %d/%d"
              % (label, red, kinds, clamped, len(qs)))
        ok = ok and list(kinds) == ["reduction %d" % red]
    iso = make_material(cfg_iso, mi)
    kinds = classify(iso, [0, 2, 4], 24)
    print("experiment: isotropic file (1 phi_i node), 24 fresh instances: %s  (m_reduction is "
          "uninitialized for isotropic files; 2 = rotate wi, wo by 180 deg, 4 = mirror into the "
          "third quadrant)" % kinds)
    ok = ok and set(kinds) <= {"reduction 0", "reduction 2"}
    f = dict(iso)
    f["phi_i"] = np.array([-1.0, 2.0], dtype=np.float32)
    for key in ("vndf", "luminance", "spectra"):
        f[key] = np.concatenate([iso[key], iso[key] * 1.5], axis=0)
    kinds = classify(f, [0, 2, 4], 24)
    print("experiment: isotropic file with 2 phi_i nodes [-1, 2] (second slice x1.5; phi_i, the "
          "absolute azimuth of wi, is then interpolated), 24 fresh instances: %s" % kinds)
    ok = ok and set(kinds) <= {"reduction 0", "reduction 2"}
    return ok


# ---------------------------------------------------------------------------------------------
# Marginal2D direct tests
# ---------------------------------------------------------------------------------------------
def marginal_tables():
    rng = np.random.RandomState(2018)
    t = []
    d0 = (rng.rand(4, 5) * 2 + 0.2).astype(np.float32)  # H=4 rows, W=5 columns
    t.append(("2D0-4x5-normalized", 0, d0, [], True))
    t.append(("2D0-4x5-unnormalized", 0, d0, [], False))
    dz = (rng.rand(3, 6) + 0.3).astype(np.float32)
    dz[:, 0] = 0.0          # zero first column (like a vndf at u_theta = 0)
    dz[1, 3:5] = dz[1, 2]   # equal neighbours -> constant segments
    t.append(("2D0-3x6-zero-column-normalized", 0, dz, [], True))
    d2 = (rng.rand(2, 3, 4, 5) * 3 + 0.1).astype(np.float32)
    pv2 = [[-0.5, 1.25], [0.0, 0.2, 1.0]]
    t.append(("2D2-params2x3-4x5-normalized", 2, d2, pv2, True))
    t.append(("2D2-params2x3-4x5-unnormalized", 2, d2, pv2, False))
    d3 = (rng.rand(2, 1, 3, 3, 4) + 0.05).astype(np.float32)
    pv3 = [[10.0, 30.0], [0.7], [400.0, 500.0, 700.0]]
    t.append(("2D3-params2x1x3-3x4-unnormalized", 3, d3, pv3, False))
    t.append(("2D3-params2x1x3-3x4-normalized", 3, d3, pv3, True))
    return t


def param_sets(pv, rng):
    if not pv:
        return [[]]
    on = [[v[0] for v in pv], [v[-1] for v in pv], [v[min(1, len(v) - 1)] for v in pv]]
    between = [[rng.uniform(v[0], v[-1]) for v in pv] for _ in range(2)]
    outside = [[v[0] - 0.7 for v in pv], [v[-1] + 3.0 for v in pv]]
    mixed = [[v[0] - 1.0 if i == 0 else rng.uniform(v[0], v[-1]) for i, v in enumerate(pv)]]
    return on + between + outside + mixed


def marginal_json(mi):
    cls = {0: mi.MarginalContinuous2D0, 2: mi.MarginalContinuous2D2, 3: mi.MarginalContinuous2D3}
    rng = random.Random(77)
    out_tables = []
    worst_port = worst_inv = worst_node = worst_pdf = 0.0
    for name, dim, data, pv, norm in marginal_tables():
        if dim == 0:
            w = cls[0](data, [], normalize=norm)
        else:
            w = cls[dim](data, pv, norm)
        py = PyMarginal2D(data, pv, norm)
        params = param_sets(pv, rng)
        h, wd = data.shape[-2:]
        evals, samples, inverts = [], [], []
        pts = [[0.0, 0.0], [1.0, 1.0], [1 / (wd - 1), 2 / (h - 1)], [0.5, 0.5], [1.0, 0.0]]
        pts += [[rng.random(), rng.random()] for _ in range(3)]
        pts += [[-0.2, 0.4], [0.3, 1.3]]
        for k, pos in enumerate(pts):
            par = params[k % len(params)]
            pos = vec(pos)
            par = [f32(p) for p in par]
            v = float(w.eval(mi.Point2f(pos), par))
            evals.append({"pos": pos, "param": par, "value": g8(v)})
            worst_port = max(worst_port, abs(v - py.eval(pos, par)) / max(abs(v), 1e-3))
        us = [[rng.random(), rng.random()] for _ in range(7)] + [[0.0, 0.0], [1.0, 1.0], [0.5, 0.999]]
        for k, u in enumerate(us):
            par = [f32(p) for p in params[(k + 1) % len(params)]]
            u = vec(u)
            p, pdf = w.sample(mi.Point2f(u), par)
            p = [float(p[0]), float(p[1])]
            pdf = float(pdf)
            samples.append({"u": u, "param": par, "point": vec(p), "pdf": g8(pdf)})
            (qx, qy), qpdf = py.sample(u, par)
            worst_port = max(worst_port, abs(qx - p[0]), abs(qy - p[1]), abs(qpdf - pdf) / max(pdf, 1e-3))
            # round trip and pdf consistency
            back, ipdf = w.invert(mi.Point2f(p), par)
            uc = [min(max(c, 2.0 ** -24), 1 - 2.0 ** -24) for c in u]
            worst_inv = max(worst_inv, abs(float(back[0]) - uc[0]), abs(float(back[1]) - uc[1]))
            ev = float(w.eval(mi.Point2f(p), par))
            worst_pdf = max(worst_pdf, abs(ev - pdf) / max(pdf, 1e-3), abs(float(ipdf) - pdf) / max(pdf, 1e-3))
            if k < 5:
                inverts.append({"point": vec(p), "param": par, "u": [g8(back[0]), g8(back[1])],
                                "pdf": g8(ipdf)})
        for k in range(5):
            par = [f32(p) for p in params[(k + 3) % len(params)]]
            pt = vec([rng.random(), rng.random()]) if k < 4 else [1.0, 1.0]
            u, pdf = w.invert(mi.Point2f(pt), par)
            inverts.append({"point": pt, "param": par, "u": [g8(u[0]), g8(u[1])], "pdf": g8(pdf)})
            (qx, qy), qpdf = py.invert(pt, par)
            worst_port = max(worst_port, abs(qx - float(u[0])), abs(qy - float(u[1])),
                             abs(qpdf - float(pdf)) / max(float(pdf), 1e-3))
        # eval at grid nodes (parameters on nodes) == stored value * normalization
        flat = data.reshape(-1, h, wd)
        for s_idx in range(flat.shape[0]):
            idx = np.unravel_index(s_idx, data.shape[:-2]) if dim else ()
            par = [pv[d][idx[d]] for d in range(dim)]
            sl = flat[s_idx].astype(np.float64)
            if norm:  # the continuous normalization of that slice (trapezoid integral)
                integ = np.trapezoid(np.trapezoid(sl, dx=1.0 / (wd - 1), axis=1), dx=1.0 / (h - 1))
                sl = sl / integ
            for y in range(h):
                for x in range(wd):
                    v = float(w.eval(mi.Point2f(x / (wd - 1), y / (h - 1)), par))
                    worst_node = max(worst_node, abs(v - sl[y, x]) / max(abs(sl[y, x]), 1e-3))
        out_tables.append({
            "name": name, "class": "MarginalContinuous2D%d" % dim, "dimension": dim,
            "size": [int(wd), int(h)], "param_res": [len(v) for v in pv],
            "param_values": [[f32(x) for x in v] for v in pv], "normalize": norm,
            "data_shape": list(data.shape), "data": [f32(x) for x in data.reshape(-1)],
            "eval": evals, "sample": samples, "invert": inverts})
    return out_tables, (worst_port, worst_inv, worst_node, worst_pdf)


# ---------------------------------------------------------------------------------------------
def dump_configs(path, head, configs, key="rows"):
    head_txt = json.dumps(head, indent=1)[:-2]
    parts = []
    for c in configs:
        rows = ",\n   ".join(json.dumps(r) for r in c[key])
        rest = {k: v for k, v in c.items() if k != key}
        parts.append("  " + json.dumps(rest)[:-1] + ', "%s": [\n   %s]}' % (key, rows))
    with open(path, "w") as f:
        f.write(head_txt + ',\n "configs": [\n' + ",\n".join(parts) + "\n ]\n}\n")


def main():
    mi = load_mitsuba()
    ok = True
    mats = {}
    for cfg in (ISO, ANISO):
        fields = make_material(cfg, mi)
        path = os.path.join(HERE, cfg["name"] + ".bsdf")
        with open(path, "wb") as f:
            f.write(tensor_file_bytes(fields))
        good = check_tensor_file(mi, path, fields)
        print("format check %s: bytes == mitsuba.tensor_io.write and mi.TensorFile reads back: %s"
              % (os.path.basename(path), good))
        for k, v in fields.items():
            print("   %-11s %-7s %s" % (k, v.dtype, list(v.shape)))
        ok = ok and good
        mats[cfg["name"]] = fields

    ok = experiments(mi, ISO, ANISO) and ok

    head = {
        "generator": "Mitsuba 3.9.1 scalar_spectral (testdata/measured/make_reference.py)",
        "conventions": "local frame, normal +z (si.sh_frame = identity); value = bsdf.eval(ctx, si, wo)"
                       " exactly as Mitsuba returns it: measured.cpp returns the interpolated RGL "
                       "'spectra' value times ndf/(4 sigma), which the RGL data defines as "
                       "f * cos(theta_o), so the cosine IS included (do not divide by cos theta_o); "
                       "pdf = bsdf.pdf (solid angle); sample rows: bsdf.sample(ctx, si, sample1, "
                       "sample2), value = sample weight (eval / pdf, 0 when the sampled wo is below "
                       "the horizon even though pdf > 0), sample1 is ignored by the plugin; all 4 "
                       "si.wavelengths = lambda_nm; directions are float32 (shortest decimal, may be "
                       "-0.0); values/pdfs 8 significant digits; mode has no effect on this plugin; "
                       "filename relative to testdata/measured/",
    }
    configs = []
    worst_e = worst_s = 0.0
    junk = []
    for name in ("iso", "aniso"):
        xml = ('<bsdf version="3.0.0" type="measured"><string name="filename" value="%s.bsdf"/></bsdf>'
               % name)
        py = PyMeasured(mats[name])
        # Fresh plugin instances. For isotropic files measured.cpp never initializes
        # m_reduction, so each instance behaves either as "no mirroring" or as "rotate wi and wo
        # by 180 degrees" (observed ~50/50). The two agree to ~1e-7 except at wi = (+0, +0, 1).
        # `mirror_probe` tells them apart; rows are stored from a "no mirroring" instance.
        results, kinds = {}, {}
        for trial in range(LOADS):
            with resolver_dir(mi, HERE):
                bsdf = mi.load_string(xml)
            kind = mirror_probe(mi, bsdf, mats[name])
            rows, we = eval_rows(mi, bsdf, py, eval_queries(random.Random(2018), name == "iso"))
            srows, ws = sample_rows(mi, bsdf, py, sample_queries(random.Random(7)))
            worst_e, worst_s = max(worst_e, we), max(worst_s, ws)
            kinds[kind] = kinds.get(kind, 0) + 1
            results.setdefault(kind, set()).add(json.dumps(rows + srows))
            junk.append(bsdf)
            junk.extend(mi.load_dict({"type": "diffuse"}) for _ in range(trial % 3))
            if trial + 1 >= LOADS_MIN and "no mirroring" in results:
                break
        variants = [json.loads(r) for v in results.values() for r in v]
        spread = 0.0
        for var in variants[1:]:
            for a, b in zip(var, variants[0]):
                for key in ("value", "pdf"):
                    spread = max(spread, abs(a[key] - b[key]) / max(abs(b[key]), 1e-6))
                spread = max(spread, max(abs(x - y) for x, y in zip(a["wo"], b["wo"])))
        print("%s: plugin instances by mirror_probe: %s; distinct row sets per kind: %s; worst "
              "rel. spread between all instances %.1e"
              % (name, kinds, {k: len(v) for k, v in results.items()}, spread))
        good = (spread < 1e-5 and "no mirroring" in results and len(results["no mirroring"]) == 1
                and (name == "iso" or len(results) == 1))
        ok = ok and good
        rows_all = json.loads(next(iter(results["no mirroring"]))) if "no mirroring" in results else []
        rows = [r for r in rows_all if r["kind"] == "eval"]
        srows = [r for r in rows_all if r["kind"] == "sample"]
        nan = sum(1 for r in rows + srows if r["value"] is None or r["pdf"] is None)
        configs.append({"name": name, "xml": xml, "rows": rows + srows})
        print("%s: %d eval rows, %d sample rows, %d NaN" % (name, len(rows), len(srows), nan))
    print("self-check: measured eval/pdf vs. independent model: worst rel. err %.1e; sample "
          "(wo abs., pdf/weight rel.; the ill-conditioned corner rows only to 5e-3): %.1e"
          % (worst_e, worst_s))
    ok = ok and worst_e < 1e-4 and worst_s < 1e-4
    dump_configs(VALUES_JSON, head, configs)

    tables, (wp, wi_, wn, wpdf) = marginal_json(mi)
    print("self-check: Marginal2D vs. independent model: worst err %.1e; invert(sample(u)) == u: "
          "worst abs. err %.1e; eval at nodes == stored/normalized data: worst rel. err %.1e; "
          "sample pdf == eval(point) == invert pdf: worst rel. err %.1e" % (wp, wi_, wn, wpdf))
    ok = ok and wp < 1e-4 and wi_ < 1e-5 and wn < 1e-5 and wpdf < 1e-4
    mhead = {
        "generator": "Mitsuba 3.9.1 scalar_spectral mi.MarginalContinuous2D{0,2,3} "
                     "(testdata/measured/make_reference.py)",
        "conventions": "C++ Marginal2D<Float, D, Continuous=true>(data, size = (x = W, y = H), "
                       "param_res, param_values, normalize, enable_sampling = true). data is "
                       "row-major with shape data_shape = [param_res..., H, W] (parameter 0 "
                       "slowest, then y = row, x = column fastest); size = [W, H]; positions, "
                       "samples and points are [x, y] in the unit square, node (i, j) of a slice at "
                       "[i/(W-1), j/(H-1)]; param lists are given in the same order as param_values. "
                       "Python constructor used: MarginalContinuous2D0(data[H,W], [], normalize=...),"
                       " MarginalContinuous2DN(data, param_values, normalize). eval -> value; "
                       "sample(u) -> (point, pdf); invert(point) -> (u, pdf). All inputs are float32"
                       " (shortest decimals); outputs 8 significant digits.",
    }
    head_txt = json.dumps(mhead, indent=1)[:-2]
    parts = []
    for t in tables:
        meta = {k: v for k, v in t.items() if k not in ("eval", "sample", "invert")}
        lines = ["  " + json.dumps(meta)[:-1]]
        for key in ("eval", "sample", "invert"):
            lines.append('   "%s": [\n    %s]' % (key, ",\n    ".join(json.dumps(r) for r in t[key])))
        parts.append(lines[0] + ",\n" + ",\n".join(lines[1:]) + "}")
    with open(MARGINAL_JSON, "w") as f:
        f.write(head_txt + ',\n "tables": [\n' + ",\n".join(parts) + "\n ]\n}\n")

    for p in ("iso.bsdf", "aniso.bsdf", "mitsuba-values.json", "marginal2d-values.json"):
        print("wrote %s (%d bytes)" % (p, os.path.getsize(os.path.join(HERE, p))))
    if not ok:
        print("SELF-CHECK FAILED")
        sys.exit(1)
    print("self-check passed")


if __name__ == "__main__":
    main()
