//! The BSDF interface every model implements.
//!
//! # Conventions
//!
//! * **Local shading frame**: the normal is +z; cos θ(ω) = ω.z. Every direction is a unit vector
//!   pointing *away* from the surface.
//! * **Names follow Mitsuba 3**: `wi` is the direction the path arrived from (towards the camera
//!   in [`TransportMode::Radiance`]); `wo` is the direction being sampled or evaluated (towards
//!   the light in radiance mode). pbrt-v4 swaps the two names.
//! * [`Bsdf::eval`] returns the BSDF value **f(wi, wo) without the cosine** (1/sr), non-delta
//!   lobes only; a delta lobe evaluates to 0.
//! * [`Bsdf::pdf`] is the solid-angle density with which [`Bsdf::sample`] produces `wo`,
//!   including the probability of choosing the lobe, over the non-delta lobes enabled in the
//!   context. Delta lobes have pdf 0 here.
//! * [`Bsdf::sample`] returns [`BsdfSample`] with `weight = f·|cos θo| / pdf` for a smooth lobe,
//!   and for a delta lobe the lobe's throughput divided by the probability of choosing it
//!   (stored in `pdf`, a discrete probability). `eta` is the relative index crossed,
//!   n(wo side)/n(wi side) (see [`BsdfSample::eta`]), 1 for reflections.
//! * **Transport mode**: in radiance mode a refraction multiplies the weight by
//!   (η_wi / η_wo)², the compression of radiance into a smaller solid angle; in importance mode
//!   it does not. So f_importance(a, b) = f_radiance(b, a): importance mode is the transpose.
//! * **Wavelengths**: every call carries the path's [`SampledWavelengths`]. `sample` takes them
//!   mutably because a dispersive refraction terminates the secondaries (see `crate::ior`).
//! * A call never allocates and never performs I/O.
//!
//! # Extensions without a rewrite
//!
//! Stochastic models (Heitz 2016 random walks, layered BSDFs) seed their own generator from a
//! hash of (wi, wo) so `eval`/`pdf` stay deterministic functions of their arguments, and draw the
//! rest of their randomness in `sample` from the `u1`, `u2` they are given. Such a model says
//! [`Bsdf::pdf_is_exact`] = false: its `sample().weight` is exact, its `eval` an unbiased
//! estimate and its `pdf` an approximation for MIS weights only (`crate::microsurface`).
//! Polarization adds methods with defaults that depolarize (a Mueller matrix diag(f, 0, 0, 0)):
//! [`Bsdf::eval_mueller`], [`Bsdf::sample_mueller`], [`Bsdf::null_transmission_mueller`],
//! leaving every unpolarized caller unchanged; polarizing models override them.

use crate::mueller::Mueller;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Lobe kinds, as bit sets. A lobe is one kind of scattering (`REFLECTION | DIFFUSE`, ...); a
/// BSDF's flags are the union of its lobes'.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct BsdfFlags(pub u32);

impl BsdfFlags {
    /// No lobe.
    pub const NONE: Self = Self(0);
    /// Leaves on the side of `wi`.
    pub const REFLECTION: Self = Self(1);
    /// Leaves on the other side.
    pub const TRANSMISSION: Self = Self(2);
    /// Lambertian-like, broad.
    pub const DIFFUSE: Self = Self(4);
    /// Rough specular.
    pub const GLOSSY: Self = Self(8);
    /// A Dirac delta (ideal mirror, ideal refraction).
    pub const DELTA: Self = Self(16);
    /// Passes straight through without changing the medium (thin sheet); used with TRANSMISSION.
    pub const NULL: Self = Self(32);
    /// The lobe is not reciprocal (refraction in radiance mode).
    pub const NON_SYMMETRIC: Self = Self(64);
    /// The BSDF depends on the azimuths of wi and wo, not only on their difference (Mitsuba's
    /// `Anisotropic`): a property of the BSDF, not a lobe kind; the isotropy check then asks for
    /// the variation to be visible instead of absent.
    pub const ANISOTROPIC: Self = Self(128);

    /// Lambertian reflection.
    pub const DIFFUSE_REFLECTION: Self = Self(1 | 4);
    /// Diffuse transmission.
    pub const DIFFUSE_TRANSMISSION: Self = Self(2 | 4);
    /// Rough reflection.
    pub const GLOSSY_REFLECTION: Self = Self(1 | 8);
    /// Rough transmission.
    pub const GLOSSY_TRANSMISSION: Self = Self(2 | 8);
    /// Mirror reflection.
    pub const DELTA_REFLECTION: Self = Self(1 | 16);
    /// Ideal refraction.
    pub const DELTA_TRANSMISSION: Self = Self(2 | 16);
    /// Every kind enabled (the default context mask).
    pub const ALL: Self = Self(1 | 2 | 4 | 8 | 16 | 32 | 64);
    /// Diffuse or glossy: lobes with a density.
    pub const SMOOTH: Self = Self(4 | 8);

    /// True when every bit of `other` is set in `self`.
    #[inline]
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
    /// True when `self` and `other` share a bit.
    #[inline]
    pub const fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }
    /// True for a Dirac lobe.
    #[inline]
    pub const fn is_delta(self) -> bool {
        self.intersects(Self::DELTA)
    }
    /// True when some lobe has a density (diffuse or glossy).
    #[inline]
    pub const fn has_smooth(self) -> bool {
        self.intersects(Self::SMOOTH)
    }
    /// True for a reflection.
    #[inline]
    pub const fn is_reflection(self) -> bool {
        self.intersects(Self::REFLECTION)
    }
    /// True for a transmission.
    #[inline]
    pub const fn is_transmission(self) -> bool {
        self.intersects(Self::TRANSMISSION)
    }
    /// Both sets of bits.
    #[inline]
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }
}

impl std::ops::BitOr for BsdfFlags {
    type Output = Self;
    #[inline]
    fn bitor(self, o: Self) -> Self {
        Self(self.0 | o.0)
    }
}
impl std::ops::BitAnd for BsdfFlags {
    type Output = Self;
    #[inline]
    fn bitand(self, o: Self) -> Self {
        Self(self.0 & o.0)
    }
}

impl std::fmt::Display for BsdfFlags {
    /// `reflection|delta`-style names, used by `gonio bsdf sample`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        const NAMES: [(BsdfFlags, &str); 8] = [
            (BsdfFlags::REFLECTION, "reflection"),
            (BsdfFlags::TRANSMISSION, "transmission"),
            (BsdfFlags::DIFFUSE, "diffuse"),
            (BsdfFlags::GLOSSY, "glossy"),
            (BsdfFlags::DELTA, "delta"),
            (BsdfFlags::NULL, "null"),
            (BsdfFlags::NON_SYMMETRIC, "nonsymmetric"),
            (BsdfFlags::ANISOTROPIC, "anisotropic"),
        ];
        let mut first = true;
        for (flag, name) in NAMES {
            if self.contains(flag) {
                if !first {
                    f.write_str("|")?;
                }
                f.write_str(name)?;
                first = false;
            }
        }
        if first {
            f.write_str("none")?;
        }
        Ok(())
    }
}

/// Which quantity a path carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum TransportMode {
    /// Paths from the camera carrying radiance: refraction scales by (η_wi/η_wo)².
    #[default]
    Radiance,
    /// Paths from lights carrying importance (adjoint BSDF): no η² factor.
    Importance,
}

impl TransportMode {
    /// The other mode.
    pub fn reverse(self) -> Self {
        match self {
            TransportMode::Radiance => TransportMode::Importance,
            TransportMode::Importance => TransportMode::Radiance,
        }
    }
}

/// Per-call settings: the transport mode and the lobes enabled (Mitsuba's `BSDFContext`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BsdfContext {
    /// Radiance or importance.
    pub mode: TransportMode,
    /// A lobe with flags `L` takes part iff `lobes.contains(L's kind bits)`; default all.
    pub lobes: BsdfFlags,
}

impl Default for BsdfContext {
    fn default() -> Self {
        Self {
            mode: TransportMode::Radiance,
            lobes: BsdfFlags::ALL,
        }
    }
}

impl BsdfContext {
    /// Radiance mode, all lobes.
    pub const fn radiance() -> Self {
        Self {
            mode: TransportMode::Radiance,
            lobes: BsdfFlags::ALL,
        }
    }
    /// Importance mode, all lobes.
    pub const fn importance() -> Self {
        Self {
            mode: TransportMode::Importance,
            lobes: BsdfFlags::ALL,
        }
    }
    /// The same mode with only the lobes whose kinds are in `lobes`.
    pub const fn with_lobes(self, lobes: BsdfFlags) -> Self {
        Self {
            mode: self.mode,
            lobes,
        }
    }
    /// True when a lobe with these flags is enabled. Only the kind bits (reflection,
    /// transmission, diffuse, glossy, delta) are compared.
    #[inline]
    pub const fn is_enabled(&self, lobe: BsdfFlags) -> bool {
        let kind = lobe.0 & 0b11111;
        self.lobes.0 & kind == kind
    }
}

/// Both lobes of a two-lobe interface at once, for the path tracer's lobe splitting
/// (`gonio_render`'s `split_escapes`): the reflection and the refraction that
/// [`Bsdf::sample`] chooses between with the same numbers (for a rough interface: about the one
/// facet it draws). Each lobe's `weight` is that lobe's alone (f·|cos θo|/p_lobe, not divided
/// by the probability of choosing it), while its `pdf` is what `sample` would report for the
/// same direction, so that MIS weights stay the same functions of the path.
#[derive(Clone, Copy, Debug)]
pub struct LobeSplit {
    /// The reflection and the probability F with which `sample` takes it.
    pub reflection: Option<(BsdfSample, f32)>,
    /// The refraction (for a coated material, `plastic`, the base's diffuse lobe) and its
    /// probability 1 − F.
    pub refraction: Option<(BsdfSample, f32)>,
    /// F, the probability with which `sample` takes the reflection (whether or not its direction
    /// is valid: `sample` fails where the lobe it takes does; for `plastic`, P_spec).
    pub reflectance: f32,
}

impl LobeSplit {
    /// Neither lobe.
    pub const NONE: Self = Self {
        reflection: None,
        refraction: None,
        reflectance: 0.0,
    };

    /// The split of a smooth interface whose `sample` takes its delta reflection with
    /// probability `reflectance` and its `transmission` lobe otherwise: each lobe as
    /// `sample` makes it with that lobe alone enabled (`alone(lobe, wl)`, which then takes it
    /// with probability 1: weight F or 1 − F, times tints), with its choice's probability as
    /// its `pdf`.
    pub fn of_delta_lobes(
        reflectance: f32,
        transmission: BsdfFlags,
        wl: &mut SampledWavelengths,
        mut alone: impl FnMut(BsdfFlags, &mut SampledWavelengths) -> Option<BsdfSample>,
    ) -> Self {
        let mut lobe = |flags: BsdfFlags, choice: f32, wl: &mut SampledWavelengths| {
            alone(flags, wl)
                .map(|bs| (BsdfSample { pdf: choice, ..bs }, choice))
                .filter(|_| choice > 0.0)
        };
        Self {
            reflection: lobe(BsdfFlags::DELTA_REFLECTION, reflectance, wl),
            refraction: lobe(transmission, 1.0 - reflectance, wl),
            reflectance,
        }
    }
}

/// The result of [`Bsdf::sample`].
///
/// The weight's type is a parameter ([`crate::weight::Weight`]): a spectrum here, a Mueller
/// matrix for a polarized renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample<W = SampledSpectrum> {
    /// The sampled direction, local frame, unit length.
    pub wo: Vec3,
    /// f·|cos θo|/pdf for smooth lobes; throughput/selection probability for delta lobes.
    pub weight: W,
    /// Solid-angle density (smooth lobe) or discrete selection probability (delta lobe).
    pub pdf: f32,
    /// The lobe that was sampled.
    pub flags: BsdfFlags,
    /// Relative index crossed, n(wo side)/n(wi side) for a refraction (Mitsuba's `eta`); 1 for
    /// reflections and for null transmission. An integrator multiplies its running η product by
    /// it so that Russian roulette can undo the radiance η² scaling.
    pub eta: f32,
}

impl<W: std::fmt::Display> std::fmt::Display for BsdfSample<W> {
    /// `wo (x, y, z) weight [..] pdf p flags eta e`, for reports.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "wo ({:.4}, {:.4}, {:.4}) weight {:.5} pdf {:.5} {} eta {}",
            self.wo.x, self.wo.y, self.wo.z, self.weight, self.pdf, self.flags, self.eta
        )
    }
}

/// A bidirectional scattering distribution function in its local frame. See the module docs for
/// every convention.
pub trait Bsdf: Send + Sync {
    /// Union of the lobes' flags.
    fn flags(&self) -> BsdfFlags;

    /// f(wi, wo) without the cosine, non-delta lobes enabled in `ctx`.
    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum;

    /// Density of [`Bsdf::sample`] producing `wo`, per solid angle, non-delta lobes enabled in
    /// `ctx`, lobe selection included.
    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32;

    /// Draws a direction: `u1` chooses the lobe, `u2` the direction. `None` when no direction
    /// was produced (e.g. `wi` below a one-sided surface). A returned sample never has a zero
    /// pdf. A smooth-lobe sample is returned whenever its pdf is positive, **even with a zero
    /// weight** (Mitsuba's contract): a mixture evaluates its other children at that direction,
    /// so a black child that dropped its samples would bias the mixture. A delta outcome with
    /// zero throughput may be dropped. Callers end a path on a black weight.
    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample>;

    /// Transmittance of a sheet that light crosses without deviation (thin dielectric), for
    /// shadow rays; `None` for every other BSDF.
    fn null_transmission(&self, _wi: Vec3, _wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        None
    }

    /// True (the default) when [`Bsdf::pdf`] is the exact density of [`Bsdf::sample`] and
    /// [`Bsdf::eval`] the exact BSDF value. False for stochastic models (Heitz et al. 2016
    /// random walks): `eval` is then an unbiased estimate, `pdf` an approximation for **MIS
    /// weights only**, and `sample().weight` the exact throughput. A caller may then never form
    /// eval·cos/pdf as a sample weight, and the checks compare sample against eval by histograms
    /// of weights instead of densities.
    fn pdf_is_exact(&self) -> bool {
        true
    }

    /// `eval` and `pdf` together (models may share work).
    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        (self.eval(ctx, wi, wo, wl), self.pdf(ctx, wi, wo, wl))
    }

    /// [`Bsdf::eval`] as a Mueller matrix in the local frame, from Mitsuba's implicit Stokes basis
    /// of the incident beam to that of the outgoing one (see [`light_directions`]). The default
    /// depolarizes: diag(f, 0, 0, 0), frame-free. Its M00 is [`Bsdf::eval`]'s value exactly.
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        Mueller::depolarizer(self.eval(ctx, wi, wo, wl))
    }

    /// [`Bsdf::sample`] with a Mueller weight (bases as [`Bsdf::eval_mueller`]); the same
    /// direction, pdf, flags and η, and M00 equal to [`Bsdf::sample`]'s weight. The default
    /// depolarizes.
    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        self.sample(ctx, wi, u1, u2, wl).map(BsdfSample::depolarized)
    }

    /// [`Bsdf::null_transmission`] as a Mueller matrix for light crossing along `wi` (towards the
    /// shadow ray's origin, as Mitsuba's `eval_null_transmission`; bases: the implicit basis of
    /// `wi` on both sides). The default depolarizes.
    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        self.null_transmission(wi, wl).map(Mueller::depolarizer)
    }
}

/// The directions light travels at a scattering event, `(light_in, light_out)`: in radiance mode
/// light arrives along −`wo` and leaves along `wi` (towards the camera); in importance mode it
/// arrives along −`wi` and leaves along `wo` (Mitsuba's `wo_hat`/`wi_hat`). A Mueller matrix of a
/// BSDF maps Stokes vectors in the implicit basis of `light_in` to the implicit basis of
/// `light_out`.
#[inline]
pub fn light_directions(ctx: &BsdfContext, wi: Vec3, wo: Vec3) -> (Vec3, Vec3) {
    match ctx.mode {
        TransportMode::Radiance => (-wo, wi),
        TransportMode::Importance => (-wi, wo),
    }
}

impl BsdfSample {
    /// The same sample with a depolarizing Mueller weight diag(weight, 0, 0, 0).
    #[inline]
    pub fn depolarized(self) -> BsdfSample<Mueller> {
        self.with_weight(Mueller::depolarizer(self.weight))
    }
}

impl<W> BsdfSample<W> {
    /// The same direction, pdf, flags and η with another weight.
    #[inline]
    pub fn with_weight<V>(self, weight: V) -> BsdfSample<V> {
        BsdfSample {
            wo: self.wo,
            weight,
            pdf: self.pdf,
            flags: self.flags,
            eta: self.eta,
        }
    }
}

/// Which of a pair of delta lobes (mirror reflection; refracted or straight transmission) a sample
/// takes, as the lecture's "sampling reflection + transmission" slide does: with both lobes enabled
/// in `ctx`, the reflection with probability `p_reflect` (the lecture's best choice p_r = F_r) and
/// the transmission otherwise; with one lobe enabled, that one with probability 1 (Mitsuba's
/// single-lobe convention). Returns `(reflect, probability)`; the sample's weight is then the
/// chosen lobe's throughput divided by the probability. `None` when neither lobe is enabled or the
/// chosen lobe has probability 0.
#[inline]
pub fn choose_delta_lobe(ctx: &BsdfContext, u1: f32, p_reflect: f32) -> Option<(bool, f32)> {
    let has_r = ctx.is_enabled(BsdfFlags::DELTA_REFLECTION);
    let has_t = ctx.is_enabled(BsdfFlags::DELTA_TRANSMISSION);
    let choice = match (has_r, has_t) {
        (true, true) if u1 < p_reflect => (true, p_reflect),
        (true, true) => (false, 1.0 - p_reflect),
        (true, false) => (true, 1.0),
        (false, true) => (false, 1.0),
        (false, false) => return None,
    };
    (choice.1 > 0.0).then_some(choice)
}

/// cos θ of a local-frame direction.
#[inline]
pub fn cos_theta(w: Vec3) -> f32 {
    w.z
}

/// True when both directions are on the same side of the surface.
#[inline]
pub fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}

/// Mirror reflection about the normal in the local frame: (−x, −y, z).
#[inline]
pub fn reflect(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn context_masks_lobes_by_kind() {
        let diffuse_only = BsdfContext::radiance().with_lobes(BsdfFlags::DIFFUSE_REFLECTION);
        assert!(diffuse_only.is_enabled(BsdfFlags::DIFFUSE_REFLECTION));
        assert!(!diffuse_only.is_enabled(BsdfFlags::DELTA_REFLECTION));
        let all = BsdfContext::radiance();
        assert!(all.is_enabled(BsdfFlags::DELTA_TRANSMISSION | BsdfFlags::NON_SYMMETRIC));
    }

    #[test]
    fn flags_print_as_names() {
        assert_eq!(BsdfFlags::DELTA_REFLECTION.to_string(), "reflection|delta");
        assert_eq!(BsdfFlags::NONE.to_string(), "none");
    }
}
