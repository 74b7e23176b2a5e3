//! Stokes vectors and Mueller matrices per sampled wavelength, with their reference frames.
//!
//! # Conventions (Mitsuba 3's, `docs/src/key_topics/polarization.rst`, `render/mueller.h`)
//!
//! A Stokes vector s = (s0, s1, s2, s3) describes a beam travelling along `forward`: s0 the
//! radiance, s1 horizontal minus vertical linear polarization, s2 +45° minus −45°, s3 right minus
//! left circular. "Horizontal" means along the frame's x-axis, and the polarization ellipse is
//! seen **by an observer looking back along the beam** (towards the source), with
//! y = forward × x ([`StokesBasis`]). A Mueller matrix M maps the Stokes vector of the incident
//! beam (in its input basis) to that of the outgoing beam (in its output basis): s' = M s.
//!
//! The meaning of the numbers depends on the bases, so here every [`Stokes`] carries its basis and
//! every [`Mueller`] its input and output bases: a product `a * b` (b applied first) checks in
//! debug builds that `b`'s output basis is `a`'s input basis (a frame mismatch panics with both
//! bases), and [`Mueller::try_mul`] returns the mismatch as an error in every build. Elements that
//! look the same in every frame (the depolarizer diag(f, 0, 0, 0), scalars, circular polarizers:
//! the matrices that commute with every rotator) may be *frame-free*: they adopt the frames of
//! what they are multiplied with. [`Weight::ONE`], [`Weight::ZERO`] and
//! [`Weight::from_spectrum`] are frame-free, so a path throughput can start from them.
//!
//! # Change of basis
//!
//! Re-expressing a Stokes vector in a basis rotated by θ about `forward` (counter-clockwise seen
//! looking back along the beam, θ the signed angle from the current x-axis to the target one) is
//! the rotator (Collett, *Polarized Light*, ch. 5 eq. 43):
//!
//! ```text
//!     R(θ) = [1 0 0 0; 0 cos2θ sin2θ 0; 0 −sin2θ cos2θ 0; 0 0 0 1]
//!     s_target = R(θ) s_current,        M_target = R(θ_out) M R(θ_in)ᵀ
//! ```
//!
//! (Mitsuba's `rotate_stokes_basis` and `rotate_mueller_basis`.) Mitsuba never stores bases:
//! it uses the implicit basis of a direction, [`StokesBasis::implicit`] (`stokes_basis`, the first
//! vector of Duff et al. 2017's orthonormal basis). gonio's BSDFs return their matrices in those
//! implicit bases of their local frame too (input basis of −ω_light_in, output basis of
//! ω_light_out), so their numbers are Mitsuba's.
//!
//! # Standard elements
//!
//! | element                     | matrix                                                     | source |
//! |-----------------------------|------------------------------------------------------------|--------|
//! | depolarizer(f)              | diag(f, 0, 0, 0)                                           | Mitsuba `mueller::depolarizer` |
//! | absorber(f)                 | f·I                                                        | |
//! | linear polarizer (0°), t    | t/2 [1 1 0 0; 1 1 0 0; 0…; 0…]                             | Collett ch. 5 eq. 13 |
//! | linear retarder (fast 0°), δ| [1 0 0 0; 0 1 0 0; 0 0 cos δ sin δ; 0 0 −sin δ cos δ]      | Goldstein, *Polarized Light* 3rd ed. eq. 6.43 |
//! | right / left circular pol.  | ½ [1 0 0 ±1; 0…; 0…; ±1 0 0 1]                             | Chipman et al., table 6.2 |
//! | diattenuator(x, y)          | [a b 0 0; b a 0 0; 0 0 c 0; 0 0 0 c], a,b = (x ± y)/2, c = √(xy) | |
//! | rotated element M by θ      | R(θ)ᵀ M R(θ)                                               | Mitsuba `rotated_element` |

use crate::frame::Frame;
use crate::spectrum::SampledSpectrum;
use crate::weight::Weight;
use glam::Vec3;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign};

/// The reference frame of a Stokes vector: the direction the beam travels and the x-axis
/// ("horizontal") perpendicular to it; y = forward × x. Both unit vectors.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StokesBasis {
    forward: Vec3,
    x: Vec3,
}

/// Tolerance on the cosines between bases that are meant to be the same (f32 round-off of
/// frame transforms).
const SAME_BASIS_COS: f32 = 1.0 - 1e-4;

impl StokesBasis {
    /// A basis from a unit propagation direction and a unit x-axis perpendicular to it (checked
    /// in debug builds).
    #[inline]
    pub fn new(forward: Vec3, x: Vec3) -> Self {
        debug_assert!(
            (forward.length() - 1.0).abs() < 1e-3 && (x.length() - 1.0).abs() < 1e-3,
            "Stokes basis vectors must be unit: forward {forward}, x {x}"
        );
        debug_assert!(
            forward.dot(x).abs() < 1e-3,
            "x {x} is not perpendicular to forward {forward}"
        );
        Self { forward, x }
    }

    /// Mitsuba's implicit basis of a direction (`stokes_basis(forward)`: the first vector of
    /// `coordinate_system`, Duff et al. 2017, "Building an orthonormal basis, revisited").
    #[inline]
    pub fn implicit(forward: Vec3) -> Self {
        let sign = if forward.z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sign + forward.z);
        let b = forward.x * forward.y * a;
        let x = Vec3::new(
            forward.x * forward.x * a * sign + 1.0,
            b * sign,
            -forward.x * sign,
        );
        Self { forward, x }
    }

    /// The basis of `forward` whose x-axis is the s direction of a plane of incidence with normal
    /// `n`: normalize(n × forward), or `fallback` when forward ∥ n (Mitsuba's choice for the
    /// Fresnel matrices).
    #[inline]
    pub fn perpendicular_to_plane(forward: Vec3, n: Vec3, fallback: Vec3) -> Self {
        let s = n.cross(forward);
        let l = s.length();
        Self {
            forward,
            x: if l > 0.0 { s / l } else { fallback },
        }
    }

    /// The propagation direction.
    #[inline]
    pub fn forward(&self) -> Vec3 {
        self.forward
    }
    /// The x-axis ("horizontal").
    #[inline]
    pub fn x(&self) -> Vec3 {
        self.x
    }
    /// The y-axis, forward × x.
    #[inline]
    pub fn y(&self) -> Vec3 {
        self.forward.cross(self.x)
    }

    /// True when both vectors agree within f32 round-off.
    #[inline]
    pub fn same_as(&self, o: &StokesBasis) -> bool {
        self.forward.dot(o.forward) > SAME_BASIS_COS && self.x.dot(o.x) > SAME_BASIS_COS
    }

    /// True when both describe the same beam direction.
    #[inline]
    pub fn same_forward(&self, o: &StokesBasis) -> bool {
        self.forward.dot(o.forward) > SAME_BASIS_COS
    }

    /// The basis with both vectors mapped by a linear map (a frame change `Frame::to_world`, a
    /// mirror): the caller states the map, the basis follows it.
    #[inline]
    pub fn transformed(&self, f: impl Fn(Vec3) -> Vec3) -> Self {
        Self {
            forward: f(self.forward),
            x: f(self.x),
        }
    }

    /// The signed angle θ from this x-axis to `target`'s about `forward` (Mitsuba's
    /// `rotate_stokes_basis`): re-expressing a Stokes vector in `target` is `R(θ)`. The
    /// directions must agree (checked in debug builds).
    #[inline]
    pub fn angle_to(&self, target: &StokesBasis) -> f32 {
        debug_assert!(
            self.same_forward(target),
            "rotation between bases of different beams: {self:?} → {target:?}"
        );
        let c = self.x.cross(target.x);
        let theta = c.length().atan2(self.x.dot(target.x));
        if self.forward.dot(c) < 0.0 { -theta } else { theta }
    }
}

/// Four Stokes components, each per wavelength.
pub type StokesComponents = [SampledSpectrum; 4];

/// A 4×4 matrix of spectra without frames (row-major, `m.0[row][col]`): the arithmetic under
/// [`Mueller`]. Only this module and the Fresnel code build them; everything else uses
/// [`Mueller`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MuellerMatrix(pub [[SampledSpectrum; 4]; 4]);

impl MuellerMatrix {
    /// All zeros.
    pub const ZERO: Self = Self([[SampledSpectrum::ZERO; 4]; 4]);
    /// The identity.
    pub const IDENTITY: Self = {
        let (o, z) = (SampledSpectrum::ONE, SampledSpectrum::ZERO);
        Self([[o, z, z, z], [z, o, z, z], [z, z, o, z], [z, z, z, o]])
    };

    /// The same scalar matrix at every wavelength.
    pub fn from_f32(rows: [[f32; 4]; 4]) -> Self {
        Self(rows.map(|r| r.map(SampledSpectrum::splat)))
    }

    /// Element (row, col).
    #[inline]
    pub fn get(&self, row: usize, col: usize) -> SampledSpectrum {
        self.0[row][col]
    }

    /// Mᵀ.
    #[inline]
    pub fn transpose(&self) -> Self {
        let mut t = Self::ZERO;
        for (i, row) in self.0.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                t.0[j][i] = *v;
            }
        }
        t
    }

    /// M s.
    #[inline]
    pub fn apply(&self, s: &StokesComponents) -> StokesComponents {
        std::array::from_fn(|i| {
            let r = &self.0[i];
            r[0] * s[0] + r[1] * s[1] + r[2] * s[2] + r[3] * s[3]
        })
    }

    /// Every element times the spectrum `f` (an absorber applied after or before).
    #[inline]
    pub fn scaled(&self, f: SampledSpectrum) -> Self {
        Self(self.0.map(|r| r.map(|v| v * f)))
    }

    /// The rotator R(θ) (Collett ch. 5 eq. 43; Mitsuba's `rotator`).
    #[inline]
    pub fn rotator(theta: f32) -> Self {
        let (s, c) = (2.0 * theta).sin_cos();
        Self::from_f32([
            [1.0, 0.0, 0.0, 0.0],
            [0.0, c, s, 0.0],
            [0.0, -s, c, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ])
    }

    /// R(θ)ᵀ M R(θ): the element turned by θ (Mitsuba's `rotated_element`).
    pub fn rotated_element(&self, theta: f32) -> Self {
        let r = Self::rotator(theta);
        r.transpose() * *self * r
    }

    /// The matrix of an element whose s/p (x/y) axes carry the reflection or transmission of a
    /// plane interface: [a b 0 0; b a 0 0; 0 0 c −d; 0 0 d c] per wavelength (Mitsuba's
    /// `specular_reflection` layout; d = 0 for transmission).
    #[inline]
    pub fn interface(a: SampledSpectrum, b: SampledSpectrum, c: SampledSpectrum, d: SampledSpectrum) -> Self {
        let z = SampledSpectrum::ZERO;
        Self([[a, b, z, z], [b, a, z, z], [z, z, c, -d], [z, z, d, c]])
    }

    /// Largest |element| difference to `o` relative to max(|M00|, tiny), for tests and checks.
    pub fn max_abs_diff(&self, o: &Self) -> f32 {
        let mut m = 0.0f32;
        for i in 0..4 {
            for j in 0..4 {
                m = m.max((self.0[i][j] - o.0[i][j]).0.abs().max_element());
            }
        }
        m
    }

    /// True when every output is unpolarized (rows S1..S3 exactly zero at every wavelength, as a
    /// depolarizer's and every product that ends in one): the output basis carries no meaning.
    fn output_unpolarized(&self) -> bool {
        self.0[1..].iter().all(|row| row.iter().all(|v| v.is_black()))
    }

    /// True when the output depends on the input's intensity only (columns S1..S3 exactly zero):
    /// the input basis carries no meaning.
    fn reads_intensity_only(&self) -> bool {
        self.0.iter().all(|row| row[1..].iter().all(|v| v.is_black()))
    }

    /// True when M commutes with every rotator (frame-free elements).
    fn rotation_invariant(&self) -> bool {
        let r = Self::rotator(0.37);
        let tol = 1e-5 * (1.0 + self.0[0][0].0.abs().max_element());
        (r * *self).max_abs_diff(&(*self * r)) <= tol
    }
}

impl Mul for MuellerMatrix {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let mut r = Self::ZERO;
        for i in 0..4 {
            for j in 0..4 {
                r.0[i][j] = self.0[i][0] * o.0[0][j]
                    + self.0[i][1] * o.0[1][j]
                    + self.0[i][2] * o.0[2][j]
                    + self.0[i][3] * o.0[3][j];
            }
        }
        r
    }
}

impl Add for MuellerMatrix {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        let mut r = self;
        for i in 0..4 {
            for j in 0..4 {
                r.0[i][j] += o.0[i][j];
            }
        }
        r
    }
}

impl Mul<f32> for MuellerMatrix {
    type Output = Self;
    #[inline]
    fn mul(self, k: f32) -> Self {
        Self(self.0.map(|r| r.map(|v| v * k)))
    }
}

/// A Stokes vector per wavelength with its basis (`None` for an unpolarized beam, whose numbers
/// (s0, 0, 0, 0) mean the same in every basis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stokes {
    s: StokesComponents,
    basis: Option<StokesBasis>,
}

impl Stokes {
    /// Unpolarized light of radiance `s0`.
    pub fn unpolarized(s0: SampledSpectrum) -> Self {
        let z = SampledSpectrum::ZERO;
        Self {
            s: [s0, z, z, z],
            basis: None,
        }
    }

    /// A Stokes vector in a basis.
    pub fn new(s: StokesComponents, basis: StokesBasis) -> Self {
        Self {
            s,
            basis: Some(basis),
        }
    }

    /// The components.
    pub fn components(&self) -> StokesComponents {
        self.s
    }

    /// The basis (`None` for unpolarized light).
    pub fn basis(&self) -> Option<StokesBasis> {
        self.basis
    }

    /// The same light expressed in `target` (Mitsuba's `rotate_stokes_basis`).
    pub fn in_basis(&self, target: StokesBasis) -> Self {
        let s = match self.basis {
            Some(b) => MuellerMatrix::rotator(b.angle_to(&target)).apply(&self.s),
            None => self.s,
        };
        Self::new(s, target)
    }

    /// Degree of polarization √(s1² + s2² + s3²)/s0 per wavelength (0 where s0 = 0).
    pub fn degree_of_polarization(&self) -> SampledSpectrum {
        let p = (self.s[1] * self.s[1] + self.s[2] * self.s[2] + self.s[3] * self.s[3]).sqrt();
        p.safe_div(self.s[0])
    }

    /// True when s0 ≥ √(s1² + s2² + s3²) − `tol`·s0 at every wavelength (a physical state).
    pub fn is_physical(&self, tol: f32) -> bool {
        let p = (self.s[1] * self.s[1] + self.s[2] * self.s[2] + self.s[3] * self.s[3]).sqrt();
        (0..4).all(|i| self.s[0][i] >= 0.0 && p[i] <= self.s[0][i] * (1.0 + tol) + 1e-7)
    }
}

/// Two bases that a product or sum needed to be the same were not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameMismatch {
    /// The basis the left operand expects.
    pub expected: StokesBasis,
    /// The basis the right operand provides.
    pub found: StokesBasis,
}

impl std::fmt::Display for FrameMismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Stokes frames differ: expected forward {} x {}, found forward {} x {} (rotate first)",
            self.expected.forward, self.expected.x, self.found.forward, self.found.x
        )
    }
}

impl std::error::Error for FrameMismatch {}

/// A Mueller matrix per wavelength with its input and output bases (`None`: a frame-free element,
/// see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mueller {
    m: MuellerMatrix,
    frames: Option<(StokesBasis, StokesBasis)>,
}

impl Mueller {
    /// M from Stokes vectors in `input` to Stokes vectors in `output`.
    #[inline]
    pub fn new(m: MuellerMatrix, input: StokesBasis, output: StokesBasis) -> Self {
        Self {
            m,
            frames: Some((input, output)),
        }
    }

    /// A frame-free element; `m` must commute with every rotator (checked in debug builds).
    #[inline]
    pub fn frame_free(m: MuellerMatrix) -> Self {
        debug_assert!(m.rotation_invariant(), "not a frame-free Mueller matrix: {m:?}");
        Self { m, frames: None }
    }

    /// The ideal depolarizer diag(f, 0, 0, 0): a depolarizing BSDF value f.
    #[inline]
    pub fn depolarizer(f: SampledSpectrum) -> Self {
        let mut m = MuellerMatrix::ZERO;
        m.0[0][0] = f;
        Self { m, frames: None }
    }

    /// The absorber f·I.
    #[inline]
    pub fn absorber(f: SampledSpectrum) -> Self {
        Self {
            m: MuellerMatrix::IDENTITY.scaled(f),
            frames: None,
        }
    }

    /// An ideal linear polarizer (attenuation `t`, 1 ideal) transmitting along `basis`'s x-axis,
    /// for a beam along `basis.forward()` (Collett ch. 5 eq. 13).
    pub fn linear_polarizer(t: SampledSpectrum, basis: StokesBasis) -> Self {
        let a = t * 0.5;
        let z = SampledSpectrum::ZERO;
        Self::new(
            MuellerMatrix([[a, a, z, z], [a, a, z, z], [z; 4], [z; 4]]),
            basis,
            basis,
        )
    }

    /// A linear retarder with its fast axis along `basis`'s x-axis and phase difference `delta`
    /// (Goldstein eq. 6.43): quarter-wave δ = π/2, half-wave δ = π.
    pub fn linear_retarder(delta: f32, basis: StokesBasis) -> Self {
        let (s, c) = delta.sin_cos();
        Self::new(
            MuellerMatrix::from_f32([
                [1.0, 0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0, 0.0],
                [0.0, 0.0, c, s],
                [0.0, 0.0, -s, c],
            ]),
            basis,
            basis,
        )
    }

    /// The right (`right = true`) or left circular polarizer (Chipman et al. table 6.2):
    /// frame-free.
    pub fn circular_polarizer(right: bool) -> Self {
        let h = if right { 0.5 } else { -0.5 };
        Self::frame_free(MuellerMatrix::from_f32([
            [0.5, 0.0, 0.0, h],
            [0.0; 4],
            [0.0; 4],
            [h, 0.0, 0.0, 0.5],
        ]))
    }

    /// The linear diattenuator attenuating the field along x by `x` and along y by `y`.
    pub fn diattenuator(x: SampledSpectrum, y: SampledSpectrum, basis: StokesBasis) -> Self {
        let z = SampledSpectrum::ZERO;
        Self::new(
            MuellerMatrix::interface((x + y) * 0.5, (x - y) * 0.5, (x * y).sqrt(), z),
            basis,
            basis,
        )
    }

    /// The rotator R(θ) acting in one basis (a counter-clockwise rotation of the field by θ seen
    /// looking back along the beam, Mitsuba's `rotator`).
    pub fn rotator(theta: f32, basis: StokesBasis) -> Self {
        Self::new(MuellerMatrix::rotator(theta), basis, basis)
    }

    /// The matrix (in the frames of [`Mueller::frames`]).
    #[inline]
    pub fn matrix(&self) -> &MuellerMatrix {
        &self.m
    }

    /// (input basis, output basis), `None` for a frame-free element.
    #[inline]
    pub fn frames(&self) -> Option<(StokesBasis, StokesBasis)> {
        self.frames
    }

    /// Element (row, col).
    #[inline]
    pub fn get(&self, row: usize, col: usize) -> SampledSpectrum {
        self.m.0[row][col]
    }

    /// The same element expressed from `input` to `output` (Mitsuba's `rotate_mueller_basis`):
    /// each new basis must describe the same beam as the old one. A frame-free element is
    /// unchanged and takes the given bases.
    pub fn in_bases(&self, input: StokesBasis, output: StokesBasis) -> Self {
        let m = match self.frames {
            None => self.m,
            Some((i, o)) => {
                let r_in = MuellerMatrix::rotator(i.angle_to(&input));
                let r_out = MuellerMatrix::rotator(o.angle_to(&output));
                r_out * self.m * r_in.transpose()
            }
        };
        Self::new(m, input, output)
    }

    /// Expressed in Mitsuba's implicit bases of its own directions.
    pub fn in_implicit_bases(&self) -> Self {
        match self.frames {
            None => *self,
            Some((i, o)) => self.in_bases(StokesBasis::implicit(i.forward), StokesBasis::implicit(o.forward)),
        }
    }

    /// Both bases mapped by a linear map of directions (a local-to-world frame change, a rotation);
    /// the matrix is unchanged (the bases move with the element). For a reflection of space (a
    /// mirror, det = −1) use [`Mueller::mirrored`].
    pub fn transformed(&self, f: impl Fn(Vec3) -> Vec3) -> Self {
        Self {
            m: self.m,
            frames: self.frames.map(|(i, o)| (i.transformed(&f), o.transformed(&f))),
        }
    }

    /// The element seen in a mirror `f` (det = −1, e.g. z ↦ −z): the bases are mirrored, which
    /// turns them left-handed, and re-expressing in right-handed bases (y ↦ −y) flips the signs of
    /// s2 and s3: M ↦ P M P with P = diag(1, 1, −1, −1).
    pub fn mirrored(&self, f: impl Fn(Vec3) -> Vec3) -> Self {
        let mut m = self.m;
        for (i, row) in m.0.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                if (i >= 2) != (j >= 2) {
                    *v = -*v;
                }
            }
        }
        Self {
            m,
            frames: self.frames.map(|(i, o)| (i.transformed(&f), o.transformed(&f))),
        }
    }

    /// `self * b` (b first), or the mismatch of `b`'s output basis and `self`'s input basis.
    /// The bases need not meet where one side makes them meaningless: `b`'s light leaves
    /// unpolarized (a depolarizer's product: light order after a diffuse vertex), or `self` reads
    /// its intensity only.
    #[inline]
    pub fn try_mul(&self, b: &Mueller) -> Result<Mueller, FrameMismatch> {
        let frames = match (self.frames, b.frames) {
            (None, f) | (f, None) => f,
            (Some((ai, ao)), Some((bi, bo))) => {
                if !ai.same_as(&bo) && !b.m.output_unpolarized() && !self.m.reads_intensity_only() {
                    return Err(FrameMismatch {
                        expected: ai,
                        found: bo,
                    });
                }
                Some((bi, ao))
            }
        };
        Ok(Mueller {
            m: self.m * b.m,
            frames,
        })
    }

    /// `self + b`: the frames must agree (or one side be frame-free).
    #[inline]
    pub fn try_add(&self, b: &Mueller) -> Result<Mueller, FrameMismatch> {
        let frames = match (self.frames, b.frames) {
            (None, f) | (f, None) => f,
            (Some((ai, ao)), Some((bi, bo))) => {
                for (e, f) in [(ai, bi), (ao, bo)] {
                    if !e.same_as(&f) {
                        return Err(FrameMismatch {
                            expected: e,
                            found: f,
                        });
                    }
                }
                Some((ai, ao))
            }
        };
        Ok(Mueller {
            m: self.m + b.m,
            frames,
        })
    }

    /// M s: the Stokes vector must be in the input basis (or be unpolarized, or M frame-free).
    pub fn try_apply(&self, s: &Stokes) -> Result<Stokes, FrameMismatch> {
        match (self.frames, s.basis) {
            (Some((i, o)), Some(b)) => {
                if !i.same_as(&b) && !self.m.reads_intensity_only() {
                    return Err(FrameMismatch {
                        expected: i,
                        found: b,
                    });
                }
                Ok(Stokes::new(self.m.apply(&s.s), o))
            }
            (Some((_, o)), None) => Ok(Stokes::new(self.m.apply(&s.s), o)),
            (None, basis) => Ok(Stokes {
                s: self.m.apply(&s.s),
                basis,
            }),
        }
    }

    /// [`Mueller::try_apply`], panicking on a frame mismatch.
    pub fn apply(&self, s: &Stokes) -> Stokes {
        self.try_apply(s).unwrap_or_else(|e| panic!("{e}"))
    }
}

impl Mul for Mueller {
    type Output = Self;
    /// `self * b` (b first). The frames are checked in debug builds (see [`Mueller::try_mul`]).
    #[inline]
    fn mul(self, b: Self) -> Self {
        match self.try_mul(&b) {
            Ok(r) => r,
            Err(e) => {
                debug_assert!(false, "{e}");
                Mueller {
                    m: self.m * b.m,
                    frames: b.frames.map(|(bi, _)| (bi, self.frames.map_or(bi, |f| f.1))),
                }
            }
        }
    }
}

impl MulAssign for Mueller {
    #[inline]
    fn mul_assign(&mut self, b: Self) {
        *self = *self * b;
    }
}

impl Mul<f32> for Mueller {
    type Output = Self;
    #[inline]
    fn mul(self, k: f32) -> Self {
        Self {
            m: self.m * k,
            frames: self.frames,
        }
    }
}

impl MulAssign<f32> for Mueller {
    #[inline]
    fn mul_assign(&mut self, k: f32) {
        self.m = self.m * k;
    }
}

impl Mul<SampledSpectrum> for Mueller {
    type Output = Self;
    /// The element followed (or preceded: it commutes) by the absorber of `f`.
    #[inline]
    fn mul(self, f: SampledSpectrum) -> Self {
        Self {
            m: self.m.scaled(f),
            frames: self.frames,
        }
    }
}

impl Div<f32> for Mueller {
    type Output = Self;
    #[inline]
    fn div(self, k: f32) -> Self {
        self * (1.0 / k)
    }
}

impl DivAssign<f32> for Mueller {
    #[inline]
    fn div_assign(&mut self, k: f32) {
        *self = *self / k;
    }
}

impl Add for Mueller {
    type Output = Self;
    /// The sum of two elements in the same frames (checked in debug builds).
    #[inline]
    fn add(self, b: Self) -> Self {
        match self.try_add(&b) {
            Ok(r) => r,
            Err(e) => {
                debug_assert!(false, "{e}");
                Mueller {
                    m: self.m + b.m,
                    frames: self.frames,
                }
            }
        }
    }
}

impl AddAssign for Mueller {
    #[inline]
    fn add_assign(&mut self, b: Self) {
        *self = *self + b;
    }
}

impl Weight for Mueller {
    const ZERO: Self = Mueller {
        m: MuellerMatrix::ZERO,
        frames: None,
    };
    const ONE: Self = Mueller {
        m: MuellerMatrix::IDENTITY,
        frames: None,
    };
    /// The depolarizer diag(f, 0, 0, 0).
    #[inline]
    fn from_spectrum(s: SampledSpectrum) -> Self {
        Mueller::depolarizer(s)
    }
    /// M00: the radiance a path of throughput M carries from an unpolarized source (emitters are
    /// unpolarized, and an intensity camera reads S0 = M00·L).
    #[inline]
    fn intensity(self) -> SampledSpectrum {
        self.m.0[0][0]
    }
    /// Bases mapped by the (right-handed, orthonormal) `frame` and re-expressed in the implicit
    /// world bases of the same beams ([`Mueller::in_implicit_bases`]).
    #[inline]
    fn local_to_world(self, frame: &Frame) -> Self {
        match self.frames {
            None => self,
            Some(_) => self.transformed(|v| frame.to_world(v)).in_implicit_bases(),
        }
    }
    /// `self · t · D(Lₑ)`: the source is unpolarized, so it enters last as a depolarizer.
    #[inline]
    fn through_then_source(self, t: Self, le: SampledSpectrum) -> Self {
        self * t * Mueller::depolarizer(le)
    }
}

#[cfg(test)]
#[path = "mueller_tests.rs"]
mod tests;
