//! `<emitter>` plugins (Mitsuba 3 `src/emitters/`). The runtime lights are in
//! [`crate::emitter`]. An `area` emitter is nested in a shape, or declared in the scene with an
//! `id` and referenced by one shape ([`area`]); the others stand in the scene (`build`). Colours and numbers are × D65, as in spectral Mitsuba.

pub mod area;
pub mod constant;
pub mod directional;
pub mod envmap;
pub mod point;
pub mod projector;
pub mod spot;

use crate::plugins::{AREA_EMITTER_PLUGINS, EMITTER_PLUGINS, Plugin};
use crate::scene::{AreaEmitterDesc, EmitterDesc};
use crate::xml::{Builder, ErrorKind, Location, SceneError, err, unknown_plugin};

/// Whether the `<emitter>` object is one a shape carries (`area`).
pub(crate) fn is_area(obj: &crate::xml::Obj) -> bool {
    Plugin::find(AREA_EMITTER_PLUGINS, &obj.ty).is_some()
}

/// Builds the `<emitter>` object `idx` standing in the scene.
pub(crate) fn build(b: &mut Builder<'_>, idx: usize) -> Result<EmitterDesc, SceneError> {
    let obj = &b.doc.objs[idx];
    if Plugin::find(AREA_EMITTER_PLUGINS, &obj.ty).is_some() {
        return Err(err(
            &obj.loc,
            ErrorKind::Grammar,
            format!(
                "an \"{}\" emitter must be nested in a <shape> (or given an id and referenced by one)",
                obj.ty
            ),
        ));
    }
    let Some(plugin) = Plugin::find(EMITTER_PLUGINS, &obj.ty) else {
        let mut names = Plugin::names(AREA_EMITTER_PLUGINS);
        names.extend(Plugin::names(EMITTER_PLUGINS));
        return Err(unknown_plugin(obj, &names));
    };
    b.run_plugin(plugin, idx)
}

/// Builds the emitter object `idx` nested in a shape (at `loc`).
pub(crate) fn area(b: &mut Builder<'_>, idx: usize, loc: &Location) -> Result<AreaEmitterDesc, SceneError> {
    let obj = &b.doc.objs[idx];
    let Some(plugin) = Plugin::find(AREA_EMITTER_PLUGINS, &obj.ty) else {
        return Err(err(
            &obj.ty_loc,
            ErrorKind::UnknownPlugin,
            format!("a shape can only carry an \"area\" emitter, found \"{}\"", obj.ty),
        ));
    };
    // Mitsuba's `AreaLight::set_shape`: one emitter, one shape.
    if let Some(first) = b.attached_emitters.get(&idx) {
        return Err(err(
            loc,
            ErrorKind::Grammar,
            format!(
                "this \"{}\" emitter{} is already attached to the shape at {first}; an area emitter can be attached to a single shape",
                obj.ty,
                obj.id
                    .as_ref()
                    .map(|i| format!(" (id \"{i}\")"))
                    .unwrap_or_default()
            ),
        ));
    }
    b.attached_emitters.insert(idx, loc.clone());
    b.enter(idx, loc)?;
    let e = b.run_plugin(plugin, idx)?;
    b.leave();
    Ok(e)
}
