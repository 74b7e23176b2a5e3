//! Cost of one `sample` + one `eval` per model (ns per call pair), issue 2 §8.
//!
//! Each iteration draws its uniforms from a PCG32, samples a direction and evaluates the BSDF
//! at it, the pair of calls a path tracer makes per vertex. Run with
//! `cargo bench -p gonio-core --bench bsdf`.

use divan::{Bencher, black_box};
use glam::Vec3;
use gonio_core::bsdfs::Diffuse;
use gonio_core::rng::Pcg32;
use gonio_core::{Bsdf, BsdfContext, SampledWavelengths};

fn main() {
    divan::main();
}

/// sample + eval with random uniforms, a fixed oblique wi and path-like wavelengths.
fn sample_eval(bencher: Bencher, bsdf: &dyn Bsdf) {
    let ctx = BsdfContext::radiance();
    let wi = Vec3::new(0.48, 0.36, 0.8);
    let mut rng = Pcg32::new(1, 2);
    bencher.bench_local(move || {
        let mut wl = SampledWavelengths::sample_visible(rng.next_f32());
        let u1 = rng.next_f32();
        let u2 = rng.next_vec2();
        let s = black_box(bsdf).sample(&ctx, black_box(wi), u1, u2, &mut wl);
        let wo = s.map_or(Vec3::Z, |s| s.wo);
        black_box(bsdf.eval(&ctx, wi, wo, &wl))
    });
}

#[divan::bench]
fn diffuse(bencher: Bencher) {
    sample_eval(bencher, &Diffuse::default());
}
