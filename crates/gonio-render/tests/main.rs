//! The integration tests of `gonio-render`, one module per file beside this one, linked into one test
//! binary: a binary per file cost a link of the whole renderer each, the larger part of a
//! clean `cargo test --release` on two cores. Add a test file by adding its `mod` line here
//! (`autotests = false` in Cargo.toml: a file not listed is not compiled).
//! Run one file's tests with `cargo test --release -p gonio-render --test integration <file>::`.

mod accel;
mod bsdf_plugins;
mod camera;
mod caustics;
mod compare;
mod corpus_scenes;
mod directional_area;
mod dispersion;
mod emitter;
mod film;
mod furnace;
mod geometry;
mod image;
mod integrator;
mod layers;
mod light_splitting;
mod lobe_split;
mod manifold;
mod measured;
mod measured_polarized;
mod media;
mod media_bounds;
mod mis_exponent;
mod mitsuba_bsdf_values;
mod mitsuba_json;
mod mitsuba_perturbed_values;
mod mitsuba_principled_values;
mod mitsuba_roughconductor_values;
mod mitsuba_roughdielectric_values;
mod mitsuba_roughplastic_values;
mod narrow_lobes;
mod path_weight;
mod plugins;
mod ptracer;
mod reference_scenes;
mod refracted;
mod render;
mod render_stats;
mod resampled;
mod russian_roulette;
mod sampler;
mod sggx;
mod specfilm;
mod spectrum_plugins;
mod sunsky;
mod xml_errors;
mod xml_grammar;
mod xml_mesh;
mod xml_plugins;
mod xml_robustness;
mod xml_scenes;
mod xml_serialized;
mod xml_tabulated;
mod xml_toplevel;
