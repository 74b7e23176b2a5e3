//! The plugin registries of every kind (`gonio_render::plugins`): their tables are consistent,
//! every row is a parameter the builder reads, the reader's "unknown plugin" and "unused
//! parameter" errors come from them, the scene's defaults are the tables' defaults, and
//! `docs/plugins.md` is generated from them.

use gonio_render::plugins::{DefaultValue, KindTable, ParamSpec, ParamType, all_kinds, plugins_markdown};
use gonio_render::scene::{FilmDesc, FilterDesc, IntegratorDesc, SamplerDesc};
use gonio_render::xml::{ErrorKind, SceneError, load_scene_str, load_scene_str_with_warnings};
use std::path::PathBuf;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn load(body: &str) -> Result<gonio_render::scene::Scene, SceneError> {
    load_scene_str(&format!("<scene version=\"3.0.0\">{body}</scene>"), data(), &[])
}

/// A scene holding one object of `kind` and type `name` with the parameters `params` (XML).
fn scene_with(kind: &str, name: &str, params: &str) -> String {
    let object = |tag: &str| format!("<{tag} type=\"{name}\">{params}</{tag}>");
    match kind {
        // The irradiance meter measures over the shape it is nested in.
        "sensor" if name == "irradiancemeter" => {
            format!("<shape type=\"sphere\">{}</shape>", object("sensor"))
        }
        "integrator" | "sensor" | "shape" => object(kind),
        "emitter" if name == "area" || name == "directionalarea" => {
            format!("<shape type=\"sphere\">{}</shape>", object("emitter"))
        }
        "emitter" => object("emitter"),
        "film" | "sampler" => format!("<sensor type=\"perspective\">{}</sensor>", object(kind)),
        "rfilter" => format!(
            "<sensor type=\"perspective\"><film type=\"hdrfilm\">{}</film></sensor>",
            object("rfilter")
        ),
        "texture" => format!(
            "<bsdf type=\"diffuse\"><texture name=\"reflectance\" type=\"{name}\">{params}</texture></bsdf>"
        ),
        "spectrum" => format!(
            "<bsdf type=\"diffuse\"><spectrum name=\"reflectance\" type=\"{name}\">{params}</spectrum></bsdf>"
        ),
        "bsdf" => object("bsdf"),
        "volume" => object("volume"),
        "medium" => object("medium"),
        "phase" => format!("<medium type=\"homogeneous\">{}</medium>", object("phase")),
        k => panic!("unknown kind {k}"),
    }
}

/// Parameters a plugin cannot do without (files from `tests/data`).
fn required(name: &str) -> &'static str {
    match name {
        "obj" => "<string name=\"filename\" value=\"quad.obj\"/>",
        "ply" => "<string name=\"filename\" value=\"quad_ascii.ply\"/>",
        "serialized" => "<string name=\"filename\" value=\"quad.serialized\"/>",
        "bitmap" | "envmap" => "<string name=\"filename\" value=\"rgbw.png\"/>",
        "blackbody" => "<float name=\"temperature\" value=\"3000\"/>",
        "regular" => {
            "<float name=\"wavelength_min\" value=\"400\"/><float name=\"wavelength_max\" value=\"700\"/><string name=\"values\" value=\"0.5, 0.7\"/>"
        }
        "irregular" => {
            "<string name=\"wavelengths\" value=\"400, 700\"/><string name=\"values\" value=\"0.5, 0.7\"/>"
        }
        "srgb" => "<rgb name=\"color\" value=\"0.5, 0.2, 0.1\"/>",
        "rawconstant" => "<float name=\"value\" value=\"0.5\"/>",
        "thinlens" => "<float name=\"aperture_radius\" value=\"0.1\"/>",
        "batch" => "<sensor type=\"perspective\"/>",
        "radiancemeter" | "distant" => {
            "<film type=\"hdrfilm\"><integer name=\"width\" value=\"1\"/><integer name=\"height\" value=\"1\"/></film>"
        }
        "instance" => "<shape type=\"shapegroup\"><shape type=\"sphere\"/></shape>",
        "sdfgrid" => "<string name=\"filename\" value=\"sphere_sdf.vol\"/>",
        "sggx" => {
            "<volume name=\"S\" type=\"gridvolume\"><string name=\"filename\" value=\"../../../../testdata/sggx/flakes.vol\"/></volume>"
        }
        "linearcurve" | "bsplinecurve" => "<string name=\"filename\" value=\"curve.txt\"/>",
        "projector" => "<float name=\"irradiance\" value=\"1\"/>",
        "stokes" => "<integrator type=\"path\"/>",
        "aov" => "<string name=\"aovs\" value=\"d:depth\"/>",
        "mesh_attribute" => "<string name=\"name\" value=\"vertex_color\"/>",
        "gridvolume" => "<string name=\"filename\" value=\"sphere_sdf.vol\"/>",
        "tabphase" => "<string name=\"values\" value=\"1, 2, 3\"/>",
        "blendphase" => "<phase type=\"isotropic\"/><phase type=\"rayleigh\"/>",
        "specfilm" => "<spectrum name=\"band\" value=\"400:1, 700:1\"/>",
        "volume" => {
            "<volume type=\"gridvolume\"><string name=\"filename\" value=\"sphere_sdf.vol\"/></volume>"
        }
        _ => "",
    }
}

/// The row as XML, set to its default; `None` when it has no value of its own (nested objects,
/// transforms, points, defaults derived from other parameters, no default).
fn row_xml(p: &ParamSpec) -> Option<String> {
    let n = p.name;
    Some(match (p.ty, p.default) {
        (ParamType::Boolean, DefaultValue::Bool(v)) => format!("<boolean name=\"{n}\" value=\"{v}\"/>"),
        (ParamType::Integer, DefaultValue::Int(v)) => format!("<integer name=\"{n}\" value=\"{v}\"/>"),
        (ParamType::Float | ParamType::Spectrum | ParamType::Texture, DefaultValue::Float(v)) => {
            format!("<float name=\"{n}\" value=\"{v}\"/>")
        }
        (ParamType::Rgb, DefaultValue::Float(v)) => format!("<rgb name=\"{n}\" value=\"{v}\"/>"),
        (ParamType::String | ParamType::Ior, DefaultValue::Str(s)) => {
            format!("<string name=\"{n}\" value=\"{s}\"/>")
        }
        _ => return None,
    })
}

fn non_bsdf_kinds() -> impl Iterator<Item = KindTable> {
    all_kinds().into_iter().filter(|k| k.tag != "bsdf")
}

#[test]
fn every_table_default_has_its_parameters_type() {
    for kind in all_kinds() {
        for (name, summary, params) in &kind.plugins {
            assert!(!summary.is_empty(), "{}", name);
            for p in *params {
                let ok = match (p.ty, p.default) {
                    (_, DefaultValue::None) => true,
                    (_, DefaultValue::Derived(s)) => !s.is_empty(),
                    (
                        ParamType::Float | ParamType::Spectrum | ParamType::Texture | ParamType::Rgb,
                        DefaultValue::Float(v),
                    ) => v.is_finite(),
                    (ParamType::Integer, DefaultValue::Int(_)) => true,
                    (ParamType::Boolean, DefaultValue::Bool(_)) => true,
                    (
                        ParamType::String
                        | ParamType::Ior
                        | ParamType::Film
                        | ParamType::Sampler
                        | ParamType::Rfilter
                        | ParamType::Phase,
                        DefaultValue::Str(s),
                    ) => !s.is_empty(),
                    _ => false,
                };
                assert!(
                    ok,
                    "{} {}.{}: default {:?} does not fit {:?}",
                    kind.tag, name, p.name, p.default, p.ty
                );
                assert!(!p.doc.is_empty(), "{}.{} has no doc", name, p.name);
            }
        }
    }
}

#[test]
fn names_are_unique_within_a_kind_and_a_table() {
    let mut seen = std::collections::HashSet::new();
    for kind in all_kinds() {
        for (name, _, params) in &kind.plugins {
            assert!(
                seen.insert((kind.tag, *name)),
                "{} {name} registered twice",
                kind.tag
            );
            let mut rows = std::collections::HashSet::new();
            for p in *params {
                assert!(rows.insert(p.name), "{name}.{} listed twice", p.name);
            }
        }
    }
}

/// Every row with a value of its own is read by the builder: set to its default, it loads.
#[test]
fn every_row_is_a_parameter_the_plugin_reads() {
    let mut checked = 0;
    for kind in non_bsdf_kinds() {
        for (name, _, params) in &kind.plugins {
            let base = required(name);
            load(&scene_with(kind.tag, name, base)).unwrap_or_else(|e| panic!("{name}: {e}"));
            for row in params.iter().filter_map(|p| row_xml(p).map(|x| (p.name, x))) {
                if base.contains(&format!("\"{}\"", row.0)) {
                    continue;
                }
                let text = scene_with(kind.tag, name, &format!("{base}{}", row.1));
                load(&text).unwrap_or_else(|e| panic!("{} {name}.{}: {e}\n{text}", kind.tag, row.0));
                checked += 1;
            }
        }
    }
    assert!(checked > 40, "only {checked} rows checked");
}

#[test]
fn unknown_plugin_error_lists_the_registry() {
    for kind in all_kinds() {
        let e = load(&scene_with(kind.tag, "velvet", "")).unwrap_err();
        assert_eq!(e.kind, ErrorKind::UnknownPlugin, "{}: {e}", kind.tag);
        let msg = e.to_string();
        assert!(msg.contains("(supported: "), "{msg}");
        for (name, _, _) in &kind.plugins {
            assert!(msg.contains(name), "{}: {msg}", kind.tag);
        }
    }
}

#[test]
fn unused_parameter_error_lists_the_accepted_names() {
    for kind in non_bsdf_kinds() {
        for (name, _, params) in &kind.plugins {
            let extra = format!("{}<float name=\"misspelt\" value=\"1\"/>", required(name));
            let e = load(&scene_with(kind.tag, name, &extra)).unwrap_err();
            assert_eq!(e.kind, ErrorKind::UnusedParameter, "{name}: {e}");
            let names: Vec<&str> = params.iter().map(|p| p.name).collect();
            let msg = e.to_string();
            // A plugin without parameters (`catmullrom`) has no list to give.
            let expected = if names.is_empty() {
                "not supported by this plugin)".to_string()
            } else {
                format!("it accepts: {}", names.join(", "))
            };
            assert!(msg.contains(&expected), "{name}: {msg}");
        }
    }
}

/// The scene's defaults (`Default` impls and the sensor of a scene without one) are the tables'.
#[test]
fn absent_objects_are_their_plugins_with_every_default() {
    let explicit = load(
        "<integrator type=\"path\"/><sensor type=\"perspective\"><film type=\"hdrfilm\">\
         <rfilter type=\"gaussian\"/></film><sampler type=\"independent\"/></sensor>",
    )
    .unwrap();
    assert_eq!(explicit.integrator, IntegratorDesc::default());
    assert_eq!(explicit.sensor.film, FilmDesc::default());
    assert_eq!(explicit.sensor.film.filter, FilterDesc::default());
    assert_eq!(explicit.sensor.sampler, SamplerDesc::default());
    let implicit = load_scene_str_with_warnings("<scene version=\"3.0.0\"/>", data(), &[]).unwrap();
    assert_eq!(implicit.warnings.len(), 2, "{:?}", implicit.warnings);
    assert_eq!(explicit.sensor, implicit.scene.sensor);
}

/// `docs/plugins.md` is generated from the tables; `GONIO_BLESS=1` rewrites it.
#[test]
fn docs_plugins_md_is_generated_from_the_tables() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/plugins.md");
    let want = plugins_markdown();
    if std::env::var_os("GONIO_BLESS").is_some() {
        std::fs::write(path, &want).unwrap();
    }
    let have = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        have == want,
        "docs/plugins.md is stale: run GONIO_BLESS=1 cargo test --release -p gonio-render --test integration plugins::"
    );
    for kind in all_kinds() {
        for (name, _, _) in &kind.plugins {
            assert!(
                want.contains(&format!("### `{name}`")),
                "{name} is not documented"
            );
        }
    }
}
