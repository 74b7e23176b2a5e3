//! # gonio-render
//!
//! Scenes (the Mitsuba 3 XML reader), shapes and acceleration, camera, emitters, textures, the
//! spectral path tracer, film and image files. Depends only on `gonio-core`.
#![warn(missing_docs)]

pub mod camera;
pub mod sampler;
pub mod emitter;
pub mod accel;
pub mod compare;
pub mod film;
pub mod geometry;
pub mod image;
pub mod material;
pub mod mesh;
pub mod plot;
pub mod scene;
pub mod tabulated_io;
pub mod texture;
pub mod xml;
pub mod integrator;
pub mod render;
