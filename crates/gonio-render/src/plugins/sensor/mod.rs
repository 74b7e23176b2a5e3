//! `<sensor>` plugins.

pub mod perspective;
