//! `bsplinecurve`: round uniform cubic B-spline curves read from a text file (Mitsuba 3
//! `src/shapes/bsplinecurve.cpp`); file format, geometry and texture coordinates in
//! [`crate::geometry::curve`].
//!
//! | parameter | default |
//! |---|---|
//! | `filename` | the curve file (required; at least four control points per curve) |
//! | `to_world` | identity; moves the control points, not their radii |
//! | `flip_normals`, nested `bsdf` and `emitter` | as every shape |

use super::linearcurve::{FILENAME, curve};
use super::{BSDF, EMITTER, FLIP_NORMALS, MEDIA, TO_WORLD};
use crate::geometry::curve::CurveKind;
use crate::plugins::Plugin;
use crate::scene::ShapeDesc;
use crate::xml::{Builder, Params, SceneError};

/// The `bsplinecurve` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "bsplinecurve",
    summary: "Tubes swept by a sphere along uniform cubic B-splines (radius interpolated too), open ends (ours: a fine triangle mesh with exact normals and Mitsuba's uv).",
    params: &[TO_WORLD, FLIP_NORMALS, FILENAME, BSDF, EMITTER, MEDIA],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    curve(b, p, CurveKind::BSpline)
}
