//! XML → object tree: the grammar of Mitsuba 3 scene files (Mitsuba 3
//! `docs/src/key_topics/scene_format.rst`, `src/core/parser.cpp`).
//!
//! The parser reads the XML with `roxmltree`, substitutes `$name` parameters in every attribute
//! value, expands `<include>`, parses property values and transforms, and produces an arena of
//! [`Obj`]s, each with its properties in document order. Plugin instantiation (which parameters a
//! plugin takes, defaults, the unused-parameter check) happens afterwards in `plugins.rs`, so
//! forward references work.

use super::error::{ErrorKind, Location, SceneError};
use super::values::{self, SpecValue};
use glam::{DMat4, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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
        }
    }

    fn from_name(s: &str) -> Option<Self> {
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
}

impl Doc {
    /// Resolves a file name written in an object: relative names against the object's folder,
    /// then against the `<path>` folders.
    pub(crate) fn resolve(&self, obj: &Obj, name: &str) -> PathBuf {
        resolve_path(&obj.base_dir, &self.search_paths, name)
    }
}

fn resolve_path(base: &Path, search: &[PathBuf], name: &str) -> PathBuf {
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

/// One XML file being parsed.
struct FileCtx<'a, 'i> {
    doc: &'a roxmltree::Document<'i>,
    name: Arc<str>,
    dir: PathBuf,
    legacy: bool,
}

impl FileCtx<'_, '_> {
    fn loc_at(&self, pos: usize) -> Location {
        let p = self.doc.text_pos_at(pos);
        Location {
            file: self.name.clone(),
            line: p.row,
            column: p.col,
        }
    }
    fn loc(&self, node: roxmltree::Node) -> Location {
        self.loc_at(node.range().start)
    }
}

/// Attribute values of one element after `$` substitution, with their positions.
struct Attrs {
    list: Vec<(String, String, Location)>,
    elem: Location,
}

impl Attrs {
    fn get(&self, name: &str) -> Option<(&str, &Location)> {
        self.list
            .iter()
            .find(|(k, _, _)| k == name)
            .map(|(_, v, l)| (v.as_str(), l))
    }
    fn has(&self, name: &str) -> bool {
        self.get(name).is_some()
    }
    fn required(&self, name: &str, tag: &str) -> Result<(&str, &Location), SceneError> {
        self.get(name).ok_or_else(|| {
            SceneError::new(
                self.elem.clone(),
                ErrorKind::Grammar,
                format!("<{tag}> needs a \"{name}\" attribute"),
            )
        })
    }
}

/// The parser: parameters, the arena under construction, and the include stack.
pub(crate) struct Parser {
    /// `-D` definitions (name, value, used).
    cli: Vec<(String, String, bool)>,
    /// `<default>` definitions.
    defaults: HashMap<String, String>,
    pub doc: Doc,
    include_stack: Vec<PathBuf>,
}

const OBJECT_ATTRS: &[&str] = &["type", "id", "name"];

impl Parser {
    pub(crate) fn new(defines: &[(String, String)]) -> Self {
        Self {
            cli: defines
                .iter()
                .map(|(k, v)| (k.clone(), v.clone(), false))
                .collect(),
            defaults: HashMap::new(),
            doc: Doc::default(),
            include_stack: Vec::new(),
        }
    }

    /// Fails if a `-D` parameter was never used (Mitsuba reports these).
    pub(crate) fn check_defines_used(&self, file: &Arc<str>) -> Result<(), SceneError> {
        if let Some((k, v, _)) = self.cli.iter().find(|(_, _, used)| !used) {
            return Err(SceneError::new(
                Location::file_only(file.clone()),
                ErrorKind::Undefined,
                format!("parameter \"{k}={v}\" given on the command line is not used by the scene"),
            ));
        }
        Ok(())
    }

    /// Parses a whole scene file (root `<scene>`).
    pub(crate) fn parse_scene_text(
        &mut self,
        text: &str,
        name: Arc<str>,
        dir: PathBuf,
        canonical: Option<PathBuf>,
    ) -> Result<(), SceneError> {
        let xml = parse_xml(text, &name)?;
        let root_node = xml.root_element();
        let mut ctx = FileCtx {
            doc: &xml,
            name,
            dir,
            legacy: false,
        };
        if root_node.tag_name().name() != "scene" {
            return Err(SceneError::new(
                ctx.loc(root_node),
                ErrorKind::Grammar,
                format!(
                    "the root element must be <scene>, found <{}>",
                    root_node.tag_name().name()
                ),
            ));
        }
        let attrs = self.attrs(&ctx, root_node, &["version"])?;
        let (version, vloc) = attrs.required("version", "scene")?;
        ctx.legacy = parse_version(version, vloc)? < (2, 0, 0);
        let root = self.push_obj(Obj {
            tag: Tag::Scene,
            ty: "scene".into(),
            id: None,
            loc: ctx.loc(root_node),
            ty_loc: ctx.loc(root_node),
            props: Vec::new(),
            base_dir: ctx.dir.clone(),
        });
        self.doc.root = root;
        if let Some(c) = canonical {
            self.include_stack.push(c);
        }
        self.children(&ctx, root_node, root)?;
        Ok(())
    }

    /// Parses a lone `<bsdf>` document (for `gonio bsdf`); `version` is allowed on it.
    pub(crate) fn parse_bsdf_text(
        &mut self,
        text: &str,
        name: Arc<str>,
        dir: PathBuf,
    ) -> Result<(), SceneError> {
        let xml = parse_xml(text, &name)?;
        let node = xml.root_element();
        let mut ctx = FileCtx {
            doc: &xml,
            name,
            dir,
            legacy: false,
        };
        if node.tag_name().name() != "bsdf" {
            return Err(SceneError::new(
                ctx.loc(node),
                ErrorKind::Grammar,
                format!("expected a <bsdf> element, found <{}>", node.tag_name().name()),
            ));
        }
        let attrs = self.attrs(&ctx, node, &["type", "id", "name", "version"])?;
        if let Some((v, l)) = attrs.get("version") {
            ctx.legacy = parse_version(v, l)? < (2, 0, 0);
        }
        let idx = self.object(&ctx, node, Tag::Bsdf, attrs)?;
        self.doc.root = idx;
        Ok(())
    }

    fn push_obj(&mut self, o: Obj) -> usize {
        self.doc.objs.push(o);
        self.doc.objs.len() - 1
    }

    /// Reads the attributes of `node`, rejecting any not in `allowed`, substituting `$name`.
    fn attrs(&mut self, ctx: &FileCtx, node: roxmltree::Node, allowed: &[&str]) -> Result<Attrs, SceneError> {
        let elem = ctx.loc(node);
        let mut list = Vec::new();
        for a in node.attributes() {
            let loc = ctx.loc_at(a.range_value().start);
            if !allowed.contains(&a.name()) {
                return Err(SceneError::new(
                    ctx.loc_at(a.range().start),
                    ErrorKind::Grammar,
                    format!(
                        "unexpected attribute \"{}\" on <{}> (allowed: {})",
                        a.name(),
                        node.tag_name().name(),
                        allowed.join(", ")
                    ),
                ));
            }
            let v = self.substitute(a.value(), &loc)?;
            list.push((a.name().to_owned(), v, loc));
        }
        Ok(Attrs { list, elem })
    }

    /// Replaces each `$name` by its value, matching the longest defined name first.
    fn substitute(&mut self, s: &str, loc: &Location) -> Result<String, SceneError> {
        if !s.contains('$') {
            return Ok(s.to_owned());
        }
        let mut out = String::with_capacity(s.len());
        let mut rest = s;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            // Longest matching name among -D and <default> parameters.
            let mut best: Option<(usize, String, Option<usize>)> = None;
            for (ci, (k, v, _)) in self.cli.iter().enumerate() {
                if after.starts_with(k.as_str()) && best.as_ref().is_none_or(|b| k.len() > b.0) {
                    best = Some((k.len(), v.clone(), Some(ci)));
                }
            }
            for (k, v) in &self.defaults {
                if after.starts_with(k.as_str())
                    && best.as_ref().is_none_or(|b| k.len() > b.0)
                    && !self.cli.iter().any(|(c, _, _)| c == k)
                {
                    best = Some((k.len(), v.clone(), None));
                }
            }
            match best {
                Some((len, v, ci)) => {
                    if let Some(ci) = ci {
                        self.cli[ci].2 = true;
                    }
                    out.push_str(&v);
                    rest = &after[len..];
                }
                None => {
                    let ident: String = after
                        .chars()
                        .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                        .collect();
                    return Err(SceneError::new(
                        loc.clone(),
                        ErrorKind::Undefined,
                        format!(
                            "undefined parameter \"${ident}\" in \"{s}\" (define it with <default name=\"{ident}\" value=\"…\"/> or -D {ident}=…)"
                        ),
                    ));
                }
            }
        }
        out.push_str(rest);
        Ok(out)
    }

    fn children(&mut self, ctx: &FileCtx, node: roxmltree::Node, parent: usize) -> Result<(), SceneError> {
        for child in node.children() {
            if child.is_element() {
                self.element(ctx, child, parent)?;
            } else if child.is_text() {
                let t = child.text().unwrap_or("");
                if !t.trim().is_empty() {
                    return Err(SceneError::new(
                        ctx.loc(child),
                        ErrorKind::Grammar,
                        format!("unexpected text \"{}\"", t.trim()),
                    ));
                }
            }
        }
        Ok(())
    }

    fn add_prop(&mut self, parent: usize, prop: Prop) -> Result<(), SceneError> {
        let props = &self.doc.objs[parent].props;
        if let Some(prev) = props.iter().find(|p| p.name == prop.name) {
            return Err(SceneError::new(
                prop.loc.clone(),
                ErrorKind::Grammar,
                format!("property \"{}\" was already specified at {}", prop.name, prev.loc),
            ));
        }
        self.doc.objs[parent].props.push(prop);
        Ok(())
    }

    fn positional_name(&self, parent: usize) -> String {
        let n = self.doc.objs[parent]
            .props
            .iter()
            .filter(|p| p.name.starts_with("_arg_"))
            .count();
        format!("_arg_{n}")
    }

    fn prop_name(&self, ctx: &FileCtx, raw: &str) -> String {
        if ctx.legacy {
            camel_to_snake(raw)
        } else {
            raw.to_owned()
        }
    }

    fn element(&mut self, ctx: &FileCtx, node: roxmltree::Node, parent: usize) -> Result<(), SceneError> {
        let tag = node.tag_name().name();
        let loc = ctx.loc(node);
        let is_root = parent == self.doc.root && self.doc.objs[parent].tag == Tag::Scene;
        // Objects.
        let obj_tag = Tag::from_name(tag)
            .or_else(|| (tag == "spectrum" && node.has_attribute("type")).then_some(Tag::Spectrum));
        if let Some(t) = obj_tag {
            let attrs = self.attrs(ctx, node, OBJECT_ATTRS)?;
            let name = attrs.get("name").map(|(n, _)| self.prop_name(ctx, n));
            let idx = self.object(ctx, node, t, attrs)?;
            let name = name.unwrap_or_else(|| self.positional_name(parent));
            let name = self.legacy_rename(ctx, parent, name);
            return self.add_prop(
                parent,
                Prop {
                    name,
                    value: Value::Object(idx),
                    loc: loc.clone(),
                    value_loc: loc,
                },
            );
        }
        match tag {
            "scene" => Err(SceneError::new(loc, ErrorKind::Grammar, "nested <scene> element")),
            "medium" | "phase" | "volume" => Err(SceneError::new(
                loc,
                ErrorKind::UnknownPlugin,
                format!("<{tag}> (participating media) is not supported"),
            )),
            "ref" => {
                let attrs = self.attrs(ctx, node, &["id", "name"])?;
                let (id, _) = attrs.required("id", "ref")?;
                let id = id.to_owned();
                let name = match attrs.get("name") {
                    Some((n, _)) => self.prop_name(ctx, n),
                    None => self.positional_name(parent),
                };
                let name = self.legacy_rename(ctx, parent, name);
                let vloc = attrs.get("id").map(|(_, l)| l.clone()).unwrap_or(loc.clone());
                self.add_prop(
                    parent,
                    Prop {
                        name,
                        value: Value::Ref(id),
                        loc,
                        value_loc: vloc,
                    },
                )
            }
            "default" => {
                let attrs = self.attrs(ctx, node, &["name", "value"])?;
                let (n, nloc) = attrs.required("name", "default")?;
                let (v, _) = attrs.required("value", "default")?;
                if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    return Err(SceneError::new(
                        nloc.clone(),
                        ErrorKind::BadValue,
                        format!("invalid parameter name \"{n}\""),
                    ));
                }
                self.defaults.insert(n.to_owned(), v.to_owned());
                Ok(())
            }
            "include" => {
                if !is_root {
                    return Err(SceneError::new(
                        loc,
                        ErrorKind::Grammar,
                        "<include> must be a child of <scene>",
                    ));
                }
                let attrs = self.attrs(ctx, node, &["filename"])?;
                let (f, floc) = attrs.required("filename", "include")?;
                let path = resolve_path(&ctx.dir, &self.doc.search_paths, f);
                self.include(&path, f, floc, parent)
            }
            "alias" => {
                let attrs = self.attrs(ctx, node, &["id", "as"])?;
                let (id, idloc) = attrs.required("id", "alias")?;
                let (alias, aloc) = attrs.required("as", "alias")?;
                let Some(&target) = self.doc.ids.get(id) else {
                    return Err(SceneError::new(
                        idloc.clone(),
                        ErrorKind::Reference,
                        format!("<alias> refers to unknown id \"{id}\""),
                    ));
                };
                if self.doc.ids.contains_key(alias) {
                    return Err(SceneError::new(
                        aloc.clone(),
                        ErrorKind::Reference,
                        format!("id \"{alias}\" is already defined"),
                    ));
                }
                self.doc.ids.insert(alias.to_owned(), target);
                Ok(())
            }
            "path" => {
                if !is_root {
                    return Err(SceneError::new(
                        loc,
                        ErrorKind::Grammar,
                        "<path> must be a child of <scene>",
                    ));
                }
                let attrs = self.attrs(ctx, node, &["value"])?;
                let (v, _) = attrs.required("value", "path")?;
                let p = ctx.dir.join(v);
                self.doc.search_paths.push(p);
                Ok(())
            }
            "integer" | "float" | "boolean" | "string" | "point" | "vector" | "rgb" | "spectrum"
            | "transform" => {
                let prop = self.property(ctx, node, tag)?;
                let prop = Prop {
                    name: self.legacy_rename(ctx, parent, prop.name.clone()),
                    ..prop
                };
                self.add_prop(parent, prop)
            }
            _ => Err(SceneError::new(
                loc,
                ErrorKind::Grammar,
                format!("unknown element <{tag}>"),
            )),
        }
    }

    /// Version < 2: `diffuse.diffuse_reflectance` → `reflectance`.
    fn legacy_rename(&self, ctx: &FileCtx, parent: usize, name: String) -> String {
        let p = &self.doc.objs[parent];
        if ctx.legacy && p.tag == Tag::Bsdf && p.ty == "diffuse" && name == "diffuse_reflectance" {
            "reflectance".into()
        } else {
            name
        }
    }

    fn object(
        &mut self,
        ctx: &FileCtx,
        node: roxmltree::Node,
        tag: Tag,
        attrs: Attrs,
    ) -> Result<usize, SceneError> {
        let loc = ctx.loc(node);
        let (ty, ty_loc) = attrs.required("type", tag.name())?;
        let ty = ty.to_owned();
        let ty_loc = ty_loc.clone();
        let id = attrs.get("id").map(|(v, l)| (v.to_owned(), l.clone()));
        let idx = self.push_obj(Obj {
            tag,
            ty,
            id: id.as_ref().map(|(v, _)| v.clone()),
            loc,
            ty_loc,
            props: Vec::new(),
            base_dir: ctx.dir.clone(),
        });
        if let Some((id, idloc)) = id {
            if let Some(&prev) = self.doc.ids.get(&id) {
                return Err(SceneError::new(
                    idloc,
                    ErrorKind::Reference,
                    format!("id \"{id}\" is already defined at {}", self.doc.objs[prev].loc),
                ));
            }
            self.doc.ids.insert(id, idx);
        }
        self.children(ctx, node, idx)?;
        if ctx.legacy && tag == Tag::Texture {
            legacy_uv_transform(&mut self.doc.objs[idx])?;
        }
        Ok(idx)
    }

    fn include(
        &mut self,
        path: &Path,
        written: &str,
        loc: &Location,
        parent: usize,
    ) -> Result<(), SceneError> {
        let canonical = path.canonicalize().map_err(|e| {
            SceneError::new(
                loc.clone(),
                ErrorKind::Io,
                format!(
                    "cannot read included file \"{written}\" ({}): {e}",
                    path.display()
                ),
            )
        })?;
        if self.include_stack.contains(&canonical) {
            return Err(SceneError::new(
                loc.clone(),
                ErrorKind::Cycle,
                format!("cyclic include of \"{written}\" ({})", canonical.display()),
            ));
        }
        let text = std::fs::read_to_string(path).map_err(|e| {
            SceneError::new(
                loc.clone(),
                ErrorKind::Io,
                format!(
                    "cannot read included file \"{written}\" ({}): {e}",
                    path.display()
                ),
            )
        })?;
        let name: Arc<str> = path.display().to_string().into();
        let xml = parse_xml(&text, &name)?;
        let dir = path.parent().map(Path::to_owned).unwrap_or_default();
        let mut ctx = FileCtx {
            doc: &xml,
            name,
            dir,
            legacy: false,
        };
        let root = xml.root_element();
        if root.tag_name().name() != "scene" {
            return Err(SceneError::new(
                ctx.loc(root),
                ErrorKind::Grammar,
                format!(
                    "an included file must have a <scene> root, found <{}>",
                    root.tag_name().name()
                ),
            ));
        }
        let attrs = self.attrs(&ctx, root, &["version"])?;
        let (version, vloc) = attrs.required("version", "scene")?;
        ctx.legacy = parse_version(version, vloc)? < (2, 0, 0);
        self.include_stack.push(canonical);
        self.children(&ctx, root, parent)?;
        self.include_stack.pop();
        Ok(())
    }

    fn property(&mut self, ctx: &FileCtx, node: roxmltree::Node, tag: &str) -> Result<Prop, SceneError> {
        let loc = ctx.loc(node);
        let allowed: &[&str] = match tag {
            "point" | "vector" => &["name", "value", "x", "y", "z"],
            "spectrum" => &["name", "value", "filename"],
            "transform" => &["name"],
            _ => &["name", "value"],
        };
        let attrs = self.attrs(ctx, node, allowed)?;
        let (raw_name, _) = attrs.required("name", tag)?;
        let name = self.prop_name(ctx, raw_name);
        if tag != "transform" {
            if let Some(c) = node.children().find(|c| c.is_element()) {
                return Err(SceneError::new(
                    ctx.loc(c),
                    ErrorKind::Grammar,
                    format!("<{tag}> cannot contain <{}>", c.tag_name().name()),
                ));
            }
        }
        let (value, value_loc) = match tag {
            "integer" => {
                let (v, l) = attrs.required("value", tag)?;
                (Value::Int(values::parse_int(v, l)?), l.clone())
            }
            "float" => {
                let (v, l) = attrs.required("value", tag)?;
                (Value::Float(values::parse_float(v, l)?), l.clone())
            }
            "boolean" => {
                let (v, l) = attrs.required("value", tag)?;
                let b = match v.trim().to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => {
                        return Err(SceneError::new(
                            l.clone(),
                            ErrorKind::BadValue,
                            format!("invalid boolean \"{v}\" (expected true or false)"),
                        ));
                    }
                };
                (Value::Bool(b), l.clone())
            }
            "string" => {
                let (v, l) = attrs.required("value", tag)?;
                (Value::Str(v.to_owned()), l.clone())
            }
            "point" | "vector" => {
                let (p, l) = xyz_or_value(&attrs, tag, 0.0)?;
                (
                    if tag == "point" {
                        Value::Point(p)
                    } else {
                        Value::Vector(p)
                    },
                    l,
                )
            }
            "rgb" => {
                let (v, l) = attrs.required("value", tag)?;
                let n = values::parse_list(v, l)?;
                let c = match n.as_slice() {
                    [x] => [*x; 3],
                    [r, g, b] => [*r, *g, *b],
                    _ => {
                        return Err(SceneError::new(
                            l.clone(),
                            ErrorKind::BadValue,
                            format!("<rgb> needs 1 or 3 numbers, found \"{v}\""),
                        ));
                    }
                };
                (Value::Rgb(c), l.clone())
            }
            "spectrum" => match (attrs.get("value"), attrs.get("filename")) {
                (Some((v, l)), None) => (Value::Spectrum(values::parse_spectrum_value(v, l)?), l.clone()),
                (None, Some((f, l))) => {
                    let path = resolve_path(&ctx.dir, &self.doc.search_paths, f);
                    (Value::Spectrum(values::read_spd(&path, f, l)?), l.clone())
                }
                _ => {
                    return Err(SceneError::new(
                        loc,
                        ErrorKind::Grammar,
                        "<spectrum> needs exactly one of \"value\" and \"filename\"",
                    ));
                }
            },
            "transform" => (Value::Transform(self.transform(ctx, node)?), loc.clone()),
            _ => unreachable!("property tags are matched by the caller"),
        };
        Ok(Prop {
            name,
            value,
            loc,
            value_loc,
        })
    }

    /// `<transform>`: each operation left-multiplies, so operations apply in document order.
    fn transform(&mut self, ctx: &FileCtx, node: roxmltree::Node) -> Result<DMat4, SceneError> {
        let mut m = DMat4::IDENTITY;
        for c in node.children() {
            if c.is_text() {
                if c.text().is_some_and(|t| !t.trim().is_empty()) {
                    return Err(SceneError::new(
                        ctx.loc(c),
                        ErrorKind::Grammar,
                        "unexpected text in <transform>",
                    ));
                }
                continue;
            }
            if !c.is_element() {
                continue;
            }
            let tag = c.tag_name().name();
            let op = match tag {
                "translate" => {
                    let attrs = self.attrs(ctx, c, &["value", "x", "y", "z"])?;
                    let (t, _) = xyz_or_value(&attrs, tag, 0.0)?;
                    DMat4::from_translation(t)
                }
                "scale" => {
                    let attrs = self.attrs(ctx, c, &["value", "x", "y", "z"])?;
                    let (s, _) = xyz_or_value(&attrs, tag, 1.0)?;
                    DMat4::from_scale(s)
                }
                "rotate" => {
                    let attrs = self.attrs(ctx, c, &["value", "x", "y", "z", "angle"])?;
                    let (axis, aloc) = xyz_or_value(&attrs, tag, 0.0)?;
                    let (a, l) = attrs.required("angle", tag)?;
                    let angle = values::parse_float(a, l)?;
                    if axis.length_squared() == 0.0 {
                        return Err(SceneError::new(
                            aloc,
                            ErrorKind::BadValue,
                            "<rotate> axis is zero (give value=\"x, y, z\" or x/y/z attributes)",
                        ));
                    }
                    DMat4::from_axis_angle(axis.normalize(), angle.to_radians())
                }
                "matrix" => {
                    let attrs = self.attrs(ctx, c, &["value"])?;
                    let (v, l) = attrs.required("value", tag)?;
                    let n = values::parse_list(v, l)?;
                    match n.len() {
                        16 => DMat4::from_cols_array(&[
                            n[0], n[4], n[8], n[12], n[1], n[5], n[9], n[13], n[2], n[6], n[10], n[14], n[3],
                            n[7], n[11], n[15],
                        ]),
                        9 => DMat4::from_cols_array(&[
                            n[0], n[3], n[6], 0.0, n[1], n[4], n[7], 0.0, n[2], n[5], n[8], 0.0, 0.0, 0.0,
                            0.0, 1.0,
                        ]),
                        k => {
                            return Err(SceneError::new(
                                l.clone(),
                                ErrorKind::BadValue,
                                format!("<matrix> needs 16 (or 9) numbers, found {k} in \"{v}\""),
                            ));
                        }
                    }
                }
                "lookat" => {
                    let attrs = self.attrs(ctx, c, &["origin", "target", "up"])?;
                    let (o, ol) = attrs.required("origin", tag)?;
                    let origin = values::parse_vec3(o, ol)?;
                    let (t, tl) = attrs.required("target", tag)?;
                    let target = values::parse_vec3(t, tl)?;
                    let up = match attrs.get("up") {
                        Some((u, ul)) => Some((values::parse_vec3(u, ul)?, ul.clone())),
                        None => None,
                    };
                    values::look_at(origin, target, up.as_ref().map(|(u, _)| *u)).map_err(|msg| {
                        let l = match &up {
                            Some((_, ul)) if msg.contains("up") => ul.clone(),
                            _ => tl.clone(),
                        };
                        SceneError::new(l, ErrorKind::BadValue, msg)
                    })?
                }
                _ => {
                    return Err(SceneError::new(
                        ctx.loc(c),
                        ErrorKind::Grammar,
                        format!(
                            "unknown transform operation <{tag}> (expected translate, rotate, scale, matrix, lookat)"
                        ),
                    ));
                }
            };
            if let Some(x) = c.children().find(|x| x.is_element()) {
                return Err(SceneError::new(
                    ctx.loc(x),
                    ErrorKind::Grammar,
                    format!("<{tag}> cannot contain <{}>", x.tag_name().name()),
                ));
            }
            m = op * m;
        }
        Ok(m)
    }
}

fn parse_xml<'i>(text: &'i str, name: &Arc<str>) -> Result<roxmltree::Document<'i>, SceneError> {
    roxmltree::Document::parse(text).map_err(|e| {
        let p = e.pos();
        SceneError::new(
            Location {
                file: name.clone(),
                line: p.row,
                column: p.col,
            },
            ErrorKind::Syntax,
            format!("malformed XML: {e}"),
        )
    })
}

fn parse_version(v: &str, loc: &Location) -> Result<(u32, u32, u32), SceneError> {
    let parts: Vec<&str> = v.trim().split('.').collect();
    let bad = || {
        SceneError::new(
            loc.clone(),
            ErrorKind::BadValue,
            format!("invalid version \"{v}\" (expected major.minor.patch, e.g. 3.0.0)"),
        )
    };
    if parts.is_empty() || parts.len() > 3 {
        return Err(bad());
    }
    let mut n = [0u32; 3];
    for (i, p) in parts.iter().enumerate() {
        n[i] = p.parse().map_err(|_| bad())?;
    }
    Ok((n[0], n[1], n[2]))
}

/// `value="x, y, z"` (1 number is replicated) or x/y/z attributes (missing ones = `missing`).
fn xyz_or_value(attrs: &Attrs, tag: &str, missing: f64) -> Result<(DVec3, Location), SceneError> {
    let has_xyz = attrs.has("x") || attrs.has("y") || attrs.has("z");
    match attrs.get("value") {
        Some((v, l)) => {
            if has_xyz {
                return Err(SceneError::new(
                    l.clone(),
                    ErrorKind::Grammar,
                    format!("<{tag}> has both \"value\" and x/y/z attributes"),
                ));
            }
            Ok((values::parse_vec3(v, l)?, l.clone()))
        }
        None => {
            if !has_xyz && tag != "translate" && tag != "scale" && tag != "rotate" {
                return Err(SceneError::new(
                    attrs.elem.clone(),
                    ErrorKind::Grammar,
                    format!("<{tag}> needs \"value\" or x/y/z attributes"),
                ));
            }
            let mut p = [missing; 3];
            for (i, k) in ["x", "y", "z"].iter().enumerate() {
                if let Some((v, l)) = attrs.get(k) {
                    p[i] = values::parse_float(v, l)?;
                }
            }
            Ok((DVec3::from_array(p), attrs.elem.clone()))
        }
    }
}

/// camelCase → snake_case (version < 2 scenes): `maxDepth` → `max_depth`, `toWorld` → `to_world`.
pub(crate) fn camel_to_snake(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 4);
    for (i, c) in s.chars().enumerate() {
        if c.is_ascii_uppercase() {
            if i > 0 {
                out.push('_');
            }
            out.push(c.to_ascii_lowercase());
        } else {
            out.push(c);
        }
    }
    out
}

/// Version < 2 textures: `uoffset`, `voffset`, `uscale`, `vscale` become a `to_uv` transform
/// (scale, then translate).
fn legacy_uv_transform(obj: &mut Obj) -> Result<(), SceneError> {
    let keys = ["uoffset", "voffset", "uscale", "vscale"];
    if !obj.props.iter().any(|p| keys.contains(&p.name.as_str())) {
        return Ok(());
    }
    let mut v = [0.0, 0.0, 1.0, 1.0];
    let mut loc = obj.loc.clone();
    for (i, k) in keys.iter().enumerate() {
        if let Some(pos) = obj.props.iter().position(|p| p.name == *k) {
            let p = obj.props.remove(pos);
            loc = p.loc.clone();
            v[i] = match p.value {
                Value::Float(f) => f,
                Value::Int(n) => n as f64,
                _ => {
                    return Err(SceneError::new(
                        p.value_loc,
                        ErrorKind::WrongType,
                        format!("\"{k}\" must be a float"),
                    ));
                }
            };
        }
    }
    if obj.props.iter().any(|p| p.name == "to_uv") {
        return Err(SceneError::new(
            loc,
            ErrorKind::Grammar,
            "both to_uv and uoffset/voffset/uscale/vscale given",
        ));
    }
    let m =
        DMat4::from_translation(DVec3::new(v[0], v[1], 0.0)) * DMat4::from_scale(DVec3::new(v[2], v[3], 1.0));
    obj.props.push(Prop {
        name: "to_uv".into(),
        value: Value::Transform(m),
        loc: loc.clone(),
        value_loc: loc,
    });
    Ok(())
}
