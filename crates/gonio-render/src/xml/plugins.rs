//! Plugin instantiation: object tree → [`Scene`]. Each loader below lists the Mitsuba 3
//! parameters it accepts and their defaults; any other parameter is an error ("unused
//! parameter"), as in Mitsuba.

use super::error::{ErrorKind, Location, SceneError};
use super::params::{ParamSpec, Params, err, resolve_ref, to_affine};
use super::parse::{Doc, Obj, Tag, Value};
use super::values::SpecValue;
use crate::image::{Encoding, RgbImage};
use crate::material::Material;
use crate::mesh;
use crate::scene::{
    AreaEmitter, Emitter, Film, Filter, Geometry, Integrator, Sampler, SamplerKind, Scene, Sensor, Shape,
    TriangleMesh,
};
use crate::texture::{Bitmap, FilterType, Texture, WrapMode};
use glam::{Affine3A, DVec3, Vec3};
use gonio_core::Ior;
use gonio_core::bsdfs::surface::MAX_NODES;
use gonio_core::named;
use gonio_core::spectra::{Extrapolation, PiecewiseLinear, RgbKind, Spectrum};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

type Result<T> = std::result::Result<T, SceneError>;

/// The builder: caches so that a referenced BSDF, texture or mesh is built once.
pub(crate) struct Builder<'d> {
    pub(crate) doc: &'d Doc,
    materials: Vec<Material>,
    material_index: HashMap<usize, usize>,
    default_material: [Option<usize>; 2],
    bsdfs: HashMap<usize, Material>,
    textures: HashMap<(usize, u8), Texture>,
    meshes: HashMap<(PathBuf, bool, bool), Arc<TriangleMesh>>,
    visiting: Vec<usize>,
    pub warnings: Vec<String>,
}

fn kind_key(k: RgbKind) -> u8 {
    match k {
        RgbKind::Albedo => 0,
        RgbKind::Unbounded => 1,
        RgbKind::Illuminant => 2,
    }
}

fn unknown_plugin(obj: &Obj, supported: &[&str]) -> SceneError {
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
            warnings: Vec::new(),
        }
    }

    fn enter(&mut self, idx: usize, loc: &Location) -> Result<()> {
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

    fn leave(&mut self) {
        self.visiting.pop();
    }

    // ----------------------------------------------------------------------------------------
    // Scene

    /// Builds the scene from the `<scene>` root.
    pub(crate) fn scene(mut self) -> Result<(Scene, Vec<String>)> {
        let doc = self.doc;
        let root = &doc.objs[doc.root];
        let mut integrator: Option<Integrator> = None;
        let mut sensor: Option<Sensor> = None;
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
                    integrator = Some(self.integrator(idx)?);
                }
                Tag::Sensor => {
                    let s = self.sensor(idx)?;
                    if sensor.is_none() {
                        sensor = Some(s);
                    } else {
                        self.warnings
                            .push(format!("{}: more than one sensor; rendering the first", obj.loc));
                    }
                }
                Tag::Shape => shapes.push(self.shape(idx)?),
                Tag::Emitter => emitters.push(self.emitter(idx)?),
                // Definitions: built (and so checked) even when nothing refers to them.
                Tag::Bsdf => {
                    self.bsdf(idx, &obj.loc)?;
                }
                Tag::Texture | Tag::Spectrum => {
                    // Referenced textures are built where they are used, in their role (a
                    // colour above 1 is fine for an emitter); others are built once to check them.
                    if !referenced.contains(&idx) {
                        self.texture_object(idx, RgbKind::Unbounded, &obj.loc)?;
                    }
                }
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
            Integrator::default()
        });
        let sensor = match sensor {
            Some(s) => s,
            None => {
                self.warnings.push(format!(
                    "{}: no <sensor>; using a default perspective camera",
                    root.loc
                ));
                perspective_default()
            }
        };
        let scene = Scene {
            integrator,
            sensor,
            shapes,
            emitters,
            materials: self.materials,
        };
        Ok((scene, self.warnings))
    }

    /// Integrator `path`: `max_depth` (−1 = ∞), `rr_depth` (5), `hide_emitters` (false), ours
    /// `thin_shadows` (true) and `caustic_paths` (true); `samples_per_pass` and `timeout` accepted and ignored.
    fn integrator(&mut self, idx: usize) -> Result<Integrator> {
        let obj = &self.doc.objs[idx];
        if obj.ty != "path" {
            return Err(unknown_plugin(obj, &["path"]));
        }
        let mut p = Params::new(self.doc, idx);
        let max_depth = p.int_in("max_depth", -1, -1, i32::MAX as i64)? as i32;
        let rr_depth = p.int_in("rr_depth", 5, 1, u32::MAX as i64)? as u32;
        let hide_emitters = p.bool("hide_emitters", false)?;
        let thin_shadows = p.bool("thin_shadows", true)?;
        let caustic_paths = p.bool("caustic_paths", true)?;
        p.int_in("samples_per_pass", -1, -1, i64::MAX)?;
        p.float("timeout", -1.0)?;
        p.finish()?;
        Ok(Integrator {
            max_depth,
            rr_depth,
            hide_emitters,
            thin_shadows,
            caustic_paths,
        })
    }

    /// Sensor `perspective`: `to_world`, `fov` or `focal_length` ("50mm"), `fov_axis` (x, y,
    /// diagonal, smaller, larger), `near_clip` (0.01), `far_clip` (10000),
    /// `principal_point_offset_x/y` (only 0), `shutter_open`/`shutter_close` (ignored); nested
    /// `film` (hdrfilm) and `sampler` (independent).
    fn sensor(&mut self, idx: usize) -> Result<Sensor> {
        let obj = &self.doc.objs[idx];
        if obj.ty != "perspective" {
            return Err(unknown_plugin(obj, &["perspective"]));
        }
        let mut p = Params::new(self.doc, idx);
        let films = p.objects(Tag::Film)?;
        let film = match films.as_slice() {
            [] => Film::default(),
            [(f, _)] => self.film(*f)?,
            [_, (_, extra), ..] => {
                return Err(err(
                    &extra.loc,
                    ErrorKind::Grammar,
                    "more than one <film> in a sensor",
                ));
            }
        };
        let samplers = p.objects(Tag::Sampler)?;
        let sampler = match samplers.as_slice() {
            [] => Sampler::default(),
            [(s, _)] => self.sampler(*s)?,
            [_, (_, extra), ..] => {
                return Err(err(
                    &extra.loc,
                    ErrorKind::Grammar,
                    "more than one <sampler> in a sensor",
                ));
            }
        };
        let tw_loc = p
            .obj
            .props
            .iter()
            .find(|x| x.name == "to_world")
            .map(|x| x.loc.clone());
        let to_world = p.affine("to_world")?;
        // Mitsuba: "Scale factors in the camera-to-world transformation are not allowed!"
        // (a mirror flip, scale −1, keeps unit axes and is allowed).
        let m = to_world.matrix3;
        if [m.x_axis, m.y_axis, m.z_axis]
            .iter()
            .any(|a| (a.length() - 1.0).abs() > 1e-3)
        {
            return Err(err(
                tw_loc.as_ref().unwrap_or(&obj.loc),
                ErrorKind::BadValue,
                format!(
                    "scale factors in the sensor's to_world are not allowed (axis lengths {}, {}, {})",
                    m.x_axis.length(),
                    m.y_axis.length(),
                    m.z_axis.length()
                ),
            ));
        }
        let aspect = film.width as f64 / film.height as f64;
        let fov = p.float_opt("fov")?;
        let focal = p.string_opt("focal_length")?;
        let axis = p.choice("fov_axis", "x", &["x", "y", "diagonal", "smaller", "larger"])?;
        let fov_x = match (fov, focal) {
            (Some(_), Some((_, loc))) => {
                return Err(err(
                    loc,
                    ErrorKind::Grammar,
                    "give either fov or focal_length, not both",
                ));
            }
            (Some((v, loc)), None) => {
                if !(v > 0.0 && v < 180.0) {
                    return Err(err(
                        loc,
                        ErrorKind::BadValue,
                        format!("invalid fov {v} (must be in (0, 180) degrees)"),
                    ));
                }
                fov_to_x(v, axis, aspect)
            }
            (None, f) => {
                let (s, loc) = f.map(|(s, l)| (s, Some(l))).unwrap_or(("50mm", None));
                let num = s.trim().strip_suffix("mm").unwrap_or(s.trim());
                let mm: f64 = num
                    .trim()
                    .parse()
                    .ok()
                    .filter(|v: &f64| *v > 0.0 && v.is_finite())
                    .ok_or_else(|| {
                        err(
                            loc.unwrap_or(&obj.loc),
                            ErrorKind::BadValue,
                            format!("invalid focal_length \"{s}\" (expected e.g. \"50mm\")"),
                        )
                    })?;
                // 35 mm film diagonal: sqrt(36² + 24²) mm.
                let diag = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
                let fov_diag = 2.0 * (diag / (2.0 * mm)).atan().to_degrees();
                fov_to_x(fov_diag, "diagonal", aspect)
            }
        };
        let near_clip = p.float_checked("near_clip", 0.01, |v| v > 0.0, "must be positive")?;
        let far_clip = p.float_checked("far_clip", 10000.0, |v| v > 0.0, "must be positive")?;
        if far_clip <= near_clip {
            return Err(err(
                &obj.loc,
                ErrorKind::BadValue,
                format!("far_clip {far_clip} must exceed near_clip {near_clip}"),
            ));
        }
        for name in ["principal_point_offset_x", "principal_point_offset_y"] {
            if let Some((v, loc)) = p.float_opt(name)? {
                if v != 0.0 {
                    return Err(err(
                        loc,
                        ErrorKind::BadValue,
                        format!("{name} {v} is not supported (only 0)"),
                    ));
                }
            }
        }
        p.float("shutter_open", 0.0)?;
        p.float("shutter_close", 0.0)?;
        p.finish()?;
        Ok(Sensor {
            to_world,
            fov_x_deg: fov_x as f32,
            near_clip: near_clip as f32,
            far_clip: far_clip as f32,
            film,
            sampler,
        })
    }

    /// Film `hdrfilm`: `width` (768), `height` (576), nested `rfilter` (gaussian); Mitsuba's output
    /// settings `file_format` (openexr, exr, rgbe, pfm), `pixel_format` (rgb, rgba, luminance,
    /// luminance_alpha, xyz, xyza), `component_format` (float16, float32, uint32),
    /// `sample_border`, `compensate` are accepted and ignored (gonio writes by file name);
    /// `crop_*` only as the full image.
    fn film(&mut self, idx: usize) -> Result<Film> {
        let obj = &self.doc.objs[idx];
        if obj.ty != "hdrfilm" {
            return Err(unknown_plugin(obj, &["hdrfilm"]));
        }
        let mut p = Params::new(self.doc, idx);
        let width = p.int_in("width", 768, 1, 1 << 16)? as u32;
        let height = p.int_in("height", 576, 1, 1 << 16)? as u32;
        let filters = p.objects(Tag::Rfilter)?;
        let filter = match filters.as_slice() {
            [] => Filter::default(),
            [(f, _)] => self.rfilter(*f)?,
            [_, (_, extra), ..] => {
                return Err(err(
                    &extra.loc,
                    ErrorKind::Grammar,
                    "more than one <rfilter> in a film",
                ));
            }
        };
        p.choice("file_format", "openexr", &["openexr", "exr", "rgbe", "pfm"])?;
        p.choice(
            "pixel_format",
            "rgb",
            &["rgb", "rgba", "luminance", "luminance_alpha", "xyz", "xyza"],
        )?;
        p.choice("component_format", "float16", &["float16", "float32", "uint32"])?;
        p.bool("sample_border", false)?;
        p.bool("compensate", false)?;
        p.int_in("crop_offset_x", 0, 0, 0)?;
        p.int_in("crop_offset_y", 0, 0, 0)?;
        p.int_in("crop_width", width as i64, width as i64, width as i64)?;
        p.int_in("crop_height", height as i64, height as i64, height as i64)?;
        p.finish()?;
        Ok(Film {
            width,
            height,
            filter,
        })
    }

    /// Reconstruction filters: `box` (`radius` 0.5), `tent` (`radius` 1), `gaussian` (`stddev`
    /// 0.5).
    fn rfilter(&mut self, idx: usize) -> Result<Filter> {
        let obj = &self.doc.objs[idx];
        let mut p = Params::new(self.doc, idx);
        let positive = |v: f64| v > 0.0;
        let f = match obj.ty.as_str() {
            "box" => Filter::Box {
                radius: p.float_checked("radius", 0.5, positive, "must be positive")? as f32,
            },
            "tent" => Filter::Tent {
                radius: p.float_checked("radius", 1.0, positive, "must be positive")? as f32,
            },
            "gaussian" => Filter::Gaussian {
                stddev: p.float_checked("stddev", 0.5, positive, "must be positive")? as f32,
            },
            _ => return Err(unknown_plugin(obj, &["box", "tent", "gaussian"])),
        };
        p.finish()?;
        Ok(f)
    }

    /// Samplers `independent`, `stratified`, `multijitter`: `sample_count` (4), `seed` (0);
    /// `jitter` (true) for the stratified ones.
    fn sampler(&mut self, idx: usize) -> Result<Sampler> {
        let obj = &self.doc.objs[idx];
        let mut p = Params::new(self.doc, idx);
        let kind = match obj.ty.as_str() {
            "independent" => SamplerKind::Independent,
            "stratified" => SamplerKind::Stratified {
                jitter: p.bool("jitter", true)?,
            },
            "multijitter" => SamplerKind::MultiJitter {
                jitter: p.bool("jitter", true)?,
            },
            _ => return Err(unknown_plugin(obj, &["independent", "stratified", "multijitter"])),
        };
        let sample_count = p.int_in("sample_count", 4, 1, u32::MAX as i64)? as u32;
        let seed = p.int_in("seed", 0, 0, i64::MAX)? as u64;
        p.finish()?;
        Ok(Sampler {
            kind,
            sample_count,
            seed,
        })
    }

    // ----------------------------------------------------------------------------------------
    // Shapes

    /// Shapes `sphere` (`center` 0, `radius` 1), `rectangle`, `disk`, `cube`, `obj` and `ply`
    /// (`filename`, `face_normals` false, `flip_tex_coords` true for obj / false for ply); all take
    /// `to_world`, `flip_normals` (false), one nested or referenced bsdf (default: diffuse 0.5,
    /// or black if the shape emits) and one nested `area` emitter.
    fn shape(&mut self, idx: usize) -> Result<Shape> {
        let doc = self.doc;
        let obj = &doc.objs[idx];
        let mut p = Params::new(doc, idx);
        let to_world = p.affine("to_world")?;
        let flip_normals = p.bool("flip_normals", false)?;
        let mut face_normals = false;
        let geometry = match obj.ty.as_str() {
            "sphere" => {
                let center = p.point_opt("center")?.map_or(DVec3::ZERO, |(c, _)| c);
                let radius = p.float_checked("radius", 1.0, |r| r > 0.0, "must be positive")?;
                check_similarity(&to_world, obj)?;
                Geometry::Sphere {
                    center: center.as_vec3(),
                    radius: radius as f32,
                }
            }
            "rectangle" => Geometry::Rectangle,
            "disk" => {
                check_similarity(&to_world, obj)?;
                Geometry::Disk
            }
            "cube" => {
                face_normals = p.bool("face_normals", false)?;
                Geometry::Mesh(Arc::new(mesh::cube()))
            }
            "obj" | "ply" => {
                face_normals = p.bool("face_normals", false)?;
                let flip = p.bool("flip_tex_coords", obj.ty == "obj")?;
                let Some((name, loc)) = p.string_opt("filename")? else {
                    return Err(err(
                        &obj.loc,
                        ErrorKind::Grammar,
                        format!("<shape type=\"{}\"> needs a filename", obj.ty),
                    ));
                };
                let path = doc.resolve(obj, name);
                let key = (path.clone(), flip, face_normals);
                let m = match self.meshes.get(&key) {
                    Some(m) => m.clone(),
                    None => {
                        let r = if obj.ty == "obj" {
                            mesh::load_obj(&path, flip)
                        } else {
                            mesh::load_ply(&path, flip)
                        };
                        let mut m = r.map_err(|e| {
                            let kind = if e.is_io() { ErrorKind::Io } else { ErrorKind::Mesh };
                            err(loc, kind, format!("cannot load mesh \"{name}\": {e}"))
                        })?;
                        // Mitsuba smooths meshes without normals unless face_normals is set.
                        if !face_normals && m.normals.is_empty() {
                            m.normals = mesh::vertex_normals(&m);
                        }
                        let m = Arc::new(m);
                        self.meshes.insert(key, m.clone());
                        m
                    }
                };
                Geometry::Mesh(m)
            }
            _ => {
                return Err(unknown_plugin(
                    obj,
                    &["sphere", "rectangle", "disk", "cube", "obj", "ply"],
                ));
            }
        };
        let bsdfs = p.objects(Tag::Bsdf)?;
        let emitters = p.objects(Tag::Emitter)?;
        p.finish()?;
        let emitter = match emitters.as_slice() {
            [] => None,
            [(e, prop)] => Some(self.area_emitter(*e, &prop.value_loc)?),
            [_, (_, extra), ..] => {
                return Err(err(
                    &extra.loc,
                    ErrorKind::Grammar,
                    "more than one emitter attached to a shape",
                ));
            }
        };
        let material = match bsdfs.as_slice() {
            [] => {
                let e = emitter.is_some() as usize;
                match self.default_material[e] {
                    Some(i) => i,
                    None => {
                        self.materials
                            .push(Material::default_for_shape(emitter.is_some()));
                        let i = self.materials.len() - 1;
                        self.default_material[e] = Some(i);
                        i
                    }
                }
            }
            [(b, prop)] => match self.material_index.get(b) {
                Some(&i) => i,
                None => {
                    let m = self.bsdf(*b, &prop.value_loc)?;
                    self.materials.push(m);
                    let i = self.materials.len() - 1;
                    self.material_index.insert(*b, i);
                    i
                }
            },
            [_, (_, extra), ..] => {
                return Err(err(
                    &extra.loc,
                    ErrorKind::Grammar,
                    "more than one bsdf attached to a shape",
                ));
            }
        };
        Ok(Shape {
            geometry,
            to_world,
            flip_normals,
            face_normals,
            material,
            emitter,
            id: obj.id.clone(),
        })
    }

    // ----------------------------------------------------------------------------------------
    // Emitters

    /// Emitter `area` (nested in a shape): `radiance` (1, × D65 for colours and numbers).
    fn area_emitter(&mut self, idx: usize, loc: &Location) -> Result<AreaEmitter> {
        let obj = &self.doc.objs[idx];
        if obj.ty != "area" {
            return Err(err(
                &obj.ty_loc,
                ErrorKind::UnknownPlugin,
                format!("a shape can only carry an \"area\" emitter, found \"{}\"", obj.ty),
            ));
        }
        self.enter(idx, loc)?;
        let mut p = Params::new(self.doc, idx);
        let radiance = self.texture_param(&mut p, "radiance", RgbKind::Illuminant, 1.0)?;
        p.finish()?;
        self.leave();
        Ok(AreaEmitter { radiance })
    }

    /// Emitters `point` (`intensity` 1, `position` or `to_world`), `spot` (`intensity` 1,
    /// `cutoff_angle` 20°, `beam_width` ¾·cutoff, `to_world`), `directional` (`irradiance` 1,
    /// `direction` or `to_world`), `constant` (`radiance` 1), `envmap` (`filename`, `scale` 1,
    /// `to_world`, `mis_compensation` ignored). Colours and numbers are × D65 (spectral Mitsuba).
    fn emitter(&mut self, idx: usize) -> Result<Emitter> {
        let doc = self.doc;
        let obj = &doc.objs[idx];
        let mut p = Params::new(doc, idx);
        let e = match obj.ty.as_str() {
            "area" => {
                return Err(err(
                    &obj.loc,
                    ErrorKind::Grammar,
                    "an \"area\" emitter must be nested in a <shape>",
                ));
            }
            "point" => {
                let intensity = self.spectrum_param(&mut p, "intensity", RgbKind::Illuminant, 1.0)?;
                let pos = p.point_opt("position")?;
                let tw = p.transform_opt("to_world")?;
                let position = match (pos, tw) {
                    (Some(_), Some((_, loc))) => {
                        return Err(err(
                            loc,
                            ErrorKind::Grammar,
                            "give either position or to_world, not both",
                        ));
                    }
                    (Some((v, _)), None) => v.as_vec3(),
                    (None, Some((m, loc))) => to_affine(m, loc, "to_world")?.transform_point3(Vec3::ZERO),
                    (None, None) => Vec3::ZERO,
                };
                Emitter::Point { position, intensity }
            }
            "spot" => {
                let intensity = self.spectrum_param(&mut p, "intensity", RgbKind::Illuminant, 1.0)?;
                let cutoff = p.float_checked(
                    "cutoff_angle",
                    20.0,
                    |v| v > 0.0 && v <= 90.0,
                    "must be in (0, 90]",
                )?;
                let beam = p.float_checked(
                    "beam_width",
                    cutoff * 0.75,
                    |v| v > 0.0 && v <= cutoff,
                    "must be in (0, cutoff_angle]",
                )?;
                let to_world = p.affine("to_world")?;
                Emitter::Spot {
                    to_world,
                    intensity,
                    cutoff_angle_deg: cutoff as f32,
                    beam_width_deg: beam as f32,
                }
            }
            "directional" => {
                let irradiance = self.spectrum_param(&mut p, "irradiance", RgbKind::Illuminant, 1.0)?;
                let dir = p.point_opt("direction")?;
                let tw = p.transform_opt("to_world")?;
                let (d, loc) = match (dir, tw) {
                    (Some(_), Some((_, loc))) => {
                        return Err(err(
                            loc,
                            ErrorKind::Grammar,
                            "give either direction or to_world, not both",
                        ));
                    }
                    (Some((v, loc)), None) => (v.as_vec3(), loc),
                    (None, Some((m, loc))) => {
                        (to_affine(m, loc, "to_world")?.transform_vector3(Vec3::Z), loc)
                    }
                    (None, None) => (Vec3::Z, &obj.loc),
                };
                if !(d.length_squared() > 0.0) || !d.is_finite() {
                    return Err(err(
                        loc,
                        ErrorKind::BadValue,
                        format!("invalid direction {d} (must be non-zero)"),
                    ));
                }
                Emitter::Directional {
                    direction: d.normalize(),
                    irradiance,
                }
            }
            "constant" => {
                let radiance = self.spectrum_param(&mut p, "radiance", RgbKind::Illuminant, 1.0)?;
                Emitter::Constant { radiance }
            }
            "envmap" => {
                let Some((name, loc)) = p.string_opt("filename")? else {
                    return Err(err(
                        &obj.loc,
                        ErrorKind::Grammar,
                        "<emitter type=\"envmap\"> needs a filename",
                    ));
                };
                let path = doc.resolve(obj, name);
                let image = RgbImage::read(&path).map_err(|e| image_error(loc, name, e))?;
                let scale = p.float_checked("scale", 1.0, |v| v >= 0.0, "must be non-negative")? as f32;
                let to_world = p.affine("to_world")?;
                p.bool("mis_compensation", false)?;
                Emitter::EnvMap {
                    image: Arc::new(image),
                    scale,
                    to_world,
                }
            }
            _ => {
                return Err(unknown_plugin(
                    obj,
                    &["area", "point", "spot", "directional", "constant", "envmap"],
                ));
            }
        };
        p.finish()?;
        Ok(e)
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
    fn texture_object(&mut self, idx: usize, kind: RgbKind, loc: &Location) -> Result<Texture> {
        let key = (idx, kind_key(kind));
        if let Some(t) = self.textures.get(&key) {
            return Ok(t.clone());
        }
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
        self.enter(idx, loc)?;
        let mut p = Params::new(doc, idx);
        let t = match (obj.tag, obj.ty.as_str()) {
            (Tag::Texture, "checkerboard") => {
                let color0 = self.texture_param(&mut p, "color0", kind, 0.4)?;
                let color1 = self.texture_param(&mut p, "color1", kind, 0.2)?;
                let to_uv = p.to_uv()?;
                Texture::Checkerboard {
                    color0: Box::new(color0),
                    color1: Box::new(color1),
                    to_uv,
                }
            }
            (Tag::Texture, "bitmap") => self.bitmap(&mut p, kind)?,
            (Tag::Texture, _) => return Err(unknown_plugin(obj, &["checkerboard", "bitmap"])),
            (_, "d65") => {
                let scale = p.float_checked("scale", 1.0, |v| v >= 0.0, "must be non-negative")?;
                Texture::Spectrum(Spectrum::rgb_illuminant([scale as f32; 3]))
            }
            (_, "blackbody") => {
                let Some((t, tloc)) = p.float_opt("temperature")? else {
                    return Err(err(
                        &obj.loc,
                        ErrorKind::Grammar,
                        "<spectrum type=\"blackbody\"> needs a temperature",
                    ));
                };
                if !(t > 0.0 && t.is_finite()) {
                    return Err(err(
                        tloc,
                        ErrorKind::BadValue,
                        format!("invalid temperature {t} K (must be positive)"),
                    ));
                }
                let scale = p.float_checked("scale", 1.0, |v| v >= 0.0, "must be non-negative")? as f32;
                let b = Spectrum::blackbody(t as f32);
                Texture::Spectrum(if scale == 1.0 { b } else { scaled(b, scale) })
            }
            (_, "uniform") => {
                let v = p.float("value", 1.0)?;
                Texture::Spectrum(Spectrum::Constant(v as f32))
            }
            (_, _) => return Err(unknown_plugin(obj, &["d65", "blackbody", "uniform"])),
        };
        p.finish()?;
        self.leave();
        self.textures.insert(key, t.clone());
        Ok(t)
    }

    /// Texture `bitmap`: `filename`, `filter_type` (bilinear, nearest), `wrap_mode` (repeat,
    /// mirror, clamp), `raw` (false), `to_uv`; `format` (auto, variant, fp16) and `accel` are
    /// accepted and ignored.
    fn bitmap(&mut self, p: &mut Params<'d>, kind: RgbKind) -> Result<Texture> {
        let obj = p.obj;
        let Some((name, loc)) = p.string_opt("filename")? else {
            return Err(err(
                &obj.loc,
                ErrorKind::Grammar,
                "<texture type=\"bitmap\"> needs a filename",
            ));
        };
        let filter = match p.choice("filter_type", "bilinear", &["bilinear", "nearest"])? {
            "nearest" => FilterType::Nearest,
            _ => FilterType::Bilinear,
        };
        let wrap = match p.choice("wrap_mode", "repeat", &["repeat", "mirror", "clamp"])? {
            "mirror" => WrapMode::Mirror,
            "clamp" => WrapMode::Clamp,
            _ => WrapMode::Repeat,
        };
        let raw = p.bool("raw", false)?;
        let to_uv = p.to_uv()?;
        p.choice("format", "auto", &["auto", "variant", "fp16"])?;
        p.bool("accel", true)?;
        let path = self.doc.resolve(obj, name);
        let img = RgbImage::read_with(&path, if raw { Encoding::Raw } else { Encoding::Srgb })
            .map_err(|e| image_error(loc, name, e))?;
        let (w, h) = (img.width, img.height);
        let bitmap = Bitmap::new(w, h, img.data, filter, wrap, kind, to_uv).ok_or_else(|| {
            err(
                loc,
                ErrorKind::Image,
                format!("image \"{name}\" is empty ({w}x{h})"),
            )
        })?;
        Ok(Texture::Bitmap(Arc::new(bitmap)))
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
            return Ok(m.clone());
        }
        let doc = self.doc;
        let obj = &doc.objs[idx];
        if obj.tag != Tag::Bsdf {
            return Err(err(
                loc,
                ErrorKind::WrongType,
                format!("expected a bsdf, found <{} type=\"{}\">", obj.tag.name(), obj.ty),
            ));
        }
        let Some(plugin) = crate::material::bsdf_plugin(&obj.ty) else {
            let names: Vec<&str> = crate::material::BSDF_PLUGINS.iter().map(|p| p.name).collect();
            return Err(unknown_plugin(obj, &names));
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

/// Sphere and disk keep their shape only under rotation, uniform scale and translation.
fn check_similarity(m: &Affine3A, obj: &Obj) -> Result<()> {
    let a = m.matrix3;
    let (x, y, z) = (a.x_axis.length(), a.y_axis.length(), a.z_axis.length());
    let s = x.max(y).max(z);
    let ortho = a
        .x_axis
        .dot(a.y_axis)
        .abs()
        .max(a.y_axis.dot(a.z_axis).abs())
        .max(a.x_axis.dot(a.z_axis).abs());
    let tol = 1e-4 * s.max(1e-30);
    if (x - y).abs() > tol * s.max(1.0) || (y - z).abs() > tol * s.max(1.0) || ortho > tol * s {
        return Err(err(
            &obj.loc,
            ErrorKind::BadValue,
            format!(
                "<shape type=\"{}\"> to_world has a non-uniform scale or shear (axis lengths {x}, {y}, {z}); use a mesh",
                obj.ty
            ),
        ));
    }
    Ok(())
}

fn perspective_default() -> Sensor {
    let film = Film::default();
    let aspect = film.width as f64 / film.height as f64;
    let diag = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
    let fov = fov_to_x(2.0 * (diag / 100.0).atan().to_degrees(), "diagonal", aspect);
    Sensor {
        to_world: Affine3A::IDENTITY,
        fov_x_deg: fov as f32,
        near_clip: 0.01,
        far_clip: 10000.0,
        film,
        sampler: Sampler::default(),
    }
}

/// Converts a field of view along `axis` into the horizontal one (Mitsuba 3
/// `src/render/sensor.cpp`).
pub(crate) fn fov_to_x(fov_deg: f64, axis: &str, aspect: f64) -> f64 {
    let t = (fov_deg.to_radians() / 2.0).tan();
    let axis = match axis {
        "smaller" => {
            if aspect > 1.0 {
                "y"
            } else {
                "x"
            }
        }
        "larger" => {
            if aspect > 1.0 {
                "x"
            } else {
                "y"
            }
        }
        a => a,
    };
    match axis {
        "y" => 2.0 * (t * aspect).atan().to_degrees(),
        "diagonal" => {
            let width = 2.0 * t / (1.0 + 1.0 / (aspect * aspect)).sqrt();
            2.0 * (width / 2.0).atan().to_degrees()
        }
        _ => fov_deg,
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

/// A spectrum times a factor (as a 1 nm table over the visible range).
fn scaled(s: Spectrum, k: f32) -> Spectrum {
    let lambda: Vec<f32> = (360..=830).map(|l| l as f32).collect();
    let value = lambda.iter().map(|&l| k * s.eval(l)).collect();
    match PiecewiseLinear::new(lambda, value, Extrapolation::Zero) {
        Some(p) => Spectrum::piecewise(p),
        None => Spectrum::Constant(0.0),
    }
}

fn image_error(loc: &Location, name: &str, e: crate::image::ImageError) -> SceneError {
    use crate::image::ImageError as E;
    let kind = if matches!(e, E::Io { .. }) {
        ErrorKind::Io
    } else {
        ErrorKind::Image
    };
    err(loc, kind, format!("cannot load image \"{name}\": {e}"))
}
