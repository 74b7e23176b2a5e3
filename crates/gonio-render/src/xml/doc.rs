//! The object tree the parser produces ([`Doc`]): objects with their properties in document
//! order, and the file resolver that turns a name written in a scene into a path.

use super::error::Location;
use super::values::SpecValue;
use glam::{DMat4, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Object kinds (XML tag names of objects).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) enum Tag {
    Scene,
    Bsdf,
    Emitter,
    Film,
    Integrator,
    Rfilter,
    Sampler,
    Sensor,
    Shape,
    Texture,
    /// `<spectrum type="…">`: a spectrum object (d65, blackbody, …).
    Spectrum,
    /// `<volume>`: data over space (`gridvolume`), read by the `volume` texture.
    Volume,
    /// `<medium>`: a participating medium (`homogeneous`).
    Medium,
    /// `<phase>`: a medium's phase function (`isotropic`, `hg`, `rayleigh`).
    Phase,
}

impl Tag {
    pub(crate) fn name(self) -> &'static str {
        match self {
            Tag::Scene => "scene",
            Tag::Bsdf => "bsdf",
            Tag::Emitter => "emitter",
            Tag::Film => "film",
            Tag::Integrator => "integrator",
            Tag::Rfilter => "rfilter",
            Tag::Sampler => "sampler",
            Tag::Sensor => "sensor",
            Tag::Shape => "shape",
            Tag::Texture => "texture",
            Tag::Spectrum => "spectrum",
            Tag::Volume => "volume",
            Tag::Medium => "medium",
            Tag::Phase => "phase",
        }
    }

    pub(crate) fn from_name(s: &str) -> Option<Self> {
        Some(match s {
            "bsdf" => Tag::Bsdf,
            "emitter" => Tag::Emitter,
            "film" => Tag::Film,
            "integrator" => Tag::Integrator,
            "rfilter" => Tag::Rfilter,
            "sampler" => Tag::Sampler,
            "sensor" => Tag::Sensor,
            "shape" => Tag::Shape,
            "texture" => Tag::Texture,
            "volume" => Tag::Volume,
            "medium" => Tag::Medium,
            "phase" => Tag::Phase,
            _ => return None,
        })
    }
}

/// A property value as written in the file (role-dependent conversion happens in the plugins).
#[derive(Clone, Debug)]
pub(crate) enum Value {
    Int(i64),
    Float(f64),
    Bool(bool),
    Str(String),
    Point(DVec3),
    Vector(DVec3),
    Rgb([f64; 3]),
    Spectrum(SpecValue),
    Transform(DMat4),
    /// A nested object (index into [`Doc::objs`]).
    Object(usize),
    /// `<ref id>`: resolved at instantiation.
    Ref(String),
}

impl Value {
    /// The type as the user would write it, for error messages.
    pub(crate) fn describe(&self, doc: &Doc) -> String {
        match self {
            Value::Int(v) => format!("integer {v}"),
            Value::Float(v) => format!("float {v}"),
            Value::Bool(v) => format!("boolean {v}"),
            Value::Str(s) => format!("string \"{s}\""),
            Value::Point(p) => format!("point ({}, {}, {})", p.x, p.y, p.z),
            Value::Vector(p) => format!("vector ({}, {}, {})", p.x, p.y, p.z),
            Value::Rgb(c) => format!("rgb ({}, {}, {})", c[0], c[1], c[2]),
            Value::Spectrum(_) => "spectrum".into(),
            Value::Transform(_) => "transform".into(),
            Value::Object(i) => {
                let o = &doc.objs[*i];
                format!("<{} type=\"{}\">", o.tag.name(), o.ty)
            }
            Value::Ref(id) => format!("reference to \"{id}\""),
        }
    }
}

/// One property of an object.
#[derive(Clone, Debug)]
pub(crate) struct Prop {
    /// Property name (`_arg_N` for unnamed nested objects and references).
    pub name: String,
    pub value: Value,
    /// Where the property element starts.
    pub loc: Location,
    /// Where its value attribute starts (the element when there is none).
    pub value_loc: Location,
}

/// An object: plugin kind, plugin name, id and properties in document order.
#[derive(Clone, Debug)]
pub(crate) struct Obj {
    pub tag: Tag,
    pub ty: String,
    pub id: Option<String>,
    pub loc: Location,
    /// Where the `type` attribute value is (for "unknown plugin" errors).
    pub ty_loc: Location,
    pub props: Vec<Prop>,
    /// Folder for relative file names (the folder of the file this object was written in).
    pub base_dir: PathBuf,
}

/// The parsed document.
#[derive(Debug, Default)]
pub(crate) struct Doc {
    pub objs: Vec<Obj>,
    pub ids: HashMap<String, usize>,
    /// The root object (the `<scene>`, or the lone `<bsdf>` of [`super::load_bsdf_str`]).
    pub root: usize,
    /// Extra search folders from `<path value>`.
    pub search_paths: Vec<PathBuf>,
    /// The folder of the scene file itself (None for a lone `<bsdf>` document).
    pub scene_dir: Option<PathBuf>,
    /// Parameters of ours that depart from Mitsuba's estimators default to Mitsuba's values
    /// ([`super::LoadOptions::mitsuba_estimators`]).
    pub mitsuba_estimators: bool,
}

impl Doc {
    /// Resolves a file name written in an object: relative names against the object's folder,
    /// then against the `<path>` folders, then against the scene file's folder. The last is for
    /// a name written in an included fragment but relative to the scene, as Mitsuba resolves it
    /// (its file resolver keeps the scene's folder while it reads an include: Mitsuba's own
    /// `scenes/cbox/fragments/shapes.xml` names `meshes/...` beside `cbox.xml`).
    pub(crate) fn resolve(&self, obj: &Obj, name: &str) -> PathBuf {
        let first = resolve_path(&obj.base_dir, &self.search_paths, name);
        match &self.scene_dir {
            Some(dir) if !first.exists() && !Path::new(name).is_absolute() && dir.join(name).exists() => {
                dir.join(name)
            }
            _ => first,
        }
    }
}

pub(crate) fn resolve_path(base: &Path, search: &[PathBuf], name: &str) -> PathBuf {
    let p = Path::new(name);
    if p.is_absolute() {
        return p.to_owned();
    }
    let first = base.join(p);
    if first.exists() {
        return first;
    }
    for s in search {
        let c = s.join(p);
        if c.exists() {
            return c;
        }
    }
    first
}
