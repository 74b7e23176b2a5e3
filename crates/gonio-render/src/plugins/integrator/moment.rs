//! `moment`: first and second moments of nested integrators (Mitsuba 3
//! `src/integrators/moment.cpp`), written as film layers: per nested integrator its image in CIE
//! XYZ (`name.X, .Y, .Z`, after its own layers), then `m2_` and the name of every one of those
//! channels for the per-sample square, so that `m2_c − c²` is a pixel's sample variance. The
//! channels and the estimator are in `crate::integrator::layers`.
//!
//! | parameter | meaning |
//! |---|---|
//! | (nested `<integrator>`s) | the integrators measured (named by their `name` attribute, `_arg_N` when unnamed); the first one's image is the film's `R, G, B` |

use super::aov::{nested_integrators, wrapper};
use crate::plugins::Plugin;
use crate::scene::{IntegratorDesc, LayersDesc};
use crate::xml::{Builder, Params, SceneError};

/// The `moment` plugin.
pub static PLUGIN: Plugin<IntegratorDesc> = Plugin {
    name: "moment",
    summary: "First and second moments of nested integrators (their XYZ image and its square per sample) as extra film layers.",
    params: &[],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let nested = nested_integrators(b, p)?;
    let layers = LayersDesc::Moment {
        nested: nested.clone(),
    };
    Ok(wrapper(&nested, layers))
}
