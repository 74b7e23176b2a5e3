//! `stokes`: the Stokes vector at the sensor (Mitsuba 3 `src/integrators/stokes.cpp`). It wraps
//! one nested integrator (`path`, `direct`, `depth`), renders it polarized and writes its image
//! as `R`, `G`, `B` followed by the layers `S0.R, S0.G, S0.B, S1.R, … S3.B`: the four Stokes
//! components, each turned into linear sRGB by the same wavelength estimator as the image.
//!
//! S0 is the radiance, S1 horizontal minus vertical linear polarization, S2 +45° minus −45°,
//! S3 right minus left circular, in the basis Mitsuba's `stokes` uses: the beam travelling
//! towards the camera (−d for the camera ray d) with its x-axis along d × up, `up` the sensor's
//! +y axis in world space (so "horizontal" is the image's horizontal).
//!
//! | parameter | meaning |
//! |---|---|
//! | (nested `<integrator>`) | the integrator whose value is measured (required, exactly one) |

use crate::plugins::{INTEGRATOR_PLUGINS, Plugin};
use crate::scene::IntegratorDesc;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

/// The `stokes` plugin.
pub static PLUGIN: Plugin<IntegratorDesc> = Plugin {
    name: "stokes",
    summary: "Polarized render of a nested integrator, writing its Stokes vector as the layers S0.R … S3.B after R, G, B.",
    params: &[],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let Some(inner) = b.nested_one(p, Tag::Integrator, INTEGRATOR_PLUGINS, "stokes integrator")? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "<integrator type=\"stokes\"> needs a nested <integrator> (e.g. <integrator type=\"path\"/>)",
        ));
    };
    if inner.stokes {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "<integrator type=\"stokes\"> cannot nest another stokes integrator",
        ));
    }
    if inner.layers.is_some() {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "<integrator type=\"stokes\"> cannot wrap an aov or moment integrator (nest stokes inside them instead)",
        ));
    }
    Ok(IntegratorDesc {
        stokes: true,
        polarized: true,
        ..inner
    })
}
