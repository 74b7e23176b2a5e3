//! `twosided`: makes a one-sided BSDF respond on both faces.
//!
//! Most reflection models (diffuse, conductor, plastic) are one-sided: they are zero when ωi is
//! below the surface. `twosided` evaluates the `front` BSDF for cos θi ≥ 0 and the `back` BSDF
//! for cos θi < 0 with both directions mirrored through the surface (z → −z), flipping the
//! sampled direction back:
//!
//! ```text
//!     f(ωi, ωo) = f_front(ωi, ωo)                      if cos θi ≥ 0
//!     f(ωi, ωo) = f_back(flip(ωi), flip(ωo)),  flip(x, y, z) = (x, y, −z),   if cos θi < 0
//! ```
//!
//! With one nested BSDF (`TwoSided::new`) this equals Mitsuba's single-child rule
//! (ωi.z ← |ωi.z|, ωo.z ← ωo.z·sign(ωi.z)). Null transmission is forwarded (Mitsuba PR #1719).
//!
//! Mitsuba 3 plugin `twosided` (`src/bsdfs/twosided.cpp`):
//!
//! | parameter            | type            | default                                     |
//! |----------------------|-----------------|---------------------------------------------|
//! | (nested BSDFs)       | 1 or 2 `bsdf`   | required: front (and back; else front twice) |
//! | `allow_transmission` | boolean, hidden | false                                       |
//!
//! Mitsuba refuses children with transmission unless `allow_transmission`; this adapter accepts
//! any child (as with `allow_transmission = true`): a transmission of the front BSDF leaves
//! through the back face, and vice versa. The scene loader enforces Mitsuba's rule.

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::mueller::Mueller;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Front BSDF on the side the normal points to, back BSDF (mirrored) on the other.
#[derive(Clone, Copy)]
pub struct TwoSided<'a> {
    /// Used when cos θi ≥ 0.
    pub front: &'a dyn Bsdf,
    /// Used, in mirrored coordinates, when cos θi < 0.
    pub back: &'a dyn Bsdf,
}

impl std::fmt::Debug for TwoSided<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TwoSided")
            .field("front_flags", &self.front.flags())
            .field("back_flags", &self.back.flags())
            .finish()
    }
}

/// Mirror through the surface plane: (x, y, z) → (x, y, −z), the frame in which a `twosided`
/// evaluates its back.
#[inline]
pub fn flip(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl<'a> TwoSided<'a> {
    /// The same BSDF on both faces.
    pub fn new(bsdf: &'a dyn Bsdf) -> Self {
        Self {
            front: bsdf,
            back: bsdf,
        }
    }

    /// Different BSDFs on the two faces.
    pub fn with_back(front: &'a dyn Bsdf, back: &'a dyn Bsdf) -> Self {
        Self { front, back }
    }
}

impl Bsdf for TwoSided<'_> {
    fn flags(&self) -> BsdfFlags {
        self.front.flags() | self.back.flags()
    }

    fn pdf_is_exact(&self) -> bool {
        self.front.pdf_is_exact() && self.back.pdf_is_exact()
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if wi.z >= 0.0 {
            self.front.eval(ctx, wi, wo, wl)
        } else {
            self.back.eval(ctx, flip(wi), flip(wo), wl)
        }
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> f32 {
        if wi.z >= 0.0 {
            self.front.pdf(ctx, wi, wo, wl)
        } else {
            self.back.pdf(ctx, flip(wi), flip(wo), wl)
        }
    }

    fn eval_pdf(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        wo: Vec3,
        wl: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if wi.z >= 0.0 {
            self.front.eval_pdf(ctx, wi, wo, wl)
        } else {
            self.back.eval_pdf(ctx, flip(wi), flip(wo), wl)
        }
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if wi.z >= 0.0 {
            self.front.sample(ctx, wi, u1, u2, wl)
        } else {
            let mut s = self.back.sample(ctx, flip(wi), u1, u2, wl)?;
            s.wo = flip(s.wo);
            Some(s)
        }
    }

    fn null_transmission(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<SampledSpectrum> {
        if wi.z >= 0.0 {
            self.front.null_transmission(wi, wl)
        } else {
            self.back.null_transmission(flip(wi), wl)
        }
    }

    /// The back side's matrix is mirrored (z ↦ −z flips the handedness of the Stokes bases:
    /// s2 and s3 change sign, [`Mueller::mirrored`]) and re-expressed in the implicit bases of the
    /// actual directions.
    fn eval_mueller(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> Mueller {
        if wi.z >= 0.0 {
            self.front.eval_mueller(ctx, wi, wo, wl)
        } else {
            unmirror(self.back.eval_mueller(ctx, flip(wi), flip(wo), wl))
        }
    }

    fn sample_mueller(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample<Mueller>> {
        if wi.z >= 0.0 {
            self.front.sample_mueller(ctx, wi, u1, u2, wl)
        } else {
            let mut s = self.back.sample_mueller(ctx, flip(wi), u1, u2, wl)?;
            s.wo = flip(s.wo);
            s.weight = unmirror(s.weight);
            Some(s)
        }
    }

    fn null_transmission_mueller(&self, wi: Vec3, wl: &SampledWavelengths) -> Option<Mueller> {
        if wi.z >= 0.0 {
            self.front.null_transmission_mueller(wi, wl)
        } else {
            self.back.null_transmission_mueller(flip(wi), wl).map(unmirror)
        }
    }
}

/// A back-side Mueller matrix brought back through the mirror z ↦ −z, in implicit bases.
fn unmirror(m: Mueller) -> Mueller {
    m.mirrored(flip).in_implicit_bases()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::{Conductor, Diffuse, Plastic, ThinDielectric};
    use crate::spectra::Spectrum;
    use std::f32::consts::FRAC_1_PI;

    fn grid_dirs() -> Vec<Vec3> {
        // 5 × 5 grid of the uniform sphere (Mitsuba 3 src/bsdfs/tests/test_twosided.py, test03),
        // offset so that no direction lies in the surface plane.
        let mut v = Vec::new();
        for a in 0..5 {
            for b in 0..5 {
                let z = 1.0 - 2.0 * (a as f32 + 0.3) / 5.0;
                let phi = 2.0 * std::f32::consts::PI * (b as f32 + 0.5) / 5.0;
                let r = (1.0 - z * z).sqrt();
                v.push(Vec3::new(r * phi.cos(), r * phi.sin(), z));
            }
        }
        v
    }

    #[test]
    fn two_diffuse_faces_mitsuba_test03_pattern() {
        // Front ρ = 0.2, back ρ = 0.7: eval = ρ_side/π when both directions are on wi's side,
        // weight·(cos θo/π)... = eval·|cos θo|/pdf, bs.pdf = pdf(ωo), no NaN.
        let front = Diffuse::new(Spectrum::Constant(0.2));
        let back = Diffuse::new(Spectrum::Constant(0.7));
        let ts = TwoSided::with_back(&front, &back);
        let ctx = BsdfContext::radiance();
        assert_eq!(ts.flags(), BsdfFlags::DIFFUSE_REFLECTION);
        for wi in grid_dirs() {
            let rho = if wi.z >= 0.0 { 0.2 } else { 0.7 };
            for a in 0..5 {
                for b in 0..5 {
                    let u2 = Vec2::new((a as f32 + 0.5) / 5.0, (b as f32 + 0.5) / 5.0);
                    let mut wl = SampledWavelengths::fixed(550.0);
                    let s = ts.sample(&ctx, wi, 0.5, u2, &mut wl).unwrap();
                    assert!(s.wo.z * wi.z > 0.0, "reflection stays on wi's side");
                    assert!((s.weight[0] - rho).abs() < 1e-6);
                    let (f, pdf) = ts.eval_pdf(&ctx, wi, s.wo, &wl);
                    assert!((f[0] - rho * FRAC_1_PI).abs() < 1e-6);
                    assert!(
                        (pdf - s.pdf).abs() < 1e-6 * pdf && (pdf - s.wo.z.abs() * FRAC_1_PI).abs() < 1e-6
                    );
                    assert!((s.weight[0] - f[0] * s.wo.z.abs() / pdf).abs() < 1e-5);
                    assert_eq!(
                        ts.eval(&ctx, wi, flip(s.wo), &wl),
                        SampledSpectrum::ZERO,
                        "no transmission"
                    );
                }
            }
        }
    }

    #[test]
    fn single_child_is_mirrored_not_reinterpreted() {
        // Mitsuba's single-child rule: eval(wi, wo) with wi below = eval(|wi|, wo·sign(wi.z)).
        let p = Plastic::default();
        let ts = TwoSided::new(&p);
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(500.0);
        let wi = Vec3::new(0.3, -0.5, -0.81).normalize();
        let wo = Vec3::new(-0.6, 0.2, -0.77).normalize();
        let expect = p.eval(&ctx, flip(wi), flip(wo), &wl);
        assert!(expect[0] > 0.0);
        assert_eq!(ts.eval(&ctx, wi, wo, &wl), expect);
        assert_eq!(ts.pdf(&ctx, wi, wo, &wl), p.pdf(&ctx, flip(wi), flip(wo), &wl));
        // Mirror from the back: exact reflection about the surface, weight 1.
        let m = Conductor::mirror();
        let tm = TwoSided::new(&m);
        let mut wl = wl;
        let s = tm.sample(&ctx, wi, 0.5, Vec2::ZERO, &mut wl).unwrap();
        assert_eq!(s.wo, Vec3::new(-wi.x, -wi.y, wi.z));
        assert_eq!(s.weight[0], 1.0);
    }

    #[test]
    fn back_face_albedo_of_twosided_diffuse_is_rho() {
        // As Mitsuba 3 src/bsdfs/twosided.cpp: twosided(diffuse 0.5) from the back ⇒ albedo 0.5
        // (every sample weighs ρ; the plain one-sided diffuse returns nothing there).
        let d = Diffuse::default();
        let ts = TwoSided::new(&d);
        let ctx = BsdfContext::radiance();
        let wi = Vec3::new(0.2, 0.1, -0.97).normalize();
        let mut wl = SampledWavelengths::fixed(550.0);
        assert!(d.sample(&ctx, wi, 0.5, Vec2::new(0.3, 0.7), &mut wl).is_none());
        let mut sum = 0.0;
        for j in 0..100 {
            let u2 = Vec2::new((j % 10) as f32 / 10.0 + 0.05, (j / 10) as f32 / 10.0 + 0.05);
            sum += ts.sample(&ctx, wi, 0.5, u2, &mut wl).map_or(0.0, |s| s.weight[0]);
        }
        assert!((sum / 100.0 - 0.5).abs() < 1e-6);
    }

    #[test]
    fn null_transmission_is_forwarded() {
        let t = ThinDielectric::default();
        let ts = TwoSided::new(&t);
        let wl = SampledWavelengths::fixed(550.0);
        for wi in [Vec3::Z, -Vec3::Z] {
            let v = ts.null_transmission(wi, &wl).unwrap()[0];
            assert!((v - 0.922086).abs() < 2e-6);
        }
        let d = Diffuse::default();
        assert!(TwoSided::new(&d).null_transmission(Vec3::Z, &wl).is_none());
    }
}
