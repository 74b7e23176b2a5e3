//! Isotropy (lecture slide "BRDF properties"): an isotropic BSDF depends on the
//! azimuths of wi and wo only through their difference, so rotating both about the normal by a
//! common angle ψ leaves f, the pdf and every delta lobe's throughput unchanged (and rotates a
//! delta lobe's direction with them).
//!
//! Row `isotropy`: the max relative change over random pairs and angles. Rotation in `f32`
//! perturbs the directions by ~1e-7, so the tolerance is 10 × `rel_tol`. Where f itself is that
//! sensitive (near a zero that f approaches smoothly, e.g. the facet-grazing edge of a rough
//! dielectric's refraction lobe, where f_t ∝ (ω·m)²), such a perturbation alone changes f by
//! more than the tolerance; so each pair's change under rotation is counted beyond 10 × the
//! change under a fixed, rotation-free perturbation of the same size (1e-7), which is ~1e-7 for
//! a well-conditioned f and leaves a real anisotropy (a change of order 1) visible. Every model of the
//! lecture is isotropic. A BSDF flagged [`BsdfFlags::ANISOTROPIC`] (a rough metal with
//! α_u ≠ α_v) must instead show a change above that tolerance: the flag is then checked too.

use super::{Bound, CheckConfig, CheckResult, random_wavelengths, rel_diff, uniform_sphere};
use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags};
use glam::{Quat, Vec3};

const TINY: f64 = 1e-12;

/// The rotation-free nudge that measures f's sensitivity at a pair (the size of an `f32`
/// rotation's rounding, in a direction with no symmetry).
const PERTURBATION: Vec3 = Vec3::new(0.6e-7, -0.8e-7, 0.5e-7);

/// The `isotropy` row.
pub fn isotropy(bsdf: &dyn Bsdf, config: &CheckConfig) -> CheckResult {
    let mut rng = config.rng(0x150_7a0);
    let ctx = BsdfContext::radiance();
    let (mut worst, mut at) = (0.0f64, String::new());
    let mut record = |e: f64, what: &dyn Fn() -> String| {
        let e = if e.is_nan() { f64::INFINITY } else { e };
        if e > worst {
            worst = e;
            at = what();
        }
    };
    for _ in 0..config.pairs {
        let (a, b) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
        let psi = std::f32::consts::TAU * rng.next_f32();
        let rot = Quat::from_rotation_z(psi);
        let (ra, rb) = (rot * a, rot * b);
        let wl = random_wavelengths(&mut rng);
        let (f, p) = (bsdf.eval(&ctx, a, b, &wl), bsdf.pdf(&ctx, a, b, &wl));
        let (fr, pr) = (bsdf.eval(&ctx, ra, rb, &wl), bsdf.pdf(&ctx, ra, rb, &wl));
        // The same pair nudged by ~1e-7 without rotating: f's own sensitivity at this pair.
        let (na, nb) = ((a + PERTURBATION).normalize(), (b - PERTURBATION).normalize());
        let (fn_, pn) = (bsdf.eval(&ctx, na, nb, &wl), bsdf.pdf(&ctx, na, nb, &wl));
        let beyond = |x: f32, rotated: f32, nudged: f32| {
            let e = rel_diff(x as f64, rotated as f64, TINY);
            if e.is_nan() {
                return e;
            }
            (e - 10.0 * rel_diff(x as f64, nudged as f64, TINY)).max(0.0)
        };
        for i in 0..4 {
            record(beyond(f[i], fr[i], fn_[i]), &|| {
                format!("f at a={a:.4} b={b:.4}: {f}, rotated by {psi:.3}: {fr}, nudged: {fn_}")
            });
        }
        record(beyond(p, pr, pn), &|| {
            format!("pdf at a={a:.4} b={b:.4}: {p}, rotated by {psi:.3}: {pr}, nudged: {pn}")
        });
        // Delta lobes: same numbers, rotated direction.
        let (u1, u2) = (rng.next_f32(), rng.next_vec2());
        let (mut w1, mut w2) = (wl, wl);
        let s = bsdf.sample(&ctx, a, u1, u2, &mut w1);
        let sr = bsdf.sample(&ctx, ra, u1, u2, &mut w2);
        if let (Some(s), Some(sr)) = (s, sr)
            && s.flags.is_delta()
            && sr.flags == s.flags
        {
            let mut e = rel_diff(s.pdf as f64, sr.pdf as f64, TINY);
            for i in 0..4 {
                e = e.max(rel_diff(s.weight[i] as f64, sr.weight[i] as f64, TINY));
            }
            e = e.max(((rot * s.wo) - sr.wo).length() as f64);
            record(e, &|| {
                format!("delta sample at a={a:.4}: {s}; rotated by {psi:.3}: {sr}")
            });
        }
    }
    let (bound, claim) = if bsdf.flags().contains(BsdfFlags::ANISOTROPIC) {
        (Bound::AtLeast, "flagged anisotropic: the change must be visible")
    } else {
        (Bound::AtMost, "isotropic")
    };
    CheckResult::compare(
        "isotropy",
        worst,
        bound,
        10.0 * config.rel_tol,
        format!(
            "{claim}; max relative change of f, pdf, delta samples under rotation about z over {} pairs; worst {at}",
            config.pairs
        ),
    )
}
