//! The BSDF models, one file each. Every file opens with the formula it implements, its source
//! (lecture slide, paper) and the Mitsuba 3 parameters with their defaults.

pub mod blendbsdf;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod hair;
pub mod lambertsphere;
pub mod lambertsphere_h;
pub mod null;
pub mod perturbed;
pub mod plastic;
pub mod polarizer;
pub mod pplastic;
pub mod principled;
pub mod principled_common;
pub mod principled_common_lanes;
pub mod principledthin;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughdiffuse;
pub mod roughplastic;
pub mod surface;
pub mod tabulated;
pub mod thindielectric;
pub mod twosided;

pub use blendbsdf::BlendBsdf;
pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use hair::{Hair, HairAbsorption, HairLobes};
pub use lambertsphere::LambertSphere;
pub use null::NullBsdf;
pub use perturbed::{Perturbation, PerturbedFrame};
pub use plastic::Plastic;
pub use polarizer::{CircularPolarizer, Polarizer, Retarder};
pub use pplastic::PPlastic;
pub use principled::Principled;
pub use principledthin::PrincipledThin;
pub use roughconductor::RoughConductor;
pub use roughdielectric::RoughDielectric;
pub use roughdiffuse::RoughDiffuse;
pub use roughplastic::{CoatAverages, RoughPlastic};
pub use surface::{LeafBsdf, SurfaceBsdf};
pub use tabulated::Tabulated;
pub use thindielectric::ThinDielectric;
pub use twosided::TwoSided;
