//! `<rfilter>` plugins (reconstruction filters, nested in a film; Mitsuba 3 `src/rfilters/`).
//! The runtime filters are in [`crate::film`].

pub mod r#box;
pub mod gaussian;
pub mod lanczos;
pub mod mitchell;
pub mod tent;

use crate::xml::{Params, SceneError};

/// A filter's size parameter: finite and positive.
fn positive<'d>(p: &mut Params<'d>, spec: &crate::plugins::ParamSpec) -> Result<f32, SceneError> {
    Ok(p.float_checked(spec.name, spec.default.float(), |v| v > 0.0, "must be positive")? as f32)
}
