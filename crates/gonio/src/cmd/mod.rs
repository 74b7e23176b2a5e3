//! One module per subcommand.

pub mod bsdf;
pub mod check;
pub mod measure;
pub mod compare;
pub mod plot;
pub mod relight;
pub mod render;
