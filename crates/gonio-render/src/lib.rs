//! # gonio-render
//!
//! Scenes (the Mitsuba 3 XML reader), shapes and acceleration, camera, emitters, textures, the
//! spectral path tracer, film and image files. Depends only on `gonio-core`.
#![warn(missing_docs)]

pub mod accel;
pub mod camera;
pub mod compare;
pub mod develop;
pub mod emitter;
pub mod film;
pub mod geometry;
pub mod image;
pub mod integrator;
pub mod material;
pub mod medium;
pub mod mesh;
pub mod output;
pub mod plugins;
pub mod render;
pub mod sampler;
pub mod scene;
pub mod tabulated_io;
pub mod texture;
pub mod xml;
