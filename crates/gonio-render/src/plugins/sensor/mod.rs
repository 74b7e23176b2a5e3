//! `<sensor>` plugins.

pub mod orthographic;
pub mod perspective;
pub mod thinlens;
