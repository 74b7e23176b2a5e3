//! The Mitsuba 3 scene XML reader.
//!
//! [`load_scene_file`] / [`load_scene_str`] read a scene as Mitsuba 3 would (grammar of
//! its `src/core/parser.cpp`: `version`, `<default>` and `$name` substitution with `-D` overrides,
//! `id`/`ref` with forward references, `<include>`, `<alias>`, `<path>`, property values and
//! transforms; legacy scenes with version < 2 have their camelCase names converted) and
//! instantiate the plugins with Mitsuba's parameter names and defaults (each plugin's table in
//! [`crate::plugins`] and [`crate::material`] lists them). As in Mitsuba, an unknown plugin or a
//! parameter that no plugin uses is an error. [`load_bsdf_str`] reads a lone `<bsdf>` element
//! (for `gonio bsdf`).
//!
//! Every error is a [`SceneError`] naming the file, line and column, and the offending value.

mod doc;
mod error;
mod params;
mod parse;
pub(crate) mod plugins;
mod property;
mod values;

pub(crate) use doc::Value;
pub use error::{ErrorKind, Location, SceneError};
pub use params::{BsdfPlugin, DefaultValue, ParamSpec, ParamType, Plugin};
pub(crate) use params::{Params, err, resolve_ref, to_affine};
pub(crate) use parse::{Obj, Tag};
pub(crate) use plugins::{Builder, image_error, unknown_plugin};
pub(crate) use values::{SpecValue, parse_list};

use crate::material::Material;
use crate::scene::Scene;
use parse::Parser;
use std::path::Path;
use std::sync::Arc;

/// A loaded scene and the warnings Mitsuba would print (missing integrator or sensor, extra
/// sensors).
#[derive(Clone, Debug)]
pub struct LoadedScene {
    /// The scene.
    pub scene: Scene,
    /// Non-fatal remarks, each starting with its location.
    pub warnings: Vec<String>,
}

/// How a scene file is read, beyond its text.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LoadOptions {
    /// `-D name=value` overrides of `<default>` parameters; a define the scene never uses is an
    /// error.
    pub defines: Vec<(String, String)>,
    /// Mitsuba 3.9.1's estimators where gonio's defaults depart from them to keep the physics
    /// right (`gonio render --mitsuba-estimators`): every parameter of ours whose table row has a
    /// [`ParamSpec::mitsuba`] value defaults to it (thin glass blocks shadow rays, no caustic
    /// light subpaths, `plastic` and `roughplastic` with Mitsuba's coat fits and tables,
    /// `blendbsdf` with Mitsuba's delta pdf, `envmap` with Mitsuba's lookup, textured `projector`
    /// and `area` emitters without D65). A value written in the scene still wins. For
    /// side-by-side comparisons with Mitsuba.
    pub mitsuba_estimators: bool,
}

/// Reads a scene file with [`LoadOptions`], also returning the warnings.
pub fn load_scene_file_with(
    path: impl AsRef<Path>,
    options: &LoadOptions,
) -> Result<LoadedScene, SceneError> {
    let path = path.as_ref();
    let name: Arc<str> = path.display().to_string().into();
    let text = std::fs::read_to_string(path).map_err(|e| {
        SceneError::new(
            Location::file_only(name.clone()),
            ErrorKind::Io,
            format!("cannot read scene file: {e}"),
        )
    })?;
    let dir = path.parent().map(Path::to_owned).unwrap_or_default();
    load(&text, name, dir, path.canonicalize().ok(), options)
}

/// Reads a scene file. `defines` are `-D name=value` overrides of `<default>` parameters; a
/// define the scene never uses is an error. Relative file names resolve against the scene's
/// folder.
pub fn load_scene_file(path: impl AsRef<Path>, defines: &[(String, String)]) -> Result<Scene, SceneError> {
    load_scene_file_with_warnings(path, defines).map(|l| l.scene)
}

/// [`load_scene_file`], also returning the warnings.
pub fn load_scene_file_with_warnings(
    path: impl AsRef<Path>,
    defines: &[(String, String)],
) -> Result<LoadedScene, SceneError> {
    load_scene_file_with(
        path,
        &LoadOptions {
            defines: defines.to_vec(),
            ..LoadOptions::default()
        },
    )
}

/// Reads a scene from text; relative file names resolve against `base_dir`.
pub fn load_scene_str(
    text: &str,
    base_dir: impl AsRef<Path>,
    defines: &[(String, String)],
) -> Result<Scene, SceneError> {
    load_scene_str_with_warnings(text, base_dir, defines).map(|l| l.scene)
}

/// [`load_scene_str`], also returning the warnings.
pub fn load_scene_str_with_warnings(
    text: &str,
    base_dir: impl AsRef<Path>,
    defines: &[(String, String)],
) -> Result<LoadedScene, SceneError> {
    load(
        text,
        "<string>".into(),
        base_dir.as_ref().to_owned(),
        None,
        &LoadOptions {
            defines: defines.to_vec(),
            ..LoadOptions::default()
        },
    )
}

fn load(
    text: &str,
    name: Arc<str>,
    dir: std::path::PathBuf,
    canonical: Option<std::path::PathBuf>,
    options: &LoadOptions,
) -> Result<LoadedScene, SceneError> {
    let mut parser = Parser::new(&options.defines);
    parser.doc.mitsuba_estimators = options.mitsuba_estimators;
    parser.parse_scene_text(text, name.clone(), dir, canonical)?;
    parser.check_defines_used(&name)?;
    let (scene, warnings) = plugins::Builder::new(&parser.doc).scene()?;
    Ok(LoadedScene { scene, warnings })
}

/// Reads a lone `<bsdf>` element (a `version` attribute is allowed on it), as `gonio bsdf`
/// takes on its command line: `<bsdf type="plastic"><rgb name="diffuse_reflectance"
/// value="0.2, 0.4, 0.8"/></bsdf>`. Relative file names (bitmaps, spectra) resolve against the
/// current folder.
pub fn load_bsdf_str(text: &str) -> Result<Material, SceneError> {
    let mut parser = Parser::new(&[]);
    let name: Arc<str> = "<bsdf>".into();
    parser.parse_bsdf_text(text, name, std::path::PathBuf::from("."))?;
    let doc = &parser.doc;
    let root = doc.root;
    debug_assert_eq!(doc.objs[root].tag, Tag::Bsdf);
    let loc = doc.objs[root].loc.clone();
    plugins::Builder::new(doc).bsdf(root, &loc)
}

#[cfg(test)]
mod tests {
    use super::parse::camel_to_snake;
    use crate::plugins::sensor::perspective::fov_to_x;

    #[test]
    fn camel_case_names() {
        assert_eq!(camel_to_snake("maxDepth"), "max_depth");
        assert_eq!(camel_to_snake("toWorld"), "to_world");
        assert_eq!(camel_to_snake("sampleCount"), "sample_count");
        assert_eq!(camel_to_snake("radius"), "radius");
    }

    #[test]
    fn fov_axis_conversions() {
        let aspect = 768.0 / 576.0;
        assert!((fov_to_x(40.0, "x", aspect) - 40.0).abs() < 1e-12);
        // y: tan(fx/2) = aspect tan(fy/2).
        let fx = fov_to_x(30.0, "y", aspect);
        assert!(((fx / 2.0).to_radians().tan() - aspect * 15f64.to_radians().tan()).abs() < 1e-12);
        assert_eq!(fov_to_x(30.0, "smaller", aspect), fx);
        assert_eq!(fov_to_x(30.0, "larger", aspect), 30.0);
        assert_eq!(fov_to_x(30.0, "smaller", 0.5), 30.0);
        // 50 mm on 35 mm film at 4:3 → 38.1848° (Mitsuba 3 src/render/sensor.cpp).
        let diag = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
        let fd = 2.0 * (diag / 100.0).atan().to_degrees();
        assert!((fov_to_x(fd, "diagonal", aspect) - 38.1848).abs() < 1e-3);
    }
}
