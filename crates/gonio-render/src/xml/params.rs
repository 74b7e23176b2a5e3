//! Plugin parameters: the table each plugin declares ([`ParamSpec`]) and typed access to the
//! parameters an object was given ([`Params`]), with the unused-parameter check.

use super::error::{ErrorKind, Location, SceneError};
use super::parse::{Doc, Obj, Prop, Tag, Value};
use crate::material::Material;
use glam::{Affine2, Affine3A, DMat4, DVec3, Mat2, Vec2};

type Result<T> = std::result::Result<T, SceneError>;

/// The type of a plugin parameter, as documented.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// `<float>` (or `<integer>`).
    Float,
    /// `<integer>`.
    Integer,
    /// `<boolean>`.
    Boolean,
    /// `<string>`.
    String,
    /// A spectrum that may not vary over the surface (`<float>`, `<rgb>`, `<spectrum>`).
    Spectrum,
    /// A colour: `<rgb>` (or one number for all three components).
    Rgb,
    /// A spectrum or a texture (`<float>`, `<rgb>`, `<spectrum>`, `<texture>`).
    Texture,
    /// An index of refraction: a number, a named material, or (ours) a dispersive glass or spectrum.
    Ior,
    /// Nested `<bsdf>` objects.
    Bsdf,
    /// A `<point>` (or `<vector>`).
    Point,
    /// A `<transform>`.
    Transform,
    /// A nested `<emitter>`.
    Emitter,
    /// A nested `<film>`.
    Film,
    /// A nested `<sampler>`.
    Sampler,
    /// A nested `<rfilter>`.
    Rfilter,
    /// Nested or referenced `<shape>` objects (`shapegroup`, `instance`).
    Shape,
    /// A nested or referenced `<volume>`.
    Volume,
    /// Nested `<sensor>` objects (`batch`, and a shape's `irradiancemeter`).
    Sensor,
    /// A nested or referenced `<medium>` (a shape's `interior`, `exterior`; a sensor's).
    Medium,
    /// A nested `<phase>` (a medium's phase function).
    Phase,
}

impl ParamType {
    /// How the documentation names it.
    pub fn name(self) -> &'static str {
        match self {
            ParamType::Float => "float",
            ParamType::Integer => "integer",
            ParamType::Boolean => "boolean",
            ParamType::String => "string",
            ParamType::Spectrum => "spectrum",
            ParamType::Rgb => "rgb",
            ParamType::Texture => "spectrum or texture",
            ParamType::Ior => "float or string",
            ParamType::Bsdf => "bsdf",
            ParamType::Point => "point",
            ParamType::Transform => "transform",
            ParamType::Emitter => "emitter",
            ParamType::Film => "film",
            ParamType::Sampler => "sampler",
            ParamType::Rfilter => "rfilter",
            ParamType::Shape => "shape",
            ParamType::Volume => "volume",
            ParamType::Sensor => "sensor",
            ParamType::Medium => "medium",
            ParamType::Phase => "phase",
        }
    }
}

/// A parameter's default: the value the reader uses when the parameter is absent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DefaultValue {
    /// A number (floats, constant spectra and textures).
    Float(f64),
    /// An integer.
    Int(i64),
    /// A boolean.
    Bool(bool),
    /// A string (names of presets, choices).
    Str(&'static str),
    /// A default that depends on other parameters, as the documentation states it (e.g.
    /// "¾ · cutoff_angle"); the builder computes it.
    Derived(&'static str),
    /// No default: the parameter must be given (or its absence has the meaning in the doc).
    None,
}

impl DefaultValue {
    /// The number; 0 for a non-number (a table error caught by the plugin tests).
    pub const fn float(self) -> f64 {
        match self {
            DefaultValue::Float(v) => v,
            _ => 0.0,
        }
    }
    /// The integer; 0 for a non-integer.
    pub const fn int(self) -> i64 {
        match self {
            DefaultValue::Int(v) => v,
            _ => 0,
        }
    }
    /// The boolean; false for a non-boolean.
    pub const fn bool(self) -> bool {
        matches!(self, DefaultValue::Bool(true))
    }
    /// The string; "" for a non-string.
    pub const fn str(self) -> &'static str {
        match self {
            DefaultValue::Str(s) => s,
            _ => "",
        }
    }
}

impl std::fmt::Display for DefaultValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DefaultValue::Float(v) => write!(f, "{v}"),
            DefaultValue::Int(v) => write!(f, "{v}"),
            DefaultValue::Derived(s) => f.write_str(s),
            DefaultValue::Bool(b) => write!(f, "{b}"),
            DefaultValue::Str(s) => write!(f, "\"{s}\""),
            DefaultValue::None => f.write_str("—"),
        }
    }
}

/// One row of a plugin's parameter table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamSpec {
    /// The XML name.
    pub name: &'static str,
    /// Its type.
    pub ty: ParamType,
    /// Used when absent.
    pub default: DefaultValue,
    /// What it means.
    pub doc: &'static str,
    /// For a parameter of ours where gonio's default departs from Mitsuba 3.9.1's estimator
    /// (to keep the physics right): the value that restores Mitsuba's, the default under
    /// [`crate::xml::LoadOptions::mitsuba_estimators`].
    pub mitsuba: Option<DefaultValue>,
}

impl ParamSpec {
    /// A table row.
    pub const fn new(name: &'static str, ty: ParamType, default: DefaultValue, doc: &'static str) -> Self {
        Self {
            name,
            ty,
            default,
            doc,
            mitsuba: None,
        }
    }

    /// A string switch of ours between gonio's way (`ours`, the default) and Mitsuba 3.9.1's
    /// (`"mitsuba"`, the default under [`crate::xml::LoadOptions::mitsuba_estimators`]); read it
    /// with `Params::mitsuba_way`.
    pub const fn ours_or_mitsuba(name: &'static str, ours: &'static str, doc: &'static str) -> Self {
        Self::new(name, ParamType::String, DefaultValue::Str(ours), doc).mitsuba(DefaultValue::Str("mitsuba"))
    }

    /// The row with the value that restores Mitsuba's estimator (see [`ParamSpec::mitsuba`]).
    pub const fn mitsuba(self, value: DefaultValue) -> Self {
        Self {
            mitsuba: Some(value),
            ..self
        }
    }
}

/// Builds a plugin's scene object of type `T` from its parsed parameters.
pub(crate) type Build<T> =
    for<'d, 'b> fn(&'b mut super::plugins::Builder<'d>, &'b mut Params<'d>) -> Result<T>;

/// A plugin of some kind (`<bsdf>`, `<shape>`, ...): its name, its parameter table and its
/// builder of the scene object `T`. Each kind has a registry of them (e.g.
/// [`crate::plugins::SHAPE_PLUGINS`]), from which the reader's "unknown plugin" and
/// "unused parameter" errors and `docs/plugins.md` are made.
pub struct Plugin<T: 'static> {
    /// The `type` attribute that selects it.
    pub name: &'static str,
    /// One line on what it is, with its source.
    pub summary: &'static str,
    /// Every parameter it accepts.
    pub params: &'static [ParamSpec],
    pub(crate) build: Build<T>,
}

/// A `<bsdf>` plugin.
pub type BsdfPlugin = Plugin<Material>;

impl<T> Plugin<T> {
    /// The plugin called `name` in `registry`.
    pub fn find(registry: &'static [&'static Plugin<T>], name: &str) -> Option<&'static Plugin<T>> {
        registry.iter().copied().find(|p| p.name == name)
    }

    /// The names of the plugins in `registry`, in order.
    pub fn names(registry: &[&Plugin<T>]) -> Vec<&'static str> {
        registry.iter().map(|p| p.name).collect()
    }
}

impl<T> std::fmt::Debug for Plugin<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Plugin").field("name", &self.name).finish()
    }
}

impl<T> Plugin<T> {
    /// The plugin's section of `docs/plugins.md` (a level-3 heading).
    pub fn markdown(&self) -> String {
        let mut s = format!("\n### `{}`\n\n{}\n\n", self.name, self.summary);
        s.push_str("| parameter | type | default | meaning |\n|---|---|---|---|\n");
        for p in self.params {
            let default = match p.mitsuba {
                Some(m) => format!("{} (Mitsuba: {m})", p.default),
                None => p.default.to_string(),
            };
            s.push_str(&format!(
                "| `{}` | {} | {} | {} |\n",
                p.name,
                p.ty.name(),
                default,
                p.doc
            ));
        }
        s
    }
}

pub(crate) fn err(loc: &Location, kind: ErrorKind, msg: impl Into<String>) -> SceneError {
    SceneError::new(loc.clone(), kind, msg)
}

/// Parameter access for one object: typed getters with defaults, and the unused-parameter check.
pub(crate) struct Params<'d> {
    pub(crate) doc: &'d Doc,
    pub(crate) obj: &'d Obj,
    used: Vec<bool>,
    /// The plugin's table, when it has one: the unused-parameter error lists its names.
    specs: &'static [ParamSpec],
}

impl<'d> Params<'d> {
    pub(crate) fn new(doc: &'d Doc, idx: usize) -> Self {
        let obj = &doc.objs[idx];
        Self {
            doc,
            obj,
            used: vec![false; obj.props.len()],
            specs: &[],
        }
    }

    /// The default of a table row for this document: [`ParamSpec::mitsuba`] when the scene is
    /// read with Mitsuba's estimators and the row has one, else [`ParamSpec::default`].
    pub(crate) fn default_of(&self, spec: &ParamSpec) -> DefaultValue {
        match spec.mitsuba {
            Some(m) if self.doc.mitsuba_estimators => m,
            _ => spec.default,
        }
    }

    /// Reads a switch made by [`ParamSpec::ours_or_mitsuba`]: true when it says `mitsuba`
    /// (written, or by default under Mitsuba's estimators).
    pub(crate) fn mitsuba_way(&mut self, spec: &ParamSpec) -> Result<bool> {
        let ours = spec.default.str();
        Ok(self.choice(spec.name, self.default_of(spec).str(), &[ours, "mitsuba"])? == "mitsuba")
    }

    /// Parameters checked against a plugin's table.
    pub(crate) fn with_specs(doc: &'d Doc, idx: usize, specs: &'static [ParamSpec]) -> Self {
        Self {
            specs,
            ..Self::new(doc, idx)
        }
    }

    pub(crate) fn what(&self) -> String {
        format!("<{} type=\"{}\">", self.obj.tag.name(), self.obj.ty)
    }

    /// The property `name`, marked as used.
    pub(crate) fn get(&mut self, name: &str) -> Option<&'d Prop> {
        let i = self.obj.props.iter().position(|p| p.name == name)?;
        self.used[i] = true;
        Some(&self.obj.props[i])
    }

    pub(crate) fn has(&self, name: &str) -> bool {
        self.obj.props.iter().any(|p| p.name == name)
    }

    pub(crate) fn wrong_type(&self, p: &Prop, expected: &str) -> SceneError {
        err(
            &p.value_loc,
            ErrorKind::WrongType,
            format!(
                "parameter \"{}\" of {} has the wrong type: expected {expected}, found {}",
                p.name,
                self.what(),
                p.value.describe(self.doc)
            ),
        )
    }

    pub(crate) fn float_opt(&mut self, name: &str) -> Result<Option<(f64, &'d Location)>> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Float(v) => Ok(Some((v, &p.value_loc))),
                Value::Int(v) => Ok(Some((v as f64, &p.value_loc))),
                _ => Err(self.wrong_type(p, "float")),
            },
        }
    }

    /// An `<rgb>` colour (a `<float>` or `<integer>` gives all three components).
    pub(crate) fn rgb_opt(&mut self, name: &str) -> Result<Option<([f64; 3], &'d Location)>> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Rgb(c) => Ok(Some((c, &p.value_loc))),
                Value::Float(v) => Ok(Some(([v; 3], &p.value_loc))),
                Value::Int(v) => Ok(Some(([v as f64; 3], &p.value_loc))),
                _ => Err(self.wrong_type(p, "rgb")),
            },
        }
    }

    pub(crate) fn float(&mut self, name: &str, default: f64) -> Result<f64> {
        Ok(self.float_opt(name)?.map_or(default, |(v, _)| v))
    }

    /// A float that must be finite and satisfy `ok`.
    pub(crate) fn float_checked(
        &mut self,
        name: &str,
        default: f64,
        ok: impl Fn(f64) -> bool,
        rule: &str,
    ) -> Result<f64> {
        match self.float_opt(name)? {
            None => Ok(default),
            // Finite in the file's double precision but not in the renderer's single precision.
            Some((v, loc)) if v.is_finite() && v.abs() > f32::MAX as f64 => Err(err(
                loc,
                ErrorKind::BadValue,
                format!(
                    "invalid {name} {} in {} (beyond single precision, |x| ≤ {:e})",
                    number(v),
                    self.what(),
                    f32::MAX
                ),
            )),
            Some((v, loc)) if v.is_finite() && ok(v) => {
                let _ = loc;
                Ok(v)
            }
            Some((v, loc)) => Err(err(
                loc,
                ErrorKind::BadValue,
                format!("invalid {name} {} in {} ({rule})", number(v), self.what()),
            )),
        }
    }

    pub(crate) fn int_opt(&mut self, name: &str) -> Result<Option<(i64, &'d Location)>> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Int(v) => Ok(Some((v, &p.value_loc))),
                _ => Err(self.wrong_type(p, "integer")),
            },
        }
    }

    /// An integer in [lo, hi].
    pub(crate) fn int_in(&mut self, name: &str, default: i64, lo: i64, hi: i64) -> Result<i64> {
        match self.int_opt(name)? {
            None => Ok(default),
            Some((v, loc)) if (lo..=hi).contains(&v) => {
                let _ = loc;
                Ok(v)
            }
            Some((v, loc)) => Err(err(
                loc,
                ErrorKind::BadValue,
                format!("invalid {name} {v} in {} (must be in [{lo}, {hi}])", self.what()),
            )),
        }
    }

    pub(crate) fn bool(&mut self, name: &str, default: bool) -> Result<bool> {
        match self.get(name) {
            None => Ok(default),
            Some(p) => match p.value {
                Value::Bool(v) => Ok(v),
                _ => Err(self.wrong_type(p, "boolean")),
            },
        }
    }

    pub(crate) fn string_opt(&mut self, name: &str) -> Result<Option<(&'d str, &'d Location)>> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match &p.value {
                Value::Str(s) => Ok(Some((s.as_str(), &p.value_loc))),
                _ => Err(self.wrong_type(p, "string")),
            },
        }
    }

    /// A string that must be one of `allowed`.
    pub(crate) fn choice(
        &mut self,
        name: &str,
        default: &'static str,
        allowed: &[&'static str],
    ) -> Result<&'static str> {
        match self.string_opt(name)? {
            None => Ok(default),
            Some((s, loc)) => allowed
                .iter()
                .find(|a| a.eq_ignore_ascii_case(s))
                .copied()
                .ok_or_else(|| {
                    err(
                        loc,
                        ErrorKind::BadValue,
                        format!(
                            "invalid {name} \"{s}\" in {} (expected one of: {})",
                            self.what(),
                            allowed.join(", ")
                        ),
                    )
                }),
        }
    }

    pub(crate) fn point_opt(&mut self, name: &str) -> Result<Option<(DVec3, &'d Location)>> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Point(v) | Value::Vector(v) => Ok(Some((v, &p.value_loc))),
                _ => Err(self.wrong_type(p, "point")),
            },
        }
    }

    pub(crate) fn transform_opt(&mut self, name: &str) -> Result<Option<(DMat4, &'d Location)>> {
        match self.get(name) {
            None => Ok(None),
            Some(p) => match p.value {
                Value::Transform(m) => Ok(Some((m, &p.loc))),
                _ => Err(self.wrong_type(p, "transform")),
            },
        }
    }

    pub(crate) fn affine(&mut self, name: &str) -> Result<Affine3A> {
        match self.transform_opt(name)? {
            None => Ok(Affine3A::IDENTITY),
            Some((m, loc)) => to_affine(m, loc, name),
        }
    }

    #[allow(clippy::wrong_self_convention)] // Mitsuba's parameter name, `to_uv`
    pub(crate) fn to_uv(&mut self) -> Result<Affine2> {
        Ok(match self.transform_opt("to_uv")? {
            None => Affine2::IDENTITY,
            Some((m, _)) => {
                // Rows/columns 0, 1, 3 of the 4×4 (Mitsuba drops the third).
                Affine2::from_mat2_translation(
                    Mat2::from_cols(
                        Vec2::new(m.x_axis.x as f32, m.x_axis.y as f32),
                        Vec2::new(m.y_axis.x as f32, m.y_axis.y as f32),
                    ),
                    Vec2::new(m.w_axis.x as f32, m.w_axis.y as f32),
                )
            }
        })
    }

    /// Nested objects (positional or named) whose tag is `tag`, in document order: Mitsuba 3.9.1
    /// hands a plugin its child objects in the order they were declared, whatever their names
    /// (its documentation says alphanumeric order; `blendbsdf`, `twosided` and `blendphase` with
    /// children named `b` then `a` take `b` first).
    pub(crate) fn objects(&mut self, tag: Tag) -> Result<Vec<(usize, &'d Prop)>> {
        let mut out = Vec::new();
        for (i, p) in self.obj.props.iter().enumerate() {
            let target = match &p.value {
                Value::Object(o) => *o,
                Value::Ref(id) => resolve_ref(self.doc, id, &p.value_loc)?,
                _ => continue,
            };
            if self.doc.objs[target].tag == tag {
                self.used[i] = true;
                out.push((target, p));
            }
        }
        Ok(out)
    }

    /// Fails on the first property nobody asked for (checking again later is harmless).
    pub(crate) fn finish(&self) -> Result<()> {
        for (p, used) in self.obj.props.iter().zip(&self.used) {
            if !used {
                let what = match &p.value {
                    Value::Object(_) | Value::Ref(_) => format!("nested {}", p.value.describe(self.doc)),
                    v => format!("parameter \"{}\" ({})", p.name, v.describe(self.doc)),
                };
                let accepted = if self.specs.is_empty() {
                    String::new()
                } else {
                    let names: Vec<&str> = self.specs.iter().map(|s| s.name).collect();
                    format!("; it accepts: {}", names.join(", "))
                };
                return Err(err(
                    &p.loc,
                    ErrorKind::UnusedParameter,
                    format!(
                        "unused {what} in {} (misspelt or not supported by this plugin{accepted})",
                        self.what()
                    ),
                ));
            }
        }
        Ok(())
    }
}

pub(crate) fn resolve_ref(doc: &Doc, id: &str, loc: &Location) -> Result<usize> {
    doc.ids.get(id).copied().ok_or_else(|| {
        err(
            loc,
            ErrorKind::Reference,
            format!("reference to unknown id \"{id}\""),
        )
    })
}

/// A 4×4 to an affine map; rejects projective, degenerate and non-finite matrices.
pub(crate) fn to_affine(m: DMat4, loc: &Location, name: &str) -> Result<Affine3A> {
    let row3 = m.row(3);
    if !m.is_finite() || (row3 - glam::DVec4::new(0.0, 0.0, 0.0, 1.0)).abs().max_element() > 1e-9 {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "{name} is not an affine transform (last row {:?})",
                row3.to_array()
            ),
        ));
    }
    let det = m.determinant();
    if det.abs() < 1e-300 || !det.is_finite() {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!("{name} is singular (determinant {det})"),
        ));
    }
    Ok(Affine3A::from_mat4(m.as_mat4()))
}

/// A number as an error message shows it: plain when short, in scientific notation when huge
/// or tiny (1e308 rather than 309 digits).
pub(crate) fn number(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}
