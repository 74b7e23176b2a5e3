//! `linearcurve`: round linear curves read from a text file (Mitsuba 3
//! `src/shapes/linearcurve.cpp`); file format, geometry and texture coordinates in
//! [`crate::geometry::curve`].
//!
//! | parameter | default |
//! |---|---|
//! | `filename` | the curve file (required) |
//! | `to_world` | identity; moves the control points, not their radii |
//! | `flip_normals`, nested `bsdf` and `emitter` | as every shape |

use super::{BSDF, EMITTER, FLIP_NORMALS, MEDIA, TO_WORLD};
use crate::geometry::curve::CurveKind;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::ShapeDesc;
use crate::xml::{Builder, Params, SceneError};

/// `filename`, shared by the curve shapes.
pub(crate) const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the curve file: one control point \"x y z radius\" per line, an empty line between curves (required)",
);

/// The `linearcurve` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "linearcurve",
    summary: "Tubes along straight segments between control points, with spherical joints and end caps (ours: a fine triangle mesh with exact normals and Mitsuba's uv).",
    params: &[TO_WORLD, FLIP_NORMALS, FILENAME, BSDF, EMITTER, MEDIA],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    curve(b, p, CurveKind::Linear)
}

/// The builder of both curve shapes.
pub(crate) fn curve<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    kind: CurveKind,
) -> Result<ShapeDesc, SceneError> {
    use crate::xml::{ErrorKind, err};
    let mut c = super::common(p)?;
    let Some((name, loc)) = p.string_opt(FILENAME.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            format!("<shape type=\"{}\"> needs a filename", p.obj.ty),
        ));
    };
    let path = b.resolve_file(p, name);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        err(
            loc,
            ErrorKind::Io,
            format!("cannot read curve file \"{name}\" ({}): {e}", path.display()),
        )
    })?;
    let curves = crate::geometry::curve::parse_curves(&text, kind, c.to_world())
        .map_err(|e| err(loc, ErrorKind::Mesh, format!("curve file \"{name}\": {e}")))?;
    let mesh = crate::geometry::curve::tessellate(&curves, kind);
    // The control points are already in world space.
    c.to_world = glam::Affine3A::IDENTITY;
    // Mitsuba's curves (Embree's round curves) are never hit from inside: light that enters a
    // fibre (the `hair` model's transmission) leaves through it.
    let mut desc = super::assemble(
        b,
        p,
        c,
        crate::scene::Geometry::Mesh(std::sync::Arc::new(mesh)),
        false,
    )?;
    desc.outside_only = true;
    Ok(desc)
}
