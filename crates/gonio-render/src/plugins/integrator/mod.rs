//! `<integrator>` plugins.

pub mod path;
