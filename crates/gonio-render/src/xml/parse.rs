//! XML → object tree: the grammar of Mitsuba 3 scene files (Mitsuba 3
//! `docs/src/key_topics/scene_format.rst`, `src/core/parser.cpp`).
//!
//! The parser reads the XML with `roxmltree`, substitutes `$name` parameters in every attribute
//! value, expands `<include>`, parses property values and transforms, and produces an arena of
//! [`Obj`]s, each with its properties in document order. Plugin instantiation (which parameters a
//! plugin takes, defaults, the unused-parameter check) happens afterwards in `plugins.rs`, so
//! forward references work.

use super::doc::resolve_path;
pub(crate) use super::doc::{Doc, Obj, Prop, Tag, Value};
use super::error::{ErrorKind, Location, SceneError};
use glam::{DMat4, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// One XML file being parsed.
pub(super) struct FileCtx<'a, 'i> {
    pub(super) doc: &'a roxmltree::Document<'i>,
    pub(super) name: Arc<str>,
    pub(super) dir: PathBuf,
    pub(super) legacy: bool,
}

impl FileCtx<'_, '_> {
    pub(super) fn loc_at(&self, pos: usize) -> Location {
        let p = self.doc.text_pos_at(pos);
        Location {
            file: self.name.clone(),
            line: p.row,
            column: p.col,
        }
    }
    pub(super) fn loc(&self, node: roxmltree::Node) -> Location {
        self.loc_at(node.range().start)
    }
}

/// Attribute values of one element after `$` substitution, with their positions.
pub(super) struct Attrs {
    pub(super) list: Vec<(String, String, Location)>,
    pub(super) elem: Location,
}

impl Attrs {
    pub(super) fn get(&self, name: &str) -> Option<(&str, &Location)> {
        self.list
            .iter()
            .find(|(k, _, _)| k == name)
            .map(|(_, v, l)| (v.as_str(), l))
    }
    pub(super) fn has(&self, name: &str) -> bool {
        self.get(name).is_some()
    }
    pub(super) fn required(&self, name: &str, tag: &str) -> Result<(&str, &Location), SceneError> {
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
        self.doc.scene_dir = Some(dir.clone());
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

    pub(super) fn push_obj(&mut self, o: Obj) -> usize {
        self.doc.objs.push(o);
        self.doc.objs.len() - 1
    }

    /// Reads the attributes of `node`, rejecting any not in `allowed`, substituting `$name`.
    pub(super) fn attrs(
        &mut self,
        ctx: &FileCtx,
        node: roxmltree::Node,
        allowed: &[&str],
    ) -> Result<Attrs, SceneError> {
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
    pub(super) fn substitute(&mut self, s: &str, loc: &Location) -> Result<String, SceneError> {
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

    pub(super) fn children(
        &mut self,
        ctx: &FileCtx,
        node: roxmltree::Node,
        parent: usize,
    ) -> Result<(), SceneError> {
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

    pub(super) fn add_prop(&mut self, parent: usize, prop: Prop) -> Result<(), SceneError> {
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

    pub(super) fn positional_name(&self, parent: usize) -> String {
        let n = self.doc.objs[parent]
            .props
            .iter()
            .filter(|p| p.name.starts_with("_arg_"))
            .count();
        format!("_arg_{n}")
    }

    pub(super) fn prop_name(&self, ctx: &FileCtx, raw: &str) -> String {
        if ctx.legacy {
            camel_to_snake(raw)
        } else {
            raw.to_owned()
        }
    }

    pub(super) fn element(
        &mut self,
        ctx: &FileCtx,
        node: roxmltree::Node,
        parent: usize,
    ) -> Result<(), SceneError> {
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
                // The first definition wins, as in Mitsuba: a scene's defaults hold over those of
                // the files it includes (Mitsuba's `medium_homogeneous_sss` sets `volpath` before
                // including a set-up whose default is `path`).
                self.defaults.entry(n.to_owned()).or_insert_with(|| v.to_owned());
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
            "animation" => Err(SceneError::new(
                loc,
                ErrorKind::Grammar,
                "<animation> (Mitsuba's animated transforms, for motion blur) is not supported: gonio renders one instant; give a <transform> instead",
            )),
            _ => Err(SceneError::new(
                loc,
                ErrorKind::Grammar,
                format!("unknown element <{tag}>"),
            )),
        }
    }

    /// Version < 2: `diffuse.diffuse_reflectance` → `reflectance`.
    pub(super) fn legacy_rename(&self, ctx: &FileCtx, parent: usize, name: String) -> String {
        let p = &self.doc.objs[parent];
        if ctx.legacy && p.tag == Tag::Bsdf && p.ty == "diffuse" && name == "diffuse_reflectance" {
            "reflectance".into()
        } else {
            name
        }
    }

    pub(super) fn object(
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

    pub(super) fn include(
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
}

/// The deepest element nesting a scene file may have. The reader walks the element tree
/// recursively; Mitsuba's own scenes nest fewer than 10 levels, and this bound keeps a hostile
/// file from overflowing the stack (checked before any recursion, in one iterative pass).
pub(crate) const MAX_XML_DEPTH: usize = 128;

fn parse_xml<'i>(text: &'i str, name: &Arc<str>) -> Result<roxmltree::Document<'i>, SceneError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| {
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
    })?;
    // Element depth of every node, in document order (a parent comes before its children).
    let mut depth = vec![0u32; doc.descendants().count()];
    for n in doc.descendants().filter(|n| n.is_element()) {
        let d = n.parent().map_or(0, |p| depth[p.id().get() as usize]) + 1;
        depth[n.id().get() as usize] = d;
        if d as usize > MAX_XML_DEPTH {
            let p = doc.text_pos_at(n.range().start);
            return Err(SceneError::new(
                Location {
                    file: name.clone(),
                    line: p.row,
                    column: p.col,
                },
                ErrorKind::Grammar,
                format!(
                    "<{}> is nested {d} elements deep; a scene file may nest at most {MAX_XML_DEPTH}",
                    n.tag_name().name()
                ),
            ));
        }
    }
    Ok(doc)
}

/// The newest scene format gonio reads: Mitsuba 3's.
const NEWEST_SCENE_MAJOR: u32 = 3;

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
    // Scenes of Mitsuba 0.x–2.x load (0.x names are translated); a major version past 3 names
    // a format gonio cannot know (Mitsuba 3.9.1 loads it silently and may misread it).
    if n[0] > NEWEST_SCENE_MAJOR {
        return Err(SceneError::new(
            loc.clone(),
            ErrorKind::BadValue,
            format!(
                "scene version \"{v}\" is newer than gonio understands (Mitsuba {NEWEST_SCENE_MAJOR}.x scenes and older)"
            ),
        ));
    }
    Ok((n[0], n[1], n[2]))
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
