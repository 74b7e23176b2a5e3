//! One module per subcommand.

pub mod bsdf;
pub mod check;
pub mod compare;
pub mod measure;
pub mod plot;
pub mod plot_diffuse;
pub mod plot_stokes;
pub mod relight;
pub mod render;
