//! The BSDF models, one file each. Every file opens with the formula it implements, its source
//! (lecture slide, paper) and the Mitsuba 3 parameters with their defaults.

pub mod diffuse;

pub use diffuse::Diffuse;
