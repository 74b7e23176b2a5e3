//! # gonio-render
//!
//! Scenes (the Mitsuba 3 XML reader), shapes and acceleration, camera, emitters, textures, the
//! spectral path tracer, film and image files. Depends only on `gonio-core`.
//!
//! A Mitsuba 3 scene, read, prepared and rendered:
//!
//! ```
//! use gonio_render::render::{PreparedScene, RenderOptions, render};
//! use gonio_render::xml::load_scene_str;
//! use std::sync::atomic::AtomicBool;
//!
//! // A white furnace: a grey diffuse sphere under a uniform sky of radiance 1.
//! let xml = r#"<scene version="3.0.0">
//!     <integrator type="path"/>
//!     <sensor type="perspective">
//!         <float name="fov" value="30"/>
//!         <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
//!         <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
//!     </sensor>
//!     <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
//!     <shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
//! </scene>"#;
//! let scene = load_scene_str(xml, ".", &[]).unwrap();
//! let prepared = PreparedScene::new(scene).unwrap();
//! let options = RenderOptions { spp: 16, ..RenderOptions::from_scene(&prepared.scene) };
//! let out = render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false));
//! assert_eq!((out.image.width, out.image.height), (8, 8));
//! // Every pixel sees the sky or the sphere, and the sphere under a uniform sky is no brighter.
//! assert!(out.image.data.iter().flatten().all(|&v| v > 0.3 && v < 1.05));
//! ```
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
pub mod tensor_file;
pub mod texture;
pub mod xml;
