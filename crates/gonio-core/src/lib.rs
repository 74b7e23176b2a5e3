//! # gonio-core
//!
//! The physics of gonio, after the lecture *Reflection Models I: Ideal Materials*: spectra and
//! hero-wavelength sampling, colour, Fresnel equations, sampling warps, one file per BSDF model,
//! and the checks every model must pass (χ², reciprocity, energy).
//!
//! Invariants: no file or scene I/O in this crate; `eval`, `pdf` and `sample` never allocate.
//!
//! A model is a [`Bsdf`]: evaluate it, sample it, check it.
//!
//! ```
//! use glam::{Vec2, Vec3};
//! use gonio_core::bsdfs::{Diffuse, Dielectric};
//! use gonio_core::check::{CheckConfig, all_passed, battery};
//! use gonio_core::fresnel::fresnel_dielectric;
//! use gonio_core::{Bsdf, BsdfContext, SampledWavelengths, Spectrum};
//!
//! // Lambert: f = ρ/π for directions on the same side.
//! let lambert = Diffuse::new(Spectrum::Constant(0.5));
//! let ctx = BsdfContext::radiance();
//! let wl = SampledWavelengths::fixed(550.0);
//! let (wi, wo) = (Vec3::new(0.0, 0.6, 0.8), Vec3::Z);
//! let f = lambert.eval(&ctx, wi, wo, &wl);
//! assert!((f.average() - 0.5 / std::f32::consts::PI).abs() < 1e-6);
//!
//! // Glass at normal incidence reflects ((η − 1)/(η + 1))² = 4 %.
//! assert!((fresnel_dielectric(1.0, 1.5).reflectance - 0.04).abs() < 1e-6);
//! let glass = Dielectric::default();
//! let mut wl2 = wl;
//! let s = glass.sample(&ctx, Vec3::Z, 0.5, Vec2::new(0.5, 0.5), &mut wl2).unwrap();
//! assert!(s.flags.is_delta());
//!
//! // The property battery behind `gonio check` (χ², reciprocity, energy, ...).
//! assert!(all_passed(&battery(&lambert, &CheckConfig::quick())));
//! ```
#![warn(missing_docs)]

pub mod albedo;
pub mod bsdf;
pub mod bsdfs;
pub mod check;
pub mod color;
mod data;
pub mod frame;
pub mod fresnel;
pub mod fresnel_polarized;
pub mod hash;
pub mod instruments;
pub mod ior;
pub mod lanes;
pub mod marginal2d;
pub mod math;
pub mod medium;
pub mod microfacet;
pub mod microsurface;
pub mod mueller;
pub mod named;
pub mod phase;
pub mod quadrature;
pub mod rgb2spec;
pub mod rng;
pub mod sampling;
pub mod sensor_response;
pub mod sggx;
pub mod spectra;
pub mod spectrum;
pub mod sunsky;
pub mod warp;
pub mod weight;

pub use bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, LobeSplit, TransportMode};
pub use frame::Frame;
pub use ior::Ior;
pub use spectra::Spectrum;
pub use spectrum::{SampledSpectrum, SampledWavelengths};
