//! The polarized side of `proptest_health`: for every generated model, the Mueller matrices
//! (`eval_mueller`, `sample_mueller`, `null_transmission_mueller`) have the unpolarized values as
//! their M00, bit for bit, and map every physical Stokes vector to a physical one. Part of the
//! `proptest_health` test binary.

use super::*;

/// Fully polarized Stokes states (1, cos2χ cos2ψ, cos2χ sin2ψ, sin2χ) and the unpolarized one.
fn stokes_probes() -> [[f32; 4]; 5] {
    let s = |psi: f32, chi: f32| {
        let (c2x, s2x) = ((2.0 * chi).cos(), (2.0 * chi).sin());
        [1.0, c2x * (2.0 * psi).cos(), c2x * (2.0 * psi).sin(), s2x]
    };
    [
        [1.0, 0.0, 0.0, 0.0],
        s(0.0, 0.0),
        s(0.7, 0.0),
        s(0.3, 0.4),
        s(-1.1, -0.6),
    ]
}

/// A Mueller matrix maps each probe to a physical state: |(S1, S2, S3)| ≤ S0 (up to f32
/// round-off relative to the matrix).
fn maps_to_physical(m: &Mueller, what: &str) -> Result<(), TestCaseError> {
    let scale = m.get(0, 0).0.abs().max_element().max(1e-30);
    for p in stokes_probes() {
        for l in 0..4 {
            let out: Vec<f32> = (0..4)
                .map(|r| (0..4).map(|c| m.get(r, c)[l] * p[c]).sum::<f32>())
                .collect();
            let pol = (out[1] * out[1] + out[2] * out[2] + out[3] * out[3]).sqrt();
            if pol > out[0] + 1e-4 * scale {
                return Err(TestCaseError::fail(format!(
                    "{what}: unphysical output {out:?} for input {p:?} from {:?}",
                    m.matrix()
                )));
            }
        }
    }
    Ok(())
}

/// The polarized methods agree with the unpolarized ones bit for bit (M00 under unpolarized
/// input is the spectral value; same direction, pdf, flags and η), and every Mueller value maps
/// physical Stokes vectors to physical ones.
fn polarized_consistent(
    bsdf: &dyn Bsdf,
    wi: Vec3,
    wo: Vec3,
    wl: &SampledWavelengths,
    u1: f32,
    u2: Vec2,
) -> Result<(), TestCaseError> {
    for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
        let f = bsdf.eval(&ctx, wi, wo, wl);
        let m = bsdf.eval_mueller(&ctx, wi, wo, wl);
        prop_assert_eq!(m.intensity(), f, "eval M00");
        maps_to_physical(&m, "eval")?;
        let (mut wa, mut wb) = (*wl, *wl);
        let s = bsdf.sample(&ctx, wi, u1, u2, &mut wa);
        let sm = bsdf.sample_mueller(&ctx, wi, u1, u2, &mut wb);
        prop_assert_eq!(wa, wb);
        match (s, sm) {
            (None, None) => {}
            (Some(s), Some(sm)) => {
                prop_assert_eq!((s.wo, s.pdf, s.flags, s.eta), (sm.wo, sm.pdf, sm.flags, sm.eta));
                prop_assert_eq!(sm.weight.intensity(), s.weight, "sample weight M00");
                maps_to_physical(&sm.weight, "sample")?;
            }
            (a, b) => prop_assert!(false, "sample {:?} vs sample_mueller {:?}", a, b),
        }
    }
    let t = bsdf.null_transmission(wi, wl);
    let tm = bsdf.null_transmission_mueller(wi, wl);
    prop_assert_eq!(t, tm.map(|m| m.intensity()));
    if let Some(tm) = tm {
        maps_to_physical(&tm, "null transmission")?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases() / 8, ..fixed_config() })]

    #[test]
    fn polarized_values_are_the_unpolarized_ones_and_physical(
        spec in spec(),
        wi in direction(),
        wo in direction(),
        wl in wavelengths(),
        u1 in sample_u(),
        u2x in sample_u(),
        u2y in sample_u(),
    ) {
        with_bsdf(&spec, &mut |bsdf| polarized_consistent(bsdf, wi, wo, &wl, u1, Vec2::new(u2x, u2y)))?;
    }
}
