//! `<phase>` plugins (Mitsuba 3 `src/phase/`): the phase function nested in a `<medium>`. The
//! models are [`gonio_core::phase::PhaseFunction`], held as [`crate::medium::Phase`] (which
//! adds `blendphase` and `sggx`, whose parameters vary in space).

pub mod blendphase;
pub mod hg;
pub mod isotropic;
pub mod rayleigh;
pub mod sggx;
pub mod tabphase;
