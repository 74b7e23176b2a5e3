//! Building the models `proptest_health` generates: a [`Spec`](super::Spec) (plain data that
//! proptest can shrink) into the BSDF it describes, children on the stack. Part of the
//! `proptest_health` test binary.

use super::*;

/// Builds the model (children live on this stack frame) and hands it to `f`.
pub(crate) fn with_bsdf<R>(spec: &Spec, f: &mut dyn FnMut(&dyn Bsdf) -> R) -> R {
    match spec {
        Spec::Diffuse { rho } => f(&Diffuse::new(rho.build())),
        Spec::Hair {
            eumelanin,
            pheomelanin,
            eta,
            beta_m,
            beta_n,
            tilt,
        } => f(&gonio_core::bsdfs::Hair {
            sigma_a: gonio_core::bsdfs::HairAbsorption::pigments(*eumelanin, *pheomelanin),
            eta: *eta,
            lobes: gonio_core::bsdfs::HairLobes::new(*beta_m, *beta_n, *tilt),
        }),
        Spec::Conductor { n, k, ext, tint } => {
            let mut c = Conductor::new(Spectrum::Constant(*n), Spectrum::Constant(*k));
            c.ext_ior = Ior::Constant(*ext);
            c.specular_reflectance = Spectrum::Constant(*tint);
            f(&c)
        }
        Spec::RoughConductor {
            n,
            k,
            ext,
            tint,
            ggx,
            alpha_u,
            alpha_v,
            visible,
        } => {
            let kind = if *ggx {
                MicrofacetKind::Ggx
            } else {
                MicrofacetKind::Beckmann
            };
            let d = MicrofacetDistribution::new(kind, *alpha_u, *alpha_v, *visible);
            let mut c = RoughConductor::new(Spectrum::Constant(*n), Spectrum::Constant(*k), d);
            c.ext_ior = Ior::Constant(*ext);
            c.specular_reflectance = Spectrum::Constant(*tint);
            f(&c)
        }
        Spec::RoughDiffuse { rho, alpha, model } => {
            let model = match model {
                0 => RoughDiffuseModel::OrenNayar,
                1 => RoughDiffuseModel::OrenNayarFast,
                2 => RoughDiffuseModel::Microfacet(MicrofacetKind::Beckmann),
                _ => RoughDiffuseModel::Microfacet(MicrofacetKind::Ggx),
            };
            f(&RoughDiffuse::new(rho.build(), *alpha, model))
        }
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
        } => {
            let int_ior = if *dispersive {
                // As the smooth dielectric's: n rises by 2 % towards the blue.
                Ior::from_spectrum(Spectrum::PiecewiseLinear(Arc::new(
                    PiecewiseLinear::from_interleaved(
                        &[360.0, int * 1.02, 830.0, *int],
                        Extrapolation::Clamp,
                    )
                    .unwrap(),
                )))
            } else {
                Ior::Constant(*int)
            };
            let kind = if *ggx {
                MicrofacetKind::Ggx
            } else {
                MicrofacetKind::Beckmann
            };
            let d = MicrofacetDistribution::new(kind, *alpha_u, *alpha_v, *visible);
            let mut r = RoughDielectric::new(int_ior, Ior::Constant(*ext), d);
            r.specular_reflectance = Spectrum::Constant(*refl);
            r.specular_transmittance = Spectrum::Constant(*trans);
            f(&r)
        }
        Spec::RoughMs {
            dielectric,
            n,
            k,
            ggx,
            alpha_u,
            alpha_v,
        } => {
            let kind = if *ggx {
                MicrofacetKind::Ggx
            } else {
                MicrofacetKind::Beckmann
            };
            let d = MicrofacetDistribution::new(kind, *alpha_u, *alpha_v, true);
            if *dielectric {
                let mut r = RoughDielectric::new(Ior::Constant(*n), Ior::Constant(*k), d);
                r.multiple_scattering = true;
                f(&r)
            } else {
                let mut c = RoughConductor::new(Spectrum::Constant(*n), Spectrum::Constant(*k), d);
                c.multiple_scattering = true;
                f(&c)
            }
        }
        Spec::LambertSphere {
            albedo,
            sphere,
            practical,
        } => {
            let kind = if *sphere {
                AlbedoParameter::Sphere
            } else {
                AlbedoParameter::Reflectance
            };
            let model = if *practical {
                LambertSphereModel::Practical
            } else {
                LambertSphereModel::Exact
            };
            f(&LambertSphere::new(albedo.build(), kind, model))
        }
        Spec::Dielectric {
            int,
            ext,
            refl,
            trans,
            dispersive,
        } => {
            let int_ior = if *dispersive {
                // Cauchy-like: n rises by 2 % towards the blue.
                Ior::Dispersive(Spectrum::PiecewiseLinear(Arc::new(
                    PiecewiseLinear::from_interleaved(
                        &[360.0, int * 1.02, 830.0, *int],
                        Extrapolation::Clamp,
                    )
                    .unwrap(),
                )))
            } else {
                Ior::Constant(*int)
            };
            let mut d = Dielectric::new(int_ior, Ior::Constant(*ext));
            d.specular_reflectance = Spectrum::Constant(*refl);
            d.specular_transmittance = Spectrum::Constant(*trans);
            f(&d)
        }
        Spec::Thin {
            int,
            ext,
            refl,
            trans,
        } => {
            let mut t = ThinDielectric::new(Ior::Constant(*int), Ior::Constant(*ext));
            t.specular_reflectance = Spectrum::Constant(*refl);
            t.specular_transmittance = Spectrum::Constant(*trans);
            f(&t)
        }
        Spec::Plastic {
            rho,
            int,
            ext,
            nonlinear,
            tint,
            s,
        } => {
            let mut p = Plastic::new(rho.build(), *int, *ext, *nonlinear, Spectrum::Constant(*tint));
            if let Some(s) = s {
                p = p.with_specular_sampling_weight(*s);
            }
            f(&p)
        }
        Spec::RoughPlastic {
            rho,
            tint,
            nonlinear,
            coat,
            s,
        } => {
            let coat = rough_coat(*coat).clone();
            let mut p = RoughPlastic::new(rho.build(), Spectrum::Constant(*tint), *nonlinear, coat);
            if let Some(s) = s {
                p = p.with_specular_sampling_weight(*s);
            }
            f(&p)
        }
        Spec::PPlastic {
            rho,
            tint,
            ggx,
            alpha_u,
            alpha_v,
            visible,
            iors: (int, ext),
            s,
        } => {
            let kind = if *ggx {
                MicrofacetKind::Ggx
            } else {
                MicrofacetKind::Beckmann
            };
            let d = MicrofacetDistribution::new(kind, *alpha_u, *alpha_v, *visible);
            let mut p =
                gonio_core::bsdfs::PPlastic::new(rho.build(), Spectrum::Constant(*tint), d, int / ext);
            if let Some(s) = s {
                p = p.with_specular_sampling_weight(*s);
            }
            f(&p)
        }
        Spec::Principled {
            rho,
            roughness,
            weights,
            eta,
            rates,
        } => {
            let mut p = Principled::new(rho.build());
            p.roughness = *roughness;
            [
                p.anisotropic,
                p.metallic,
                p.spec_trans,
                p.spec_tint,
                p.sheen,
                p.sheen_tint,
                p.flatness,
                p.clearcoat,
                p.clearcoat_gloss,
            ] = *weights;
            p.eta = *eta;
            (p.rates.diffuse, p.rates.main_specular, p.rates.clearcoat) = (rates[0], rates[1], rates[2]);
            f(&p)
        }
        Spec::PrincipledThin {
            rho,
            roughness,
            weights,
            eta,
            rates,
        } => {
            let mut p = PrincipledThin::new(rho.build());
            p.roughness = *roughness;
            [
                p.anisotropic,
                p.spec_trans,
                p.spec_tint,
                p.sheen,
                p.sheen_tint,
                p.flatness,
                p.diff_trans,
            ] = *weights;
            p.diff_trans *= 2.0;
            p.eta = *eta;
            let r = &mut p.rates;
            (
                r.diffuse_reflectance,
                r.specular_reflectance,
                r.specular_transmittance,
                r.diffuse_transmittance,
            ) = (rates[0], rates[1], rates[2], rates[3]);
            f(&p)
        }
        Spec::Tabulated { values } => {
            let th = vec![0.0, 30.0, 60.0, 90.0];
            let data = TabulatedData::new(
                th.clone(),
                th,
                vec![0.0, 90.0, 180.0],
                vec![450.0, 650.0],
                values.clone(),
                None,
                "proptest".into(),
            )
            .unwrap();
            f(&Tabulated::new(data))
        }
        Spec::Filter {
            kind,
            theta,
            delta,
            t,
            flag,
        } => match kind {
            0 => f(&Polarizer {
                theta: *theta,
                transmittance: t.build(),
                polarizing: *flag,
            }),
            1 => f(&Retarder {
                transmittance: t.build(),
                ..Retarder::new(*theta, *delta)
            }),
            _ => f(&CircularPolarizer {
                transmittance: t.build(),
                left_handed: *flag,
            }),
        },
        Spec::TwoSided { front, back } => with_bsdf(front, &mut |fr| match back {
            None => f(&TwoSided::new(fr)),
            Some(b) => with_bsdf(b, &mut |bk| f(&TwoSided::with_back(fr, bk))),
        }),
        Spec::Blend { w, a, b } => with_bsdf(a, &mut |x| with_bsdf(b, &mut |y| f(&BlendBsdf::new(*w, x, y)))),
    }
}

/// Rough plastic coats: α ∈ {1e-4, 0.01, 0.2, 1} × Beckmann/GGX × η ∈ {1.49, 3, 0.75} ×
/// (visible normals with exact averages, all normals with Mitsuba's). Each takes a fraction of a
/// second to build, so a case picks one of these, built on first use.
pub(crate) const ROUGH_COATS: usize = 48;

fn rough_coat(i: usize) -> &'static RoughCoat {
    static COATS: [OnceLock<RoughCoat>; ROUGH_COATS] = [const { OnceLock::new() }; ROUGH_COATS];
    COATS[i].get_or_init(|| {
        let alpha = [1e-4f32, 0.01, 0.2, 1.0][i % 4];
        let kind = [MicrofacetKind::Beckmann, MicrofacetKind::Ggx][(i / 4) % 2];
        let eta = [1.49f32, 3.0, 0.75][(i / 8) % 3];
        let (visible, averages) = [(true, CoatAverages::Exact), (false, CoatAverages::Mitsuba)][i / 24];
        RoughCoat::new(
            MicrofacetDistribution::new(kind, alpha, alpha, visible),
            eta,
            averages,
        )
    })
}
