//! `<integrator>` plugins.

pub mod depth;
pub mod direct;
pub mod path;
pub mod prb;
pub mod ptracer;
pub mod stokes;
