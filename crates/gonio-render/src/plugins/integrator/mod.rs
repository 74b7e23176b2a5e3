//! `<integrator>` plugins.

pub mod aov;
pub mod depth;
pub mod direct;
pub mod moment;
pub mod path;
pub mod prb;
pub mod ptracer;
pub mod stokes;
pub mod volpath;
