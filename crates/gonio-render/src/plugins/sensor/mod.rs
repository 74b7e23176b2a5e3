//! `<sensor>` plugins.

pub mod orthographic;
pub mod perspective;
pub mod radiancemeter;
pub mod thinlens;
