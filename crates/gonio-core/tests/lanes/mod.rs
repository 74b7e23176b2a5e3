//! The lane kernels (`gonio_core::lanes`) against their scalar references, lane by lane: the
//! math functions against the standard library, the microfacet distributions and the BSDF
//! models against the scalar models at each lane's parameters: the microfacet functions at
//! widths 4, 8 and 16, the models at 4 lanes and through `dispatch` (which compiles 16, 8 and 4
//! lanes and runs the CPU's). Each width a model is tested at compiles its whole kernel again,
//! minutes of the CI build for all of them: the principled models' dispatch tests need the
//! feature `lane-dispatch-tests`. Each test calls its kernels through one non-inlined
//! comparison per model and width (`principled::compare_once`) or each kernel call behind its
//! own call (`models::apart`): inlined into every test, the two principled kernels made one
//! function LLVM took four minutes over, and the three microfacet models' tests 110 s of the
//! test build on 2 cores (now 16 s).

mod math;
mod microfacet;
mod models;
mod principled;

use glam::Vec3;
use gonio_core::lanes::{Isa, SampledSpectra};
use gonio_core::rng::Pcg32;

/// A direction of the upper hemisphere with cos θ in [cos_min, 1], drawn uniformly in cos θ and φ.
pub fn upper_dir(rng: &mut Pcg32, cos_min: f32) -> Vec3 {
    let z = cos_min + (1.0 - cos_min) * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * rng.next_f32();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// |a − b| ≤ tol · max(1, |a|, |b|).
pub fn close(a: f32, b: f32, tol: f32) -> bool {
    (a - b).abs() <= tol * 1f32.max(a.abs()).max(b.abs()) || (a.is_nan() && b.is_nan())
}

/// Every lane and wavelength of `a` and `b` bit for bit (a kernel's `eval` against the value of
/// its `eval_pdf`: the same arithmetic, so the same bits, NaN included).
pub fn same_bits<const N: usize, X: Isa>(a: SampledSpectra<N, X>, b: SampledSpectra<N, X>) -> bool {
    a.0.iter().zip(b.0.iter()).all(|(x, y)| {
        x.0.iter()
            .zip(y.0.iter())
            .all(|(p, q)| p.to_bits() == q.to_bits())
    })
}
