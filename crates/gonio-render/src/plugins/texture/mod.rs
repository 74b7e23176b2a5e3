//! `<texture>` plugins (Mitsuba 3 `src/textures/`). The runtime textures are in
//! [`crate::texture`]. A texture is built in the role of the parameter it fills (reflectance,
//! unbounded, illuminant: `Builder::texture_param` in `xml/plugins.rs`), which its colours follow.

pub mod bitmap;
pub mod checkerboard;
pub mod mesh_attribute;
pub mod rawconstant;
pub mod volume;
