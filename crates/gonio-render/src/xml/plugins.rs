//! Plugin instantiation: object tree → [`Scene`]. The plugins themselves (parameter tables and
//! builders) are in [`crate::plugins`] and [`crate::material`]; this is what they share: scene
//! assembly, the caches (BSDFs, textures, meshes, materials), cycle detection, reference
//! resolution, dispatch through the registries and the typed readers of spectra, textures and
//! indices of refraction. Any parameter a plugin does not read is an error ("unused parameter"),
//! as in Mitsuba.

use super::error::{ErrorKind, Location, SceneError};
use super::params::{ParamSpec, Params, Plugin, err, resolve_ref};
use super::parse::{Doc, Obj, Tag, Value};
use super::values::SpecValue;
use crate::material::Material;
use crate::plugins::{INTEGRATOR_PLUGINS, SENSOR_PLUGINS, SPECTRUM_PLUGINS, TEXTURE_PLUGINS};
use crate::scene::{IntegratorDesc, IntegratorKind, Scene, SensorDesc, TriangleMesh};
use crate::texture::Texture;
use gonio_core::Ior;
use gonio_core::bsdfs::surface::MAX_NODES;
use gonio_core::named;
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, RgbKind, Spectrum};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

type Result<T> = std::result::Result<T, SceneError>;

/// A texture that reads the hit, as the builder logs it: the attribute's name (`None` for a
/// `volume`) and where the scene names it.
pub(crate) type HitUse = (Option<String>, Location);

/// The builder: caches so that a referenced BSDF, texture or mesh is built once.
pub(crate) struct Builder<'d> {
    pub(crate) doc: &'d Doc,
    materials: Vec<Material>,
    material_index: HashMap<usize, usize>,
    default_material: [Option<usize>; 2],
    bsdfs: HashMap<usize, Material>,
    textures: HashMap<(usize, u8), Texture>,
    /// Meshes by (file, mesh within the file, `flip_tex_coords`, `face_normals`).
    meshes: HashMap<(PathBuf, u32, bool, bool), Arc<TriangleMesh>>,
    visiting: Vec<usize>,
    role: RgbKind,
    /// Area emitters already attached to a shape, with where (Mitsuba attaches one emitter to
    /// one shape only).
    pub(crate) attached_emitters: HashMap<usize, Location>,
    pub warnings: Vec<String>,
    /// Shape groups by object, built once however many instances place them.
    pub(crate) groups: HashMap<usize, Arc<crate::geometry::instance::ShapeGroup>>,
    /// The textures that read the hit (`mesh_attribute`: the attribute's name; `volume`: `None`)
    /// met so far, in order; with the slices of it each cached texture and BSDF object added, so
    /// that a reuse adds them again (a shape's material is bound to its mesh by them).
    pub(crate) hit_log: Vec<HitUse>,
    hit_textures: HashMap<(usize, u8), Vec<HitUse>>,
    pub(crate) hit_bsdfs: HashMap<usize, Vec<HitUse>>,
    /// The attributes of the PLY meshes loaded (by the address of their cached mesh).
    pub(crate) mesh_attributes: HashMap<usize, crate::mesh::attributes::MeshAttributes>,
    /// Where each area emitter whose radiance reads the hit has its first such texture.
    pub(crate) hit_emitters: Vec<Location>,
    /// True while the sensor nested in a shape is built (`irradiancemeter` must be).
    pub(crate) in_shape: bool,
    /// The sensor nested in the shape just built, and where it is: the scene takes it when it
    /// places the shape (`shape::instance::place`).
    pub(crate) shape_sensor: Option<(SensorDesc, Location)>,
    /// Sensors nested in shapes placed in the scene, in document order.
    pub(crate) shape_sensors: Vec<(SensorDesc, Location)>,
    /// While the sensors of a `batch` are built: the film share and the sampler they take.
    pub(crate) batch_film: Option<(crate::scene::FilmDesc, crate::scene::SamplerDesc)>,
    /// The participating media built so far, and each one's object (built once however many
    /// shapes refer to it).
    media: Vec<crate::medium::Medium>,
    medium_index: HashMap<usize, crate::medium::MediumId>,
    /// The medium nested in the sensor built last.
    pub(crate) sensor_medium: Option<crate::medium::MediumId>,
}

fn kind_key(k: RgbKind) -> u8 {
    match k {
        RgbKind::Albedo => 0,
        RgbKind::Unbounded => 1,
        RgbKind::Illuminant => 2,
    }
}

pub(crate) fn unknown_plugin(obj: &Obj, supported: &[&str]) -> SceneError {
    err(
        &obj.ty_loc,
        ErrorKind::UnknownPlugin,
        format!(
            "unknown {} plugin \"{}\" (supported: {})",
            obj.tag.name(),
            obj.ty,
            supported.join(", ")
        ),
    )
}

impl<'d> Builder<'d> {
    pub(crate) fn new(doc: &'d Doc) -> Self {
        Self {
            doc,
            materials: Vec::new(),
            material_index: HashMap::new(),
            default_material: [None, None],
            bsdfs: HashMap::new(),
            textures: HashMap::new(),
            meshes: HashMap::new(),
            visiting: Vec::new(),
            role: RgbKind::Unbounded,
            attached_emitters: HashMap::new(),
            warnings: Vec::new(),
            groups: HashMap::new(),
            hit_log: Vec::new(),
            in_shape: false,
            shape_sensor: None,
            shape_sensors: Vec::new(),
            batch_film: None,
            media: Vec::new(),
            medium_index: HashMap::new(),
            sensor_medium: None,
            hit_textures: HashMap::new(),
            hit_bsdfs: HashMap::new(),
            hit_emitters: Vec::new(),
            mesh_attributes: HashMap::new(),
        }
    }

    /// The scene material number `i`.
    pub(crate) fn material(&self, i: usize) -> Material {
        self.materials[i].clone()
    }

    /// Adds a scene material; returns its number.
    pub(crate) fn add_material(&mut self, m: Material) -> usize {
        self.materials.push(m);
        self.materials.len() - 1
    }

    /// Records a texture that reads the hit (`attribute`: a `mesh_attribute`'s name).
    pub(crate) fn note_hit_texture(&mut self, attribute: Option<&str>, loc: &Location) {
        self.hit_log.push((attribute.map(str::to_owned), loc.clone()));
    }

    /// Marks object `idx` as being built; an object that contains itself is an error.
    pub(crate) fn enter(&mut self, idx: usize, loc: &Location) -> Result<()> {
        if self.visiting.contains(&idx) {
            let o = &self.doc.objs[idx];
            return Err(err(
                loc,
                ErrorKind::Cycle,
                format!(
                    "cyclic reference: <{} type=\"{}\"{}> contains itself",
                    o.tag.name(),
                    o.ty,
                    o.id.as_ref().map(|i| format!(" id=\"{i}\"")).unwrap_or_default()
                ),
            ));
        }
        self.visiting.push(idx);
        Ok(())
    }

    /// Ends [`Builder::enter`].
    pub(crate) fn leave(&mut self) {
        self.visiting.pop();
    }

    // ----------------------------------------------------------------------------------------
    // Scene

    /// Builds the scene from the `<scene>` root.
    pub(crate) fn scene(mut self) -> Result<(Scene, Vec<String>)> {
        let doc = self.doc;
        let root = &doc.objs[doc.root];
        let mut integrator: Option<IntegratorDesc> = None;
        let mut integrator_loc: Option<Location> = None;
        let mut sensor: Option<SensorDesc> = None;
        let mut sensor_medium = None;
        let mut shapes = Vec::new();
        let mut emitters = Vec::new();
        let referenced: std::collections::HashSet<usize> = doc
            .objs
            .iter()
            .flat_map(|o| &o.props)
            .filter_map(|p| match &p.value {
                Value::Ref(id) => doc.ids.get(id).copied(),
                _ => None,
            })
            .collect();
        for p in &root.props {
            let idx = match &p.value {
                Value::Object(i) => *i,
                Value::Ref(_) => {
                    return Err(err(
                        &p.loc,
                        ErrorKind::Grammar,
                        "<ref> is not allowed directly inside <scene>",
                    ));
                }
                v => {
                    return Err(err(
                        &p.loc,
                        ErrorKind::UnusedParameter,
                        format!("unused parameter \"{}\" ({}) in <scene>", p.name, v.describe(doc)),
                    ));
                }
            };
            let obj = &doc.objs[idx];
            match obj.tag {
                Tag::Integrator => {
                    if integrator.is_some() {
                        return Err(err(
                            &obj.loc,
                            ErrorKind::Grammar,
                            "more than one <integrator> in the scene",
                        ));
                    }
                    integrator = Some(self.build_plugin(INTEGRATOR_PLUGINS, idx)?);
                    integrator_loc = Some(obj.loc.clone());
                }
                Tag::Sensor => {
                    let s = self.build_plugin(SENSOR_PLUGINS, idx)?;
                    let medium = self.sensor_medium.take();
                    if sensor.is_none() {
                        sensor = Some(s);
                        sensor_medium = medium;
                    } else {
                        self.warnings
                            .push(format!("{}: more than one sensor; rendering the first", obj.loc));
                    }
                }
                Tag::Shape => {
                    crate::plugins::shape::instance::place(&mut self, idx, &mut shapes)?;
                    // An irradiancemeter nested in the shape: a sensor in document order (with
                    // the medium nested in it, if any).
                    let medium = self.sensor_medium.take();
                    for (s, loc) in std::mem::take(&mut self.shape_sensors) {
                        if sensor.is_none() {
                            sensor = Some(s);
                            sensor_medium = medium;
                        } else {
                            self.warnings
                                .push(format!("{loc}: more than one sensor; rendering the first"));
                        }
                    }
                }
                // An area emitter declared with an id and referenced by a shape (Mitsuba's
                // `scenes/cbox`: `<shape ...><ref id="area-emitter"/></shape>`) is built there.
                Tag::Emitter if referenced.contains(&idx) && crate::plugins::emitter::is_area(obj) => {}
                Tag::Emitter => emitters.push(crate::plugins::emitter::build(&mut self, idx)?),
                // Definitions: built (and so checked) even when nothing refers to them.
                Tag::Bsdf => {
                    self.bsdf(idx, &obj.loc)?;
                }
                Tag::Medium => {
                    self.medium(idx, &obj.loc)?;
                }
                Tag::Phase => {
                    return Err(err(
                        &obj.loc,
                        ErrorKind::Grammar,
                        "<phase> must be nested in a <medium>",
                    ));
                }
                Tag::Volume if referenced.contains(&idx) => {}
                Tag::Volume => {
                    self.build_plugin(crate::plugins::VOLUME_PLUGINS, idx)?;
                }
                Tag::Texture | Tag::Spectrum => {
                    // Referenced textures are built where they are used, in their role (a
                    // colour above 1 is fine for an emitter); others are built once to check them.
                    if !referenced.contains(&idx) {
                        self.texture_object(idx, RgbKind::Unbounded, &obj.loc)?;
                    }
                }
                // Declared at the top with an id and referenced later (Mitsuba's
                // `<sampler id="s"/>` … `<ref id="s"/>` inside a sensor): built where used.
                Tag::Film | Tag::Sampler | Tag::Rfilter if referenced.contains(&idx) => {}
                Tag::Film | Tag::Sampler | Tag::Rfilter => {
                    return Err(err(
                        &obj.loc,
                        ErrorKind::Grammar,
                        format!("<{}> must be nested in a sensor (or film)", obj.tag.name()),
                    ));
                }
                Tag::Scene => unreachable!("the parser rejects nested scenes"),
            }
        }
        let integrator = integrator.unwrap_or_else(|| {
            self.warnings.push(format!(
                "{}: no <integrator>; using path with default parameters",
                root.loc
            ));
            IntegratorDesc::default()
        });
        // Mitsuba 3.9.1's `ptracer` starts light paths with the emitter's `sample_spectrum`,
        // which these textures do not implement: it refuses to render ("Texture::
        // sample_spectrum(): not implemented!"), and so does the reader.
        if let (IntegratorKind::PTracer, Some(loc)) = (integrator.kind, self.hit_emitters.first()) {
            return Err(err(
                loc,
                ErrorKind::BadValue,
                "an area emitter's radiance that reads the hit (mesh_attribute, volume) cannot start the light paths of the ptracer integrator (Mitsuba 3.9.1 refuses it too: the texture has no sample_spectrum); use path or direct",
            ));
        }
        let sensor = match sensor {
            Some(s) => s,
            None => {
                self.warnings.push(format!(
                    "{}: no <sensor>; using a default perspective camera",
                    root.loc
                ));
                crate::plugins::sensor::perspective::default_sensor()
            }
        };
        crate::plugins::film::specfilm::check_integrator(
            &sensor.film,
            &integrator,
            integrator_loc.as_ref().unwrap_or(&root.loc),
        )?;
        let scene = Scene {
            integrator,
            sensor,
            shapes,
            emitters,
            materials: self.materials,
            media: self.media,
            sensor_medium,
        };
        self.warnings
            .extend(crate::plugins::integrator::what_is_left_out(&scene, &root.loc));
        Ok((scene, self.warnings))
    }

    // ----------------------------------------------------------------------------------------
    // Plugins

    /// Builds object `idx` with its plugin in `registry`; an unknown type lists the registry.
    pub(crate) fn build_plugin<T>(
        &mut self,
        registry: &'static [&'static Plugin<T>],
        idx: usize,
    ) -> Result<T> {
        let obj = &self.doc.objs[idx];
        match Plugin::find(registry, &obj.ty) {
            Some(plugin) => self.run_plugin(plugin, idx),
            None => Err(unknown_plugin(obj, &Plugin::names(registry))),
        }
    }

    /// Builds object `idx` with `plugin`: its parameters checked against the plugin's table.
    pub(crate) fn run_plugin<T>(&mut self, plugin: &'static Plugin<T>, idx: usize) -> Result<T> {
        let mut p = Params::with_specs(self.doc, idx, plugin.params);
        let v = (plugin.build)(self, &mut p)?;
        p.finish()?;
        Ok(v)
    }

    /// The index in the scene's media of the `<medium>` object `idx` (built once).
    pub(crate) fn medium(&mut self, idx: usize, loc: &Location) -> Result<crate::medium::MediumId> {
        if let Some(&m) = self.medium_index.get(&idx) {
            return Ok(m);
        }
        self.enter(idx, loc)?;
        let medium = self.build_plugin(crate::plugins::MEDIUM_PLUGINS, idx);
        self.leave();
        let id = self.media.len() as crate::medium::MediumId;
        self.media.push(medium?);
        self.medium_index.insert(idx, id);
        Ok(id)
    }

    /// The one nested `<tag>` object of `p` built with `registry` (`None` if there is none);
    /// more than one is an error ("more than one <tag> in a `container`").
    pub(crate) fn nested_one<T>(
        &mut self,
        p: &mut Params<'d>,
        tag: Tag,
        registry: &'static [&'static Plugin<T>],
        container: &str,
    ) -> Result<Option<T>> {
        match p.objects(tag)?.as_slice() {
            [] => Ok(None),
            [(i, _)] => self.build_plugin(registry, *i).map(Some),
            [_, (_, extra), ..] => Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                format!("more than one <{}> in a {container}", tag.name()),
            )),
        }
    }

    /// The index in the scene's materials of a shape's BSDF (object `bsdf`, built once however
    /// many shapes use it), or of Mitsuba's default material for a shape that does (not) `emit`.
    pub(crate) fn shape_material(&mut self, bsdf: Option<(usize, &Location)>, emits: bool) -> Result<usize> {
        Ok(match bsdf {
            None => {
                let e = emits as usize;
                match self.default_material[e] {
                    Some(i) => i,
                    None => {
                        self.materials.push(Material::default_for_shape(emits));
                        let i = self.materials.len() - 1;
                        self.default_material[e] = Some(i);
                        i
                    }
                }
            }
            Some((b, loc)) => match self.material_index.get(&b) {
                Some(&i) => i,
                None => {
                    let m = self.bsdf(b, loc)?;
                    self.materials.push(m);
                    let i = self.materials.len() - 1;
                    self.material_index.insert(b, i);
                    i
                }
            },
        })
    }

    /// The mesh cached under `key` (file, mesh within the file, `flip_tex_coords`,
    /// `face_normals`), or `load`'s.
    pub(crate) fn cached_mesh(
        &mut self,
        key: (PathBuf, u32, bool, bool),
        load: impl FnOnce() -> Result<TriangleMesh>,
    ) -> Result<Arc<TriangleMesh>> {
        if let Some(m) = self.meshes.get(&key) {
            return Ok(m.clone());
        }
        let m = Arc::new(load()?);
        self.meshes.insert(key, m.clone());
        Ok(m)
    }

    /// The role (reflectance, unbounded, illuminant) of the texture or spectrum object being
    /// built: its colours are uplifted for it.
    pub(crate) fn role(&self) -> RgbKind {
        self.role
    }

    // ----------------------------------------------------------------------------------------
    // Spectra and textures

    /// A spectrum parameter that may not vary over a surface.
    pub(crate) fn spectrum_param(
        &mut self,
        p: &mut Params<'d>,
        name: &str,
        kind: RgbKind,
        default: f32,
    ) -> Result<Spectrum> {
        let loc = p
            .obj
            .props
            .iter()
            .find(|x| x.name == name)
            .map(|x| x.value_loc.clone());
        match self.texture_param(p, name, kind, default)? {
            Texture::Spectrum(s) => Ok(s),
            _ => Err(err(
                loc.as_ref().unwrap_or(&p.obj.loc),
                ErrorKind::WrongType,
                format!(
                    "parameter \"{name}\" of {} must be a spectrum, not a spatially varying texture",
                    p.what()
                ),
            )),
        }
    }

    /// A spectrum or texture parameter in the given role (Mitsuba 3 `src/core/properties.cpp`,
    /// `create_texture_from_rgb/spectrum`): `<float>`/`<integer>` are constant (× D65 for
    /// emitters), `<rgb>` is uplifted (albedo: each component in [0, 1]; unbounded; illuminant
    /// × D65), `<spectrum>` values are uniform (also on emitters) or piecewise linear,
    /// nested or referenced `<texture>`/`<spectrum type>` objects are built in that role.
    pub(crate) fn texture_param(
        &mut self,
        p: &mut Params<'d>,
        name: &str,
        kind: RgbKind,
        default: f32,
    ) -> Result<Texture> {
        let Some(prop) = p.get(name) else {
            return Ok(Texture::Spectrum(number_spectrum(default, kind)));
        };
        let loc = &prop.value_loc;
        let s = match &prop.value {
            Value::Float(v) => {
                check_number(*v, loc, name, kind)?;
                number_spectrum(*v as f32, kind)
            }
            Value::Int(v) => {
                check_number(*v as f64, loc, name, kind)?;
                number_spectrum(*v as f32, kind)
            }
            Value::Rgb(c) => rgb_spectrum(*c, loc, name, kind)?,
            // `<spectrum value="v"/>` is Mitsuba's `uniform`, even on emitters (unlike a float).
            Value::Spectrum(SpecValue::Uniform(v)) => {
                check_number(*v, loc, name, kind)?;
                Spectrum::Constant(*v as f32)
            }
            Value::Spectrum(SpecValue::Pairs(pairs)) => pairs_spectrum(pairs, loc, name, kind)?,
            Value::Object(i) => return self.texture_object(*i, kind, loc),
            Value::Ref(id) => {
                let i = resolve_ref(self.doc, id, loc)?;
                return self.texture_object(i, kind, loc);
            }
            _ => return Err(p.wrong_type(prop, "spectrum or texture")),
        };
        Ok(Texture::Spectrum(s))
    }

    /// Builds a `<texture>` or `<spectrum type>` object (cached per role).
    pub(crate) fn texture_object(&mut self, idx: usize, kind: RgbKind, loc: &Location) -> Result<Texture> {
        let key = (idx, kind_key(kind));
        if let Some(t) = self.textures.get(&key) {
            if let Some(h) = self.hit_textures.get(&key) {
                self.hit_log.extend(h.iter().cloned());
            }
            return Ok(t.clone());
        }
        let hits_before = self.hit_log.len();
        let doc = self.doc;
        let obj = &doc.objs[idx];
        if obj.tag != Tag::Texture && obj.tag != Tag::Spectrum {
            return Err(err(
                loc,
                ErrorKind::WrongType,
                format!(
                    "expected a texture or spectrum, found <{} type=\"{}\">",
                    obj.tag.name(),
                    obj.ty
                ),
            ));
        }
        let registry = if obj.tag == Tag::Texture {
            TEXTURE_PLUGINS
        } else {
            SPECTRUM_PLUGINS
        };
        self.enter(idx, loc)?;
        let Some(plugin) = Plugin::find(registry, &obj.ty) else {
            return Err(unknown_plugin(obj, &Plugin::names(registry)));
        };
        let outer = std::mem::replace(&mut self.role, kind);
        let t = self.run_plugin(plugin, idx)?;
        self.role = outer;
        self.leave();
        self.textures.insert(key, t.clone());
        if self.hit_log.len() > hits_before {
            self.hit_textures
                .insert(key, self.hit_log[hits_before..].to_vec());
        }
        Ok(t)
    }

    /// An index of refraction: a number, a Mitsuba preset name (case-insensitive), a dispersive
    /// glass name (`N-BK7`, `SF11`, …; ours), or a spectrum (ours). NaN, infinite and non-positive
    /// values are rejected.
    pub(crate) fn ior_param(&mut self, p: &mut Params<'d>, name: &str, default: &str) -> Result<Ior> {
        let Some(prop) = p.get(name) else {
            return Ok(Ior::Constant(
                named::ior_preset(default).expect("default IOR presets exist"),
            ));
        };
        let loc = &prop.value_loc;
        let check = |v: f64| -> Result<Ior> {
            if v.is_finite() && v > 0.0 {
                Ok(Ior::Constant(v as f32))
            } else {
                Err(err(
                    loc,
                    ErrorKind::BadValue,
                    format!("invalid index of refraction {v} for \"{name}\" (must be a positive number)"),
                ))
            }
        };
        match &prop.value {
            Value::Float(v) => check(*v),
            Value::Int(v) => check(*v as f64),
            Value::Spectrum(SpecValue::Uniform(v)) => check(*v),
            Value::Spectrum(SpecValue::Pairs(pairs)) => {
                if let Some(&(l, v)) = pairs.iter().find(|(_, v)| !(*v > 0.0)) {
                    return Err(err(
                        loc,
                        ErrorKind::BadValue,
                        format!(
                            "invalid index of refraction {v} at {l} nm for \"{name}\" (must be positive)"
                        ),
                    ));
                }
                Ok(Ior::from_spectrum(pairs_spectrum(
                    pairs,
                    loc,
                    name,
                    RgbKind::Unbounded,
                )?))
            }
            Value::Str(s) => {
                if let Some(v) = named::ior_preset(s) {
                    Ok(Ior::Constant(v))
                } else if let Some(g) = named::glass(s) {
                    Ok(Ior::from_spectrum(g))
                } else {
                    Err(err(
                        loc,
                        ErrorKind::UnknownPreset,
                        format!(
                            "unknown index of refraction \"{s}\" for \"{name}\" (presets: {}; dispersive glasses: {})",
                            named::ior_preset_names().join(", "),
                            named::glass_names().join(", ")
                        ),
                    ))
                }
            }
            _ => Err(p.wrong_type(prop, "float, preset name or spectrum")),
        }
    }

    // ----------------------------------------------------------------------------------------
    // BSDFs

    /// Builds a `<bsdf>` object (cached) with its registered plugin ([`crate::material`]).
    pub(crate) fn bsdf(&mut self, idx: usize, loc: &Location) -> Result<Material> {
        if let Some(m) = self.bsdfs.get(&idx) {
            if let Some(h) = self.hit_bsdfs.get(&idx) {
                self.hit_log.extend(h.iter().cloned());
            }
            return Ok(m.clone());
        }
        let hits_before = self.hit_log.len();
        let doc = self.doc;
        let obj = &doc.objs[idx];
        if obj.tag != Tag::Bsdf {
            return Err(err(
                loc,
                ErrorKind::WrongType,
                format!("expected a bsdf, found <{} type=\"{}\">", obj.tag.name(), obj.ty),
            ));
        }
        let Some(plugin) = Plugin::find(crate::material::BSDF_PLUGINS, &obj.ty) else {
            return Err(unknown_plugin(obj, &Plugin::names(crate::material::BSDF_PLUGINS)));
        };
        self.enter(idx, loc)?;
        let mut p = Params::with_specs(doc, idx, plugin.params);
        let m = (plugin.build)(self, &mut p)?;
        p.finish()?;
        self.leave();
        if m.as_surface().node_count() > MAX_NODES {
            return Err(err(
                &obj.loc,
                ErrorKind::BadValue,
                format!(
                    "<bsdf type=\"{}\"> nests {} BSDFs; {}",
                    obj.ty,
                    m.as_surface().node_count(),
                    gonio_core::bsdfs::surface::TooManyNodes
                ),
            ));
        }
        self.bsdfs.insert(idx, m.clone());
        if self.hit_log.len() > hits_before {
            self.hit_bsdfs.insert(idx, self.hit_log[hits_before..].to_vec());
        }
        Ok(m)
    }

    /// The object being built by `p` (for plugin builders: its location, type and folder).
    pub(crate) fn object(&self, p: &Params<'d>) -> &'d Obj {
        p.obj
    }

    /// Resolves a file name written in the object of `p`.
    pub(crate) fn resolve_file(&self, p: &Params<'d>, name: &str) -> PathBuf {
        self.doc.resolve(p.obj, name)
    }

    /// A spectrum-or-texture parameter from its table row (default and name from the row).
    pub(crate) fn texture(&mut self, p: &mut Params<'d>, spec: &ParamSpec, kind: RgbKind) -> Result<Texture> {
        self.texture_param(p, spec.name, kind, spec.default.float() as f32)
    }

    /// A spectrum parameter (not spatially varying) from its table row.
    pub(crate) fn spectrum(
        &mut self,
        p: &mut Params<'d>,
        spec: &ParamSpec,
        kind: RgbKind,
    ) -> Result<Spectrum> {
        self.spectrum_param(p, spec.name, kind, spec.default.float() as f32)
    }

    /// An index-of-refraction parameter from its table row (default: the row's preset name).
    pub(crate) fn ior(&mut self, p: &mut Params<'d>, spec: &ParamSpec) -> Result<Ior> {
        self.ior_param(p, spec.name, spec.default.str())
    }
}

fn number_spectrum(v: f32, kind: RgbKind) -> Spectrum {
    match kind {
        RgbKind::Illuminant => Spectrum::rgb_illuminant([v; 3]),
        _ => Spectrum::Constant(v),
    }
}

/// Numbers as spectra: Mitsuba takes any uniform value (even a reflectance above 1); we reject
/// only non-finite and negative ones, which are always mistakes.
fn check_number(v: f64, loc: &Location, name: &str, _kind: RgbKind) -> Result<()> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(err(
            loc,
            ErrorKind::BadValue,
            format!("invalid value {v} for \"{name}\" (must be finite and non-negative)"),
        ))
    }
}

fn rgb_spectrum(c: [f64; 3], loc: &Location, name: &str, kind: RgbKind) -> Result<Spectrum> {
    let bad = c
        .iter()
        .any(|v| !v.is_finite() || *v < 0.0 || (kind == RgbKind::Albedo && *v > 1.0));
    if bad {
        let rule = if kind == RgbKind::Albedo {
            "each component in [0, 1] for a reflectance"
        } else {
            "finite, non-negative components"
        };
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "invalid rgb ({}, {}, {}) for \"{name}\" ({rule})",
                c[0], c[1], c[2]
            ),
        ));
    }
    let c = c.map(|v| v as f32);
    Ok(match kind {
        RgbKind::Albedo => Spectrum::rgb_albedo(c),
        RgbKind::Unbounded => Spectrum::rgb_unbounded(c),
        RgbKind::Illuminant => Spectrum::rgb_illuminant(c),
    })
}

/// λ:value pairs: 0 outside the range for reflectances and emission (Mitsuba `irregular`), end
/// values continued for η, k and indices (0 there would make the Fresnel terms NaN).
fn pairs_spectrum(pairs: &[(f64, f64)], loc: &Location, name: &str, kind: RgbKind) -> Result<Spectrum> {
    if let Some(&(l, v)) = pairs.iter().find(|(_, v)| *v < 0.0) {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!("negative value {v} at {l} nm in \"{name}\""),
        ));
    }
    let extrapolation = if kind == RgbKind::Unbounded {
        Extrapolation::Clamp
    } else {
        Extrapolation::Zero
    };
    let lambda = pairs.iter().map(|p| p.0 as f32).collect();
    let value = pairs.iter().map(|p| p.1 as f32).collect();
    let pl = PiecewiseLinear::new(lambda, value, extrapolation).ok_or_else(|| {
        err(
            loc,
            ErrorKind::BadValue,
            format!("invalid spectrum for \"{name}\""),
        )
    })?;
    Ok(Spectrum::piecewise(pl))
}

/// The error for an image file that cannot be read (I/O or decoding).
pub(crate) fn image_error(loc: &Location, name: &str, e: crate::image::ImageError) -> SceneError {
    use crate::image::ImageError as E;
    let kind = if matches!(e, E::Io { .. }) {
        ErrorKind::Io
    } else {
        ErrorKind::Image
    };
    err(loc, kind, format!("cannot load image \"{name}\": {e}"))
}
