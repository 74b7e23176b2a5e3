//! # gonio-core
//!
//! The physics of gonio, after the lecture *Reflection Models I: Ideal Materials*: spectra and
//! hero-wavelength sampling, colour, Fresnel equations, sampling warps, one file per BSDF model,
//! and the checks every model must pass (χ², reciprocity, energy).
//!
//! Invariants: no file or scene I/O in this crate; `eval`, `pdf` and `sample` never allocate.
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
pub mod spectra;
pub mod spectrum;
pub mod warp;
pub mod weight;

pub use bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample, LobeSplit, TransportMode};
pub use frame::Frame;
pub use ior::Ior;
pub use spectra::Spectrum;
pub use spectrum::{SampledSpectrum, SampledWavelengths};
