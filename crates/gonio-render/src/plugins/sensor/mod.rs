//! `<sensor>` plugins.

pub mod batch;
pub mod distant;
pub mod irradiancemeter;
pub mod orthographic;
pub mod perspective;
pub mod radiancemeter;
pub mod thinlens;
