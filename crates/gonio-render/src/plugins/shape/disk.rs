//! `disk`: the unit disk in the plane z = 0, normal +z (Mitsuba 3 `src/shapes/disk.cpp`), placed
//! by any affine `to_world`: a non-uniform scale or a shear makes it an ellipse, as Mitsuba
//! renders it (its documentation forbids non-uniform scales, its code intersects in object space
//! and takes them). The area is π·|∂p/∂x × ∂p/∂y| (Mitsuba's π·|∂p/∂x|·|∂p/∂y| is the same unless
//! the axes are sheared), the normal the transformed +z as a normal, so the scale along z only
//! decides its side (through the sign of the determinant).

use super::{BSDF, EMITTER, FLIP_NORMALS, MEDIA, TO_WORLD, assemble, common};
use crate::plugins::Plugin;
use crate::scene::{Geometry, ShapeDesc};
use crate::xml::{Builder, Params, SceneError};

/// The `disk` plugin.
pub static PLUGIN: Plugin<ShapeDesc> = Plugin {
    name: "disk",
    summary: "Unit disk in z = 0 with normal +z, placed by `to_world` (any affine map: an ellipse under a non-uniform scale).",
    params: &[TO_WORLD, FLIP_NORMALS, BSDF, EMITTER, MEDIA],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<ShapeDesc, SceneError> {
    let c = common(p)?;
    assemble(b, p, c, Geometry::Disk, false)
}
