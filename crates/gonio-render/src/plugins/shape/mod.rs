//! `<shape>` plugins (Mitsuba 3 `src/shapes/`). The runtime shapes are in [`crate::geometry`].
//!
//! What every shape shares lives here: the rows [`TO_WORLD`], [`FLIP_NORMALS`], [`BSDF`] and
//! [`EMITTER`] of each table, reading them (`common`, `assemble`: one nested or referenced
//! BSDF, by default Mitsuba's diffuse 0.5, or black when the shape emits; one nested `area`
//! emitter), the similarity check of the analytic shapes and the loading of `obj`/`ply` meshes
//! with the mesh cache (`mesh`).

pub mod bsplinecurve;
pub mod cube;
pub mod cylinder;
pub mod disk;
pub mod instance;
pub mod linearcurve;
pub mod merge;
pub mod obj;
pub mod ply;
pub mod rectangle;
pub mod sdfgrid;
pub mod serialized;
pub mod shapegroup;
pub mod sphere;

use crate::mesh as meshes;
use crate::plugins::{DefaultValue, ParamSpec, ParamType};
use crate::scene::{Geometry, ShapeDesc, TriangleMesh};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};
use glam::Affine3A;
use std::sync::Arc;

type Result<T> = std::result::Result<T, SceneError>;

/// `to_world`, shared by every shape.
pub const TO_WORLD: ParamSpec = ParamSpec::new(
    "to_world",
    ParamType::Transform,
    DefaultValue::None,
    "object to world (identity when absent)",
);
/// `flip_normals`, shared by every shape.
pub const FLIP_NORMALS: ParamSpec = ParamSpec::new(
    "flip_normals",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "flip the geometric and shading normals (and so the emitting side)",
);
/// The nested BSDF, shared by every shape.
pub const BSDF: ParamSpec = ParamSpec::new(
    "(nested bsdf)",
    ParamType::Bsdf,
    DefaultValue::None,
    "at most one nested or referenced BSDF; without one, diffuse 0.5 (black if the shape emits)",
);
/// The media on the two sides, shared by every shape.
pub const MEDIA: ParamSpec = ParamSpec::new(
    "interior, exterior",
    ParamType::Medium,
    DefaultValue::None,
    "the `<medium>` inside and outside the surface (`<ref name=\"interior\" id=\"...\"/>`); none: vacuum",
);
/// The nested emitter, shared by every shape.
pub const EMITTER: ParamSpec = ParamSpec::new(
    "(nested emitter)",
    ParamType::Emitter,
    DefaultValue::None,
    "at most one nested `area` or `directionalarea` emitter",
);
/// `face_normals`, shared by the meshes.
pub const FACE_NORMALS: ParamSpec = ParamSpec::new(
    "face_normals",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "shade with the triangles' normals, ignoring (and not computing) vertex normals",
);

/// The parameters every shape reads first.
pub(crate) struct Common {
    to_world: Affine3A,
    flip_normals: bool,
}

impl Common {
    /// Object to world.
    pub(crate) fn to_world(&self) -> &Affine3A {
        &self.to_world
    }
}

/// Reads `to_world` and `flip_normals`.
pub(crate) fn common(p: &mut Params<'_>) -> Result<Common> {
    let to_world = p.affine(TO_WORLD.name)?;
    let flip_normals = p.bool(FLIP_NORMALS.name, FLIP_NORMALS.default.bool())?;
    Ok(Common {
        to_world,
        flip_normals,
    })
}

/// A shape's `interior` and `exterior` media (row [`MEDIA`]).
pub(crate) fn shape_media<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
) -> Result<crate::medium::MediumInterface> {
    let (mut interior, mut exterior) = (None, None);
    for (i, prop) in p.objects(Tag::Medium)? {
        let slot = match prop.name.as_str() {
            "interior" => &mut interior,
            "exterior" => &mut exterior,
            other => {
                return Err(err(
                    &prop.loc,
                    ErrorKind::UnusedParameter,
                    format!(
                        "a <medium> named \"{other}\" in {} (a shape takes \"interior\" and \"exterior\")",
                        p.what()
                    ),
                ));
            }
        };
        *slot = Some(b.medium(i, &prop.value_loc)?);
    }
    Ok(crate::medium::MediumInterface::new(interior, exterior))
}

/// The shape of `geometry`: reads its nested BSDF and emitter, checks that no parameter is left
/// unread, then builds the emitter and finds the material.
pub(crate) fn assemble<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    common: Common,
    geometry: Geometry,
    face_normals: bool,
) -> Result<ShapeDesc> {
    let bsdfs = p.objects(Tag::Bsdf)?;
    let emitters = p.objects(Tag::Emitter)?;
    let sensors = p.objects(Tag::Sensor)?;
    let media = shape_media(b, p)?;
    p.finish()?;
    // A sensor nested in the shape (Mitsuba's `irradiancemeter`), placed with the shape.
    match sensors.as_slice() {
        [] => {}
        [(i, prop)] => {
            let loc = prop.value_loc.clone();
            if b.doc.objs[*i].ty != "irradiancemeter" {
                return Err(err(
                    &loc,
                    ErrorKind::Grammar,
                    format!(
                        "a <sensor type=\"{}\"> cannot be nested in a shape (only an irradiancemeter measures over one)",
                        b.doc.objs[*i].ty
                    ),
                ));
            }
            if !matches!(
                geometry,
                Geometry::Sphere { .. } | Geometry::Rectangle | Geometry::Disk | Geometry::Mesh(_)
            ) {
                return Err(err(
                    &loc,
                    ErrorKind::Grammar,
                    format!(
                        "an irradiancemeter cannot measure over a {} (no area to sample)",
                        p.obj.ty
                    ),
                ));
            }
            b.in_shape = true;
            let sensor = b.build_plugin(crate::plugins::SENSOR_PLUGINS, *i);
            b.in_shape = false;
            b.shape_sensor = Some((sensor?, loc));
        }
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "more than one sensor nested in a shape",
            ));
        }
    }
    // The textures of the emitter's radiance that read the hit (logged while it is built).
    let hits_before = b.hit_log.len();
    let emitter = match emitters.as_slice() {
        [] => None,
        [(e, prop)] => Some(super::emitter::area(b, *e, &prop.value_loc)?),
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "more than one emitter attached to a shape",
            ));
        }
    };
    let bsdf = match bsdfs.as_slice() {
        [] => None,
        [(i, prop)] => Some((*i, &prop.value_loc)),
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "more than one bsdf attached to a shape",
            ));
        }
    };
    let emitter_hits = b.hit_log[hits_before..].to_vec();
    let emitter = match emitter {
        Some(mut e) if !emitter_hits.is_empty() => {
            let binding = super::texture::mesh_attribute::binding(b, &emitter_hits, &geometry, &p.obj.ty)?;
            e.hit = Some(std::sync::Arc::new(binding));
            b.hit_emitters.push(emitter_hits[0].1.clone());
            Some(e)
        }
        e => e,
    };
    let material = b.shape_material(bsdf, emitter.is_some())?;
    let material =
        super::texture::mesh_attribute::bind(b, material, bsdf.map(|(i, _)| i), &geometry, &p.obj.ty)?;
    let desc = ShapeDesc {
        geometry,
        to_world: common.to_world,
        flip_normals: common.flip_normals,
        face_normals,
        outside_only: false,
        material,
        media,
        emitter,
        id: p.obj.id.clone(),
    };
    // A transform or radius that overflows (a radius of 1e308 is +inf in f32) is refused here,
    // where the shape's file and line are known.
    let name = format!("<shape type=\"{}\">", p.obj.ty);
    crate::geometry::shape::WorldShape::check_placement(&desc, &name)
        .map_err(|e| err(&p.obj.loc, ErrorKind::BadValue, e.to_string()))?;
    Ok(desc)
}

/// A sphere keeps its shape only under rotation, uniform scale and translation.
pub(crate) fn check_similarity(p: &Params<'_>, m: &Affine3A) -> Result<()> {
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
            &p.obj.loc,
            ErrorKind::BadValue,
            format!(
                "<shape type=\"{}\"> to_world has a non-uniform scale or shear (axis lengths {x}, {y}, {z}); use a mesh",
                p.obj.ty
            ),
        ));
    }
    Ok(())
}

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum MeshFormat {
    /// Wavefront OBJ ([`meshes::load_obj`]).
    Obj,
    /// Stanford PLY ([`meshes::load_ply`]).
    Ply,
    /// Mesh `shape_index` of a Mitsuba serialized file ([`meshes::serialized::load_serialized`]).
    Serialized {
        /// Which mesh of the file.
        shape_index: u32,
    },
}

/// The mesh named by `filename` (relative to the scene file), loaded once per (file, mesh of the
/// file, `flip_tex_coords`, `face_normals`). Mitsuba smooths meshes without normals unless
/// `face_normals` is set.
pub(crate) fn mesh<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    filename: &ParamSpec,
    format: MeshFormat,
    flip_tex_coords: bool,
    face_normals: bool,
) -> Result<Arc<TriangleMesh>> {
    let Some((name, loc)) = p.string_opt(filename.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            format!("<shape type=\"{}\"> needs a filename", p.obj.ty),
        ));
    };
    let path = b.resolve_file(p, name);
    let index = match format {
        MeshFormat::Serialized { shape_index } => shape_index,
        MeshFormat::Obj | MeshFormat::Ply => 0,
    };
    let mut attributes = None;
    let m = b.cached_mesh((path.clone(), index, flip_tex_coords, face_normals), || {
        let r = match format {
            MeshFormat::Obj => meshes::load_obj(&path, flip_tex_coords),
            MeshFormat::Ply => meshes::load_ply_with_attributes(&path, flip_tex_coords).map(|(m, a)| {
                attributes = Some(a);
                m
            }),
            MeshFormat::Serialized { shape_index } => {
                meshes::serialized::load_serialized(&path, shape_index, face_normals)
            }
        };
        let mut m = r.map_err(|e| {
            let kind = if e.is_io() { ErrorKind::Io } else { ErrorKind::Mesh };
            err(loc, kind, format!("cannot load mesh \"{name}\": {e}"))
        })?;
        if !face_normals && m.normals.is_empty() {
            m.normals = meshes::vertex_normals(&m);
        }
        Ok(m)
    })?;
    // The file's attributes, kept while the scene is read (a shape keeps those it uses).
    if let Some(a) = attributes.filter(|a| !a.list.is_empty()) {
        b.mesh_attributes.insert(Arc::as_ptr(&m) as usize, a);
    }
    Ok(m)
}

/// The builder of a shape read from a mesh file (`obj`, `ply`): the common shape parameters,
/// `face_normals`, the file named by `filename` and whether to flip v (`flip_tex_coords`, whose
/// default differs between the formats, as in Mitsuba).
pub(crate) fn mesh_file<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    filename: &ParamSpec,
    flip_tex_coords: &ParamSpec,
    format: MeshFormat,
) -> Result<ShapeDesc> {
    let c = common(p)?;
    let face_normals = p.bool(FACE_NORMALS.name, FACE_NORMALS.default.bool())?;
    let flip = p.bool(flip_tex_coords.name, flip_tex_coords.default.bool())?;
    let m = mesh(b, p, filename, format, flip, face_normals)?;
    assemble(b, p, c, Geometry::Mesh(m), face_normals)
}
