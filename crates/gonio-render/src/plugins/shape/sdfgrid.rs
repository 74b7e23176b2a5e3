//! `sdfgrid`: a signed distance function on a grid (Mitsuba 3 `src/shapes/sdfgrid.cpp`); the
//! grid file, its intersection and normals are in [`crate::geometry::sdfgrid`].
//!
//! | parameter | default |
//! |---|---|
//! | `filename` | Mitsuba's grid `.vol` file with one channel (required) |
//! | `normals` | `smooth` (or `analytic`) |
//! | `to_world`, `flip_normals`, nested `bsdf` | as every shape (no emitter: an SDF grid cannot emit) |

use super::{BSDF, FLIP_NORMALS, TO_WORLD, assemble, common};
use crate::geometry::sdfgrid::{SdfGrid, SdfNormals, read_vol};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};
use std::sync::Arc;

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the grid, a one-channel Mitsuba `.vol` file mapped to the unit cube (required)",
);
const NORMALS: ParamSpec = ParamSpec::new(
    "normals",
    ParamType::String,
    DefaultValue::Str("smooth"),
    "shading normals: `smooth` (blended voxel gradients) or `analytic` (the hit voxel's gradient)",
);

/// The `sdfgrid` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "sdfgrid",
    summary: "The zero level set of a signed distance function sampled on a grid over the unit cube (trilinear interpolation, exact cubic root per voxel); no uv, cannot emit.",
    params: &[TO_WORLD, FLIP_NORMALS, FILENAME, NORMALS, BSDF],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let c = common(p)?;
    let normals = match p.choice(NORMALS.name, NORMALS.default.str(), &["smooth", "analytic"])? {
        "analytic" => SdfNormals::Analytic,
        _ => SdfNormals::Smooth,
    };
    let Some((name, loc)) = p.string_opt(FILENAME.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::Grammar,
            "<shape type=\"sdfgrid\"> needs a filename",
        ));
    };
    if let Some((_, prop)) = p.objects(Tag::Emitter)?.first() {
        return Err(err(
            &prop.loc,
            ErrorKind::BadValue,
            "<shape type=\"sdfgrid\"> cannot be an area emitter",
        ));
    }
    let path = b.resolve_file(p, name);
    let bytes = std::fs::read(&path).map_err(|e| {
        err(
            loc,
            ErrorKind::Io,
            format!("cannot read SDF grid \"{name}\" ({}): {e}", path.display()),
        )
    })?;
    let grid = read_vol(&bytes)
        .and_then(|v| SdfGrid::new(v, normals))
        .map_err(|e| err(loc, ErrorKind::BadValue, format!("SDF grid \"{name}\": {e}")))?;
    assemble(b, p, c, Geometry::SdfGrid(Arc::new(grid)), false)
}
