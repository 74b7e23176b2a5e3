//! `<phase>` plugins (Mitsuba 3 `src/phase/`): the phase function nested in a `<medium>`. The
//! models are [`gonio_core::phase::PhaseFunction`].

pub mod hg;
pub mod isotropic;
pub mod rayleigh;
