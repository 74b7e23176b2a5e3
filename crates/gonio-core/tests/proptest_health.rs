//! Property tests (issue 2 §6): no NaN, no infinity, no negative value from any model, for any
//! direction (grazing and exactly grazing included, both hemispheres), any wavelength in
//! 360–830 nm, and any valid parameter: reflectances in [0, 1], indices of refraction in
//! [1.0001, 4] and their inverses, conductor η ∈ [0, 5] and k ∈ [0, 10] including the
//! n = k = 0 corner (0/0 in the textbook formula), exterior indices, tints, both plastic modes,
//! rough conductors (Beckmann and GGX, α_u, α_v from 1e-4 to 1, both samplers), rough plastics
//! (both distributions, α from 1e-4 to 1 on a grid of prebuilt coats, both samplers, both averages),
//! rough dielectrics (the same roughness, any index pair, dispersive or not, tints), `principled`
//! and `principledthin` (roughness from 1e-4 to 1, every weight in its range, η and the
//! sampling rates),
//! Lambert-sphere half-spaces (both models, k_d or c in [0, 1]),
//! measured tables (zeros included), the polarization filters (`polarizer`, `retarder`,
//! `circular`, any angle), and `twosided` / `blendbsdf` nested over all of these.
//!
//! Each case checks one (wi, wo) query of `eval`/`pdf`/`eval_pdf` and one `sample` call in both
//! transport modes with the per-query functions of `gonio_core::check::health`, the same code
//! as the `health` and `lobe_flags` rows of `gonio check`. The number of cases is
//! `PROPTEST_CASES` (default 4096 here; each case takes microseconds).
//!
//! Polarization (issue 12 §1): over the same models, the Mueller-matrix methods give exactly the
//! unpolarized values in M00 (an unpolarized caller sees no change) and map physical Stokes
//! vectors to physical ones (`PROPTEST_CASES`/8 cases).

use glam::{Vec2, Vec3};
use gonio_core::bsdfs::lambertsphere::{AlbedoParameter, LambertSphereModel};
use gonio_core::bsdfs::roughdiffuse::{RoughDiffuse, RoughDiffuseModel};
use gonio_core::bsdfs::roughplastic::{CoatAverages, RoughCoat, RoughPlastic};
use gonio_core::bsdfs::tabulated::TabulatedData;
use gonio_core::bsdfs::{
    BlendBsdf, Conductor, Dielectric, Diffuse, LambertSphere, Plastic, Principled, PrincipledThin,
    RoughConductor, RoughDielectric, Tabulated, ThinDielectric, TwoSided,
};
use gonio_core::bsdfs::{CircularPolarizer, Polarizer, Retarder};
use gonio_core::check::broken::NanAtGrazing;
use gonio_core::check::health::{check_eval, check_sample};
use gonio_core::microfacet::{MicrofacetDistribution, MicrofacetKind};
use gonio_core::mueller::Mueller;
use gonio_core::rng::ONE_MINUS_EPSILON;
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};
use gonio_core::weight::Weight;
use gonio_core::{Bsdf, BsdfContext, Ior, SampledWavelengths};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRng, TestRunner};
use std::sync::{Arc, OnceLock};

/// A model and its parameters, as plain data (so proptest can shrink it).
#[derive(Clone, Debug)]
enum Spec {
    Diffuse {
        rho: SpecSpectrum,
    },
    Hair {
        eumelanin: f32,
        pheomelanin: f32,
        eta: f32,
        beta_m: f32,
        beta_n: f32,
        tilt: f32,
    },
    Conductor {
        n: f32,
        k: f32,
        ext: f32,
        tint: f32,
    },
    RoughConductor {
        n: f32,
        k: f32,
        ext: f32,
        tint: f32,
        ggx: bool,
        alpha_u: f32,
        alpha_v: f32,
        visible: bool,
    },
    /// `roughdiffuse`: model 0 Oren–Nayar, 1 its fast form, 2/3 Beckmann/GGX microfacets.
    RoughDiffuse {
        rho: SpecSpectrum,
        alpha: f32,
        model: u8,
    },
    RoughDielectric {
        int: f32,
        ext: f32,
        refl: f32,
        trans: f32,
        dispersive: bool,
        ggx: bool,
        alpha_u: f32,
        alpha_v: f32,
        visible: bool,
    },
    /// `roughconductor` (n, k) or `roughdielectric` (n = int, k = ext) with multiple_scattering.
    RoughMs {
        dielectric: bool,
        n: f32,
        k: f32,
        ggx: bool,
        alpha_u: f32,
        alpha_v: f32,
    },
    LambertSphere {
        albedo: SpecSpectrum,
        sphere: bool,
        practical: bool,
    },
    Dielectric {
        int: f32,
        ext: f32,
        refl: f32,
        trans: f32,
        dispersive: bool,
    },
    Thin {
        int: f32,
        ext: f32,
        refl: f32,
        trans: f32,
    },
    Plastic {
        rho: SpecSpectrum,
        int: f32,
        ext: f32,
        nonlinear: bool,
        tint: f32,
        s: Option<f32>,
    },
    RoughPlastic {
        rho: SpecSpectrum,
        tint: f32,
        nonlinear: bool,
        coat: usize,
        s: Option<f32>,
    },
    /// `pplastic`: ρ, tint, GGX or Beckmann, (α_u, α_v), visible normals, the index pair, s.
    PPlastic {
        rho: SpecSpectrum,
        tint: f32,
        ggx: bool,
        alpha_u: f32,
        alpha_v: f32,
        visible: bool,
        iors: (f32, f32),
        s: Option<f32>,
    },
    /// `principled`: base colour, roughness, the nine weights (anisotropic, metallic,
    /// spec_trans, spec_tint, sheen, sheen_tint, flatness, clearcoat, clearcoat_gloss), η and
    /// the three sampling rates.
    Principled {
        rho: SpecSpectrum,
        roughness: f32,
        weights: [f32; 9],
        eta: f32,
        rates: [f32; 3],
    },
    /// `principledthin`: base colour, roughness, the seven weights (anisotropic, spec_trans,
    /// spec_tint, sheen, sheen_tint, flatness, diff_trans/2), η and the four sampling rates.
    PrincipledThin {
        rho: SpecSpectrum,
        roughness: f32,
        weights: [f32; 7],
        eta: f32,
        rates: [f32; 4],
    },
    /// A measured table on a 4 × 4 × 3 (θi, θo, φd) grid at two wavelengths, values in [0, 1].
    Tabulated {
        values: Vec<f32>,
    },
    /// `polarizer` (kind 0), `retarder` (1), `circular` (2): angle θ, phase δ (degrees), t.
    Filter {
        kind: u8,
        theta: f32,
        delta: f32,
        t: SpecSpectrum,
        flag: bool,
    },
    TwoSided {
        front: Box<Spec>,
        back: Option<Box<Spec>>,
    },
    Blend {
        w: f32,
        a: Box<Spec>,
        b: Box<Spec>,
    },
}

/// A reflectance: constant or a piecewise-linear curve with values in [0, 1].
#[derive(Clone, Debug)]
enum SpecSpectrum {
    Constant(f32),
    Curve([f32; 3]),
}

impl SpecSpectrum {
    fn build(&self) -> Spectrum {
        match *self {
            SpecSpectrum::Constant(v) => Spectrum::Constant(v),
            SpecSpectrum::Curve([a, b, c]) => Spectrum::PiecewiseLinear(Arc::new(
                PiecewiseLinear::from_interleaved(&[400.0, a, 550.0, b, 700.0, c], Extrapolation::Clamp)
                    .unwrap(),
            )),
        }
    }
}

fn unit() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.0f32), Just(1.0f32), 0.0f32..=1.0]
}

/// Microfacet roughness from 1e-4 to 1, log-uniform, with both ends exactly.
fn roughness() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(1e-4f32),
        Just(1.0f32),
        (-4.0f32..=0.0).prop_map(|e| 10f32.powf(e))
    ]
}

fn reflectance() -> impl Strategy<Value = SpecSpectrum> {
    prop_oneof![
        unit().prop_map(SpecSpectrum::Constant),
        [unit(), unit(), unit()].prop_map(SpecSpectrum::Curve)
    ]
}

/// (int, ext) with η = int/ext in [1.0001, 4] or its inverse, ext in [1, 2].
fn ior_pair() -> impl Strategy<Value = (f32, f32)> {
    (
        prop_oneof![Just(1.0001f32), Just(4.0f32), 1.0001f32..=4.0],
        1.0f32..=2.0,
        any::<bool>(),
    )
        .prop_map(|(eta, ext, inverse)| {
            if inverse {
                (ext, ext * eta)
            } else {
                (ext * eta, ext)
            }
        })
}

fn leaf() -> impl Strategy<Value = Spec> {
    prop_oneof![
        prop_oneof![
            (
                (
                    prop_oneof![Just(0.0f32), 0.0f32..=8.0],
                    prop_oneof![Just(0.0f32), 0.0f32..=8.0]
                ),
                (1.0001f32..=2.5, unit(), unit(), -10.0f32..=10.0)
            )
                .prop_map(
                    |((eumelanin, pheomelanin), (eta, beta_m, beta_n, tilt))| Spec::Hair {
                        eumelanin,
                        pheomelanin,
                        eta,
                        beta_m,
                        beta_n,
                        tilt
                    }
                ),
            proptest::collection::vec(unit(), 96).prop_map(|values| Spec::Tabulated { values }),
            (
                0u8..3,
                -360.0f32..=360.0,
                -360.0f32..=360.0,
                reflectance(),
                any::<bool>()
            )
                .prop_map(|(kind, theta, delta, t, flag)| Spec::Filter {
                    kind,
                    theta,
                    delta,
                    t,
                    flag
                }),
        ],
        reflectance().prop_map(|rho| Spec::Diffuse { rho }),
        (
            prop_oneof![Just(0.0f32), 0.0f32..=5.0],
            prop_oneof![Just(0.0f32), 0.0f32..=10.0],
            prop_oneof![Just(1.0f32), 1.0f32..=2.0],
            unit()
        )
            .prop_map(|(n, k, ext, tint)| Spec::Conductor { n, k, ext, tint }),
        (
            (
                prop_oneof![Just(0.0f32), 0.0f32..=5.0],
                prop_oneof![Just(0.0f32), 0.0f32..=10.0],
                prop_oneof![Just(1.0f32), 1.0f32..=2.0],
                unit()
            ),
            (any::<bool>(), roughness(), roughness(), any::<bool>())
        )
            .prop_map(|((n, k, ext, tint), (ggx, alpha_u, alpha_v, visible))| {
                Spec::RoughConductor {
                    n,
                    k,
                    ext,
                    tint,
                    ggx,
                    alpha_u,
                    alpha_v,
                    visible,
                }
            }),
        (
            reflectance(),
            prop_oneof![Just(0.0f32), roughness(), 0.0f32..=4.0],
            0u8..4
        )
            .prop_map(|(rho, alpha, model)| Spec::RoughDiffuse { rho, alpha, model }),
        (
            (ior_pair(), unit(), unit(), any::<bool>()),
            (any::<bool>(), roughness(), roughness(), any::<bool>())
        )
            .prop_map(
                |(((int, ext), refl, trans, dispersive), (ggx, alpha_u, alpha_v, visible))| {
                    Spec::RoughDielectric {
                        int,
                        ext,
                        refl,
                        trans,
                        dispersive,
                        ggx,
                        alpha_u,
                        alpha_v,
                        visible,
                    }
                }
            ),
        (
            (any::<bool>(), ior_pair(), 0.0f32..=5.0),
            (any::<bool>(), roughness(), roughness())
        )
            .prop_map(|((dielectric, (int, ext), k), (ggx, alpha_u, alpha_v))| {
                let (n, k) = if dielectric { (int, ext) } else { (int - 1.0, k) };
                Spec::RoughMs {
                    dielectric,
                    n,
                    k,
                    ggx,
                    alpha_u,
                    alpha_v,
                }
            }),
        (reflectance(), any::<bool>(), any::<bool>()).prop_map(|(albedo, sphere, practical)| {
            Spec::LambertSphere {
                albedo,
                sphere,
                practical,
            }
        }),
        (ior_pair(), unit(), unit(), any::<bool>()).prop_map(|((int, ext), refl, trans, dispersive)| {
            Spec::Dielectric {
                int,
                ext,
                refl,
                trans,
                dispersive,
            }
        }),
        (ior_pair(), unit(), unit()).prop_map(|((int, ext), refl, trans)| Spec::Thin {
            int,
            ext,
            refl,
            trans
        }),
        (
            reflectance(),
            ior_pair(),
            any::<bool>(),
            unit(),
            proptest::option::of(unit())
        )
            .prop_map(|(rho, (int, ext), nonlinear, tint, s)| Spec::Plastic {
                rho,
                int,
                ext,
                nonlinear,
                tint,
                s
            }),
        (
            reflectance(),
            unit(),
            any::<bool>(),
            0..ROUGH_COATS,
            proptest::option::of(unit())
        )
            .prop_map(|(rho, tint, nonlinear, coat, s)| Spec::RoughPlastic {
                rho,
                tint,
                nonlinear,
                coat,
                s
            }),
        (
            (reflectance(), unit(), any::<bool>()),
            (roughness(), roughness(), any::<bool>()),
            ior_pair(),
            proptest::option::of(unit())
        )
            .prop_map(
                |((rho, tint, ggx), (alpha_u, alpha_v, visible), iors, s)| Spec::PPlastic {
                    rho,
                    tint,
                    ggx,
                    alpha_u,
                    alpha_v,
                    visible,
                    iors,
                    s
                }
            ),
        (
            reflectance(),
            roughness(),
            proptest::array::uniform9(unit()),
            ior_pair(),
            proptest::array::uniform3(prop_oneof![Just(0.0f32), 0.0f32..=4.0]),
        )
            .prop_map(|(rho, roughness, weights, (int, ext), rates)| Spec::Principled {
                rho,
                roughness,
                weights,
                eta: int / ext,
                rates
            }),
        (
            reflectance(),
            roughness(),
            proptest::array::uniform7(unit()),
            ior_pair(),
            proptest::array::uniform4(prop_oneof![Just(0.0f32), 0.0f32..=4.0]),
        )
            .prop_map(
                |(rho, roughness, weights, (int, ext), rates)| Spec::PrincipledThin {
                    rho,
                    roughness,
                    weights,
                    eta: int / ext,
                    rates
                }
            ),
    ]
}

fn spec() -> impl Strategy<Value = Spec> {
    leaf().prop_recursive(2, 6, 2, |inner| {
        prop_oneof![
            (inner.clone(), proptest::option::of(inner.clone())).prop_map(|(f, b)| Spec::TwoSided {
                front: Box::new(f),
                back: b.map(Box::new)
            }),
            (unit(), inner.clone(), inner).prop_map(|(w, a, b)| Spec::Blend {
                w,
                a: Box::new(a),
                b: Box::new(b)
            }),
        ]
    })
}

/// Any unit direction; a third of them grazing (|z| ≤ 1e-6, or exactly 0), some at the poles.
fn direction() -> impl Strategy<Value = Vec3> {
    let phi = 0.0f32..std::f32::consts::TAU;
    prop_oneof![
        (-1.0f32..=1.0, phi.clone()).prop_map(|(z, p)| from_z_phi(z, p)),
        (prop_oneof![Just(0.0f32), Just(-0.0f32), -1e-6f32..=1e-6], phi).prop_map(|(z, p)| from_z_phi(z, p)),
        prop_oneof![Just(Vec3::Z), Just(-Vec3::Z)],
    ]
}

fn from_z_phi(z: f32, phi: f32) -> Vec3 {
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

fn wavelengths() -> impl Strategy<Value = SampledWavelengths> {
    prop_oneof![
        prop_oneof![Just(360.0f32), Just(830.0f32), 360.0f32..=830.0].prop_map(SampledWavelengths::fixed),
        (0.0f32..1.0).prop_map(SampledWavelengths::sample_visible),
    ]
}

fn sample_u() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.0f32), Just(ONE_MINUS_EPSILON), 0.0f32..1.0]
}

/// A fixed seed (the same cases on every run: a failure is reproducible and the suite does not
/// flicker) and no regression files written into the source tree.
fn fixed_config() -> ProptestConfig {
    ProptestConfig {
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x6f6e_696f_6700_0001),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(4096)
}

/// The per-query property on one model (both modes, eval at (wi, wo) and (wi, −wi), one sample).
fn healthy(
    bsdf: &dyn Bsdf,
    wi: Vec3,
    wo: Vec3,
    wl: &SampledWavelengths,
    u1: f32,
    u2: Vec2,
) -> Result<(), TestCaseError> {
    for ctx in [BsdfContext::radiance(), BsdfContext::importance()] {
        check_eval(bsdf, &ctx, wi, wo, wl).map_err(TestCaseError::fail)?;
        check_eval(bsdf, &ctx, wi, -wi, wl).map_err(TestCaseError::fail)?;
        let p = check_sample(bsdf, &ctx, wi, u1, u2, wl);
        if let Some(e) = p.health.or(p.flags) {
            return Err(TestCaseError::fail(e));
        }
    }
    Ok(())
}

/// The property can fail: on a Lambertian that divides cos θo by itself, the same strategies
/// find the NaN at an exactly grazing direction.
#[test]
fn property_catches_nan_at_grazing() {
    let config = Config {
        cases: 4096,
        failure_persistence: None,
        ..Config::default()
    };
    let rng = TestRng::deterministic_rng(config.rng_algorithm);
    let mut runner = TestRunner::new_with_rng(config, rng);
    let found = runner.run(&(direction(), direction(), wavelengths()), |(wi, wo, wl)| {
        healthy(&NanAtGrazing, wi, wo, &wl, 0.5, Vec2::splat(0.5))
    });
    assert!(found.is_err(), "NaN at grazing not found");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..fixed_config() })]

    #[test]
    fn no_nan_inf_or_negative(
        spec in spec(),
        wi in direction(),
        wo in direction(),
        wl in wavelengths(),
        u1 in sample_u(),
        u2x in sample_u(),
        u2y in sample_u(),
    ) {
        with_bsdf(&spec, &mut |bsdf| healthy(bsdf, wi, wo, &wl, u1, Vec2::new(u2x, u2y)))?;
    }
}

/// Spec → model.
#[path = "proptest_models/mod.rs"]
mod proptest_models;
use proptest_models::{ROUGH_COATS, with_bsdf};

/// The polarized property: every model's Mueller values against its unpolarized ones.
#[path = "proptest_polarized/mod.rs"]
mod proptest_polarized;
