//! Mitsuba 3's `sdfgrid` shape (`src/shapes/sdfgrid.cpp`): a signed distance function sampled
//! on an nx × ny × nz grid over the unit cube [0, 1]³ of object space, interpolated trilinearly;
//! the surface is its zero level set.
//!
//! Sample (i, j, k) sits at (i/(nx−1), j/(ny−1), k/(nz−1)). Inside voxel (i, j, k), with local
//! coordinates q ∈ [0, 1]³ and corner values s₀…s₇ (index x + 2y + 4z),
//!
//! ```text
//! f(q) = trilerp(s, q),
//! ```
//!
//! and along a ray q(t) = q₀ + t·d f is a cubic in t (Hansson-Söderlund, Evans and
//! Akenine-Möller, "Ray Tracing of Signed Distance Function Grids", JCGT 11(3), 2022). Only
//! voxels whose corners change sign (or touch zero) can hold surface. As in Mitsuba, a voxel's
//! root is the first sign change of the cubic in the voxel: the interval is split at the
//! derivative's roots into monotonic pieces and the first bracket is refined by Newton steps
//! safeguarded by bisection (Marmitt et al., "Fast and accurate ray-voxel intersection
//! techniques for iso-surface ray tracing", VMV 2004). The values where the ray enters and leaves
//! a voxel are evaluated with the crossed face's coordinate snapped to 0 or 1, so neighbouring
//! voxels agree on the sign at their shared face and no crossing is lost between them. Mitsuba
//! puts each voxel in its BVH; we walk the voxels the ray crosses in order (a 3D DDA, Amanatides
//! and Woo 1987) and stop at the first voxel with a root.
//!
//! Normals: the geometric normal is the gradient of the trilinear interpolant of the hit's voxel
//! (`normals="analytic"` shades with it, discontinuous across voxels); `normals="smooth"`
//! (Mitsuba's default) shades with the blend of the eight voxel gradients around the nearest
//! grid vertex of the paper (section 5). No texture coordinates (uv = 0), no area: an `sdfgrid`
//! cannot emit, as in Mitsuba.
//!
//! | parameter | default |
//! |---|---|
//! | `filename` | Mitsuba's grid `.vol` file, one channel (required) |
//! | `normals` | `smooth` (`analytic` or `smooth`) |
//! | `to_world`, `flip_normals`, nested `bsdf` | as every shape |
//!
//! The `.vol` format (Mitsuba's `VolumeGrid`): the bytes `VOL`, version 3, then little-endian
//! int32 encoding (1 = float32), int32 resolutions x, y, z, int32 channel count, six float32
//! bounds (ignored by `sdfgrid`, which maps the grid to the unit cube), then the samples, x
//! fastest, then y, then z, channels interleaved.

use glam::{IVec3, Vec3};

/// How an `sdfgrid` shades.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SdfNormals {
    /// The gradient of the hit voxel's trilinear interpolant.
    Analytic,
    /// The blend of the eight neighbouring voxel gradients (Hansson-Söderlund et al. 2022).
    Smooth,
}

/// A grid read from a `.vol` file.
#[derive(Clone, Debug, PartialEq)]
pub struct VolGrid {
    /// Samples along x, y, z.
    pub res: [usize; 3],
    /// Channels per sample.
    pub channels: usize,
    /// The bounding box the file states (min, max).
    pub bounds: (Vec3, Vec3),
    /// Samples, x fastest, channels interleaved.
    pub data: Vec<f32>,
}

/// Parses Mitsuba's binary grid volume format (see the module documentation).
pub fn read_vol(bytes: &[u8]) -> Result<VolGrid, String> {
    if bytes.len() < 48 {
        return Err(format!("{} bytes, shorter than the 48-byte header", bytes.len()));
    }
    if &bytes[..3] != b"VOL" {
        return Err("not a grid volume file (it does not start with \"VOL\")".into());
    }
    if bytes[3] != 3 {
        return Err(format!("file version {} (only version 3 is known)", bytes[3]));
    }
    let int = |o: usize| i32::from_le_bytes(bytes[o..o + 4].try_into().expect("4 bytes"));
    let float = |o: usize| f32::from_le_bytes(bytes[o..o + 4].try_into().expect("4 bytes"));
    let encoding = int(4);
    if encoding != 1 {
        return Err(format!("encoding {encoding} (only 1, float32, is supported)"));
    }
    let dims = [int(8), int(12), int(16)];
    let channels = int(20);
    if dims.iter().any(|&d| d <= 0) || channels <= 0 {
        return Err(format!(
            "resolution {} x {} x {} with {channels} channels (each must be at least 1)",
            dims[0], dims[1], dims[2]
        ));
    }
    let res = dims.map(|d| d as usize);
    let count = res
        .iter()
        .try_fold(channels as usize, |a, &d| a.checked_mul(d))
        .filter(|&n| n.checked_mul(4).is_some_and(|b| b <= bytes.len() - 48))
        .ok_or_else(|| {
            format!(
                "resolution {} x {} x {} with {channels} channels needs more data than the file's {} bytes",
                res[0],
                res[1],
                res[2],
                bytes.len() - 48
            )
        })?;
    if bytes.len() - 48 != count * 4 {
        return Err(format!(
            "{} bytes of samples for {count} float32 values",
            bytes.len() - 48
        ));
    }
    let bounds = (
        Vec3::new(float(24), float(28), float(32)),
        Vec3::new(float(36), float(40), float(44)),
    );
    let data = bytes[48..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect();
    Ok(VolGrid {
        res,
        channels: channels as usize,
        bounds,
        data,
    })
}

/// The grid of an `sdfgrid` shape in object space [0, 1]³, with its occupied voxels.
#[derive(Clone, Debug)]
pub struct SdfGrid {
    /// Samples along x, y, z (each at least 2).
    res: [usize; 3],
    /// Values, x fastest.
    data: Vec<f32>,
    /// Voxels whose corners change sign or touch zero, x fastest over (nx−1)(ny−1)(nz−1).
    occupied: Vec<bool>,
    /// Shading normals.
    pub normals: SdfNormals,
}

#[inline]
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    // Exact at both ends, so faces shared by two voxels interpolate identically.
    (1.0 - t) * a + t * b
}

#[inline]
fn bilerp(f: [f32; 4], u: f32, v: f32) -> f32 {
    lerp(lerp(f[0], f[1], u), lerp(f[2], f[3], u), v)
}

#[inline]
fn trilerp(s: &[f32; 8], q: Vec3) -> f32 {
    lerp(
        bilerp([s[0], s[1], s[2], s[3]], q.x, q.y),
        bilerp([s[4], s[5], s[6], s[7]], q.x, q.y),
        q.z,
    )
}

#[inline]
fn trilerp_grad(s: &[f32; 8], q: Vec3) -> Vec3 {
    Vec3::new(
        bilerp([s[1] - s[0], s[3] - s[2], s[5] - s[4], s[7] - s[6]], q.y, q.z),
        bilerp([s[2] - s[0], s[3] - s[1], s[6] - s[4], s[7] - s[5]], q.x, q.z),
        bilerp([s[4] - s[0], s[5] - s[1], s[6] - s[2], s[7] - s[3]], q.x, q.y),
    )
}

/// Real roots of a t² + b t + c, ascending (a = 0 handled as linear).
fn solve_quadratic(a: f32, b: f32, c: f32) -> Option<(f32, f32)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let x = -c / b;
        return Some((x, x));
    }
    let disc = b as f64 * b as f64 - 4.0 * a as f64 * c as f64;
    if disc < 0.0 {
        return None;
    }
    let q = -0.5 * (b as f64 + disc.sqrt().copysign(b as f64));
    let (x0, x1) = if q == 0.0 {
        (0.0, 0.0)
    } else {
        ((q / a as f64) as f32, (c as f64 / q) as f32)
    };
    Some((x0.min(x1), x0.max(x1)))
}

/// Newton iterations stop when a step is below this many ray-parameter units (Mitsuba: 1e-5;
/// ours is tighter so that hit points lie on the level set to a few ULPs and secondary rays
/// leave the surface cleanly).
const SOLVE_EPSILON: f32 = 1e-7;
/// Newton iterations at most.
const SOLVE_MAX_ITER: u32 = 60;

/// The first root of the cubic c₃s³ + c₂s² + c₁s + c₀ on [0, len] whose end values are
/// `f_beg`, `f_end` (Mitsuba's bracket split and safeguarded Newton).
fn first_root(len: f32, f_beg: f32, f_end: f32, c: [f32; 4]) -> Option<f32> {
    let [c3, c2, c1, c0] = c;
    let eval = |t: f32| ((c3 * t + c2) * t + c1) * t + c0;
    let (d2, d1) = (3.0 * c3, 2.0 * c2);
    let (mut t_near, mut t_far, mut f_near, mut f_far) = (0.0f32, len, f_beg, f_end);
    if let Some((r0, r1)) = solve_quadratic(d2, d1, c1) {
        for root in [r0, r1] {
            if t_near <= root && root <= t_far {
                let f_root = eval(root);
                if f_near * f_root <= 0.0 {
                    t_far = root;
                    f_far = f_root;
                } else {
                    t_near = root;
                    f_near = f_root;
                }
            }
        }
    }
    if f_near * f_far > 0.0 || f_near.is_nan() || f_far.is_nan() {
        return None;
    }
    let mut t = t_near + (t_far - t_near) * (-f_near / (f_far - f_near));
    if !(t >= t_near && t <= t_far) {
        t = 0.5 * (t_near + t_far);
    }
    for _ in 0..SOLVE_MAX_ITER {
        let f = eval(t);
        if f == 0.0 {
            return Some(t);
        }
        if f * f_near <= 0.0 {
            t_far = t;
        } else {
            t_near = t;
        }
        let deriv = (d2 * t + d1) * t + c1;
        let newton = t - f / deriv;
        let next = if newton > t_near && newton < t_far {
            newton
        } else {
            0.5 * (t_near + t_far)
        };
        let done = !((next - t).abs() >= SOLVE_EPSILON);
        t = next;
        if done {
            break;
        }
    }
    Some(t)
}

impl SdfGrid {
    /// The grid of a one-channel volume; `None` with a message when it cannot be one.
    pub fn new(vol: VolGrid, normals: SdfNormals) -> Result<Self, String> {
        if vol.channels != 1 {
            return Err(format!("the grid has {} channels, expected 1", vol.channels));
        }
        if vol.res.iter().any(|&n| n < 2) {
            return Err(format!(
                "resolution {} x {} x {}: an SDF grid needs at least 2 samples per axis",
                vol.res[0], vol.res[1], vol.res[2]
            ));
        }
        if let Some(i) = vol.data.iter().position(|v| !v.is_finite()) {
            return Err(format!("sample {i} is {}, not a finite number", vol.data[i]));
        }
        let [nx, ny, nz] = vol.res;
        let mut grid = Self {
            res: vol.res,
            data: vol.data,
            occupied: Vec::with_capacity((nx - 1) * (ny - 1) * (nz - 1)),
            normals,
        };
        for z in 0..nz - 1 {
            for y in 0..ny - 1 {
                for x in 0..nx - 1 {
                    let s = grid.corners(IVec3::new(x as i32, y as i32, z as i32));
                    let occ = s.iter().any(|&v| v >= 0.0) && s.iter().any(|&v| v <= 0.0);
                    grid.occupied.push(occ);
                }
            }
        }
        if !grid.occupied.iter().any(|&o| o) {
            return Err("the grid has no voxel containing surface (no sign change)".into());
        }
        Ok(grid)
    }

    /// Samples per axis.
    pub fn resolution(&self) -> [usize; 3] {
        self.res
    }

    #[inline]
    fn sample(&self, q: IVec3) -> f32 {
        let [nx, ny, nz] = self.res.map(|n| n as i32);
        let q = q.clamp(IVec3::ZERO, IVec3::new(nx - 1, ny - 1, nz - 1));
        self.data[((q.z * ny + q.y) * nx + q.x) as usize]
    }

    /// Corner values of voxel `v`, index x + 2y + 4z.
    #[inline]
    fn corners(&self, v: IVec3) -> [f32; 8] {
        std::array::from_fn(|i| {
            self.sample(v + IVec3::new((i & 1) as i32, ((i >> 1) & 1) as i32, (i >> 2) as i32))
        })
    }

    #[inline]
    fn scale(&self) -> Vec3 {
        Vec3::new(
            (self.res[0] - 1) as f32,
            (self.res[1] - 1) as f32,
            (self.res[2] - 1) as f32,
        )
    }

    #[inline]
    fn voxel_index(&self, v: IVec3) -> usize {
        let (nx, ny) = (self.res[0] - 1, self.res[1] - 1);
        (v.z as usize * ny + v.y as usize) * nx + v.x as usize
    }

    /// The voxel of flat index `i`.
    #[inline]
    pub fn voxel(&self, i: u32) -> IVec3 {
        let (nx, ny) = (self.res[0] - 1, self.res[1] - 1);
        let i = i as usize;
        IVec3::new((i % nx) as i32, ((i / nx) % ny) as i32, (i / (nx * ny)) as i32)
    }

    /// Object-space bounds: the unit cube.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (Vec3::ZERO, Vec3::ONE)
    }

    /// The first surface crossing of `o + t·d` (object space; `d` need not be unit) for `t` in
    /// `(0, tmax)`: `(t, voxel index)`.
    pub fn intersect(&self, o: Vec3, d: Vec3, tmax: f32) -> Option<(f32, u32)> {
        let scale = self.scale();
        let (g, dg) = (o * scale, d * scale);
        // Clip to the grid box [0, n − 1]³.
        let (mut t0, mut t1) = (0.0f32, tmax);
        for a in 0..3 {
            if dg[a] == 0.0 {
                if g[a] < 0.0 || g[a] > scale[a] {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / dg[a];
            let (mut ta, mut tb) = (-g[a] * inv, (scale[a] - g[a]) * inv);
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            t0 = t0.max(ta);
            t1 = t1.min(tb);
        }
        if !(t0 <= t1) {
            return None;
        }
        let cells = IVec3::new(
            self.res[0] as i32 - 2,
            self.res[1] as i32 - 2,
            self.res[2] as i32 - 2,
        );
        let start = g + dg * t0;
        let mut cell = start.floor().as_ivec3().clamp(IVec3::ZERO, cells);
        let step = IVec3::new(
            if dg.x > 0.0 { 1 } else { -1 },
            if dg.y > 0.0 { 1 } else { -1 },
            if dg.z > 0.0 { 1 } else { -1 },
        );
        let mut t_next = Vec3::INFINITY;
        let mut t_delta = Vec3::INFINITY;
        for a in 0..3 {
            if dg[a] != 0.0 {
                let face = (cell[a] + i32::from(step[a] > 0)) as f32;
                t_next[a] = (face - g[a]) / dg[a];
                t_delta[a] = 1.0 / dg[a].abs();
            }
        }
        let mut t_cur = t0;
        // The axis whose face the ray entered the current voxel through, if any.
        let mut entered: Option<usize> = None;
        loop {
            let exit_axis = if t_next.x <= t_next.y && t_next.x <= t_next.z {
                0
            } else if t_next.y <= t_next.z {
                1
            } else {
                2
            };
            let t_exit = t_next[exit_axis].min(t1);
            if self.occupied[self.voxel_index(cell)] && t_exit >= t_cur {
                let exit_face = (t_next[exit_axis] <= t1).then_some(exit_axis);
                if let Some(t) = self.voxel_root(cell, g, dg, step, t_cur, t_exit, entered, exit_face)
                    && t > 0.0
                    && t < tmax
                {
                    return Some((t, self.voxel_index(cell) as u32));
                }
            }
            if t_next[exit_axis] > t1 {
                return None;
            }
            cell[exit_axis] += step[exit_axis];
            if cell[exit_axis] < 0 || cell[exit_axis] > cells[exit_axis] {
                return None;
            }
            t_cur = t_next[exit_axis];
            t_next[exit_axis] += t_delta[exit_axis];
            entered = Some(exit_axis);
        }
    }

    /// The first root in voxel `v` on `[t_beg, t_end]` of the ray `g + t·dg` (grid units).
    #[allow(clippy::too_many_arguments)]
    fn voxel_root(
        &self,
        v: IVec3,
        g: Vec3,
        dg: Vec3,
        step: IVec3,
        t_beg: f32,
        t_end: f32,
        entered: Option<usize>,
        exit: Option<usize>,
    ) -> Option<f32> {
        let s = self.corners(v);
        let base = v.as_vec3();
        let mut p_beg = (g + dg * t_beg - base).clamp(Vec3::ZERO, Vec3::ONE);
        let mut p_end = (g + dg * t_end - base).clamp(Vec3::ZERO, Vec3::ONE);
        if let Some(a) = entered {
            p_beg[a] = if step[a] > 0 { 0.0 } else { 1.0 };
        }
        if let Some(a) = exit {
            p_end[a] = if step[a] > 0 { 1.0 } else { 0.0 };
        }
        let (f_beg, f_end) = (trilerp(&s, p_beg), trilerp(&s, p_end));
        // f(p_beg + u·dg) as a cubic in u (the paper's coefficients).
        let (o, d) = (p_beg, dg);
        let a = s[5] - s[4];
        let k0 = s[0];
        let k1 = s[1] - s[0];
        let k2 = s[2] - s[0];
        let k3 = s[3] - s[2] - k1;
        let k4 = s[4] - k0;
        let k5 = a - k1;
        let k6 = (s[6] - s[4]) - k2;
        let k7 = (s[7] - s[6] - a) - k3;
        let m0 = o.x * o.y;
        let m1 = d.x * d.y;
        let m2 = o.x * d.y + o.y * d.x;
        let m3 = k5 * o.z + k1;
        let m4 = k6 * o.z + k2;
        let m5 = k7 * o.z + k3;
        let c0 = (k4 * o.z + k0) + o.x * m3 + o.y * m4 + m0 * m5;
        let c1 = d.x * m3 + d.y * m4 + m2 * m5 + d.z * (k4 + k5 * o.x + k6 * o.y + k7 * m0);
        let c2 = m1 * m5 + d.z * (k5 * d.x + k6 * d.y + k7 * m2);
        let c3 = k7 * m1 * d.z;
        first_root(t_end - t_beg, f_beg, f_end, [c3, c2, c1, c0]).map(|u| t_beg + u)
    }

    /// The gradient of the trilinear interpolant of voxel `voxel` at object-space `p` (object
    /// units).
    pub fn gradient(&self, voxel: u32, p: Vec3) -> Vec3 {
        let v = self.voxel(voxel);
        let scale = self.scale();
        let q = (p * scale - v.as_vec3()).clamp(Vec3::ZERO, Vec3::ONE);
        trilerp_grad(&self.corners(v), q) * scale
    }

    /// The smooth shading normal direction at object-space `p` (not normalized, object space;
    /// Hansson-Söderlund et al. 2022, section 5): the eight voxels around the grid vertex
    /// nearest to `p`, each with its gradient by finite differences of the interpolant across
    /// the voxel along one axis at `p`'s position along the other two, blended trilinearly.
    pub fn smooth_normal(&self, p: Vec3) -> Vec3 {
        let res = self.scale();
        let n = IVec3::new(self.res[0] as i32, self.res[1] as i32, self.res[2] as i32);
        let sp = p * res;
        let v = sp.round().as_ivec3() - IVec3::ONE;
        let mut uvw = sp - v.as_vec3() - Vec3::splat(0.5);
        let cell = sp.floor().as_ivec3().clamp(IVec3::ZERO, n - IVec3::splat(2));
        let w = sp - cell.as_vec3();
        // The interpolant on the plane of sample index q along axis a, at p along the others.
        let plane = |a: usize, q: i32| -> f32 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let f: [f32; 4] = std::array::from_fn(|i| {
                let mut idx = IVec3::ZERO;
                idx[a] = q;
                idx[b] = cell[b] + (i & 1) as i32;
                idx[c] = cell[c] + (i >> 1) as i32;
                self.sample(idx)
            });
            bilerp(f, w[b], w[c])
        };
        let (mut d0, mut d1) = (Vec3::ZERO, Vec3::ZERO);
        for a in 0..3 {
            let upper = cell[a] != v[a];
            let g0 = plane(a, cell[a]);
            let g1 = plane(a, cell[a] + 1);
            let gq = plane(a, cell[a] + if upper { -1 } else { 2 });
            let dc = g1 - g0;
            let dq = if upper { g0 - gq } else { gq - g1 };
            d0[a] = if upper { dq } else { dc } * res[a];
            d1[a] = if upper { dc } else { dq } * res[a];
        }
        let inside = [v.x >= 0, v.y >= 0, v.z >= 0];
        for a in 0..3 {
            if !inside[a] {
                uvw[a] = 1.0;
            }
        }
        let corner = |i: usize| -> Vec3 {
            let hi = [i & 1 != 0, i & 2 != 0, i & 4 != 0];
            if (0..3).all(|a| hi[a] || inside[a]) {
                Vec3::new(
                    if hi[0] { d1.x } else { d0.x },
                    if hi[1] { d1.y } else { d0.y },
                    if hi[2] { d1.z } else { d0.z },
                )
                .normalize_or_zero()
            } else {
                Vec3::ZERO
            }
        };
        let l = |a: Vec3, b: Vec3, t: f32| a * (1.0 - t) + b * t;
        l(
            l(
                l(corner(0), corner(1), uvw.x),
                l(corner(2), corner(3), uvw.x),
                uvw.y,
            ),
            l(
                l(corner(4), corner(5), uvw.x),
                l(corner(6), corner(7), uvw.x),
                uvw.y,
            ),
            uvw.z,
        )
    }

    /// The interpolated value at object-space `p` (clamped to the grid).
    pub fn value(&self, p: Vec3) -> f32 {
        let scale = self.scale();
        let n = IVec3::new(self.res[0] as i32, self.res[1] as i32, self.res[2] as i32);
        let sp = p * scale;
        let v = sp.floor().as_ivec3().clamp(IVec3::ZERO, n - IVec3::splat(2));
        let q = (sp - v.as_vec3()).clamp(Vec3::ZERO, Vec3::ONE);
        trilerp(&self.corners(v), q)
    }
}
