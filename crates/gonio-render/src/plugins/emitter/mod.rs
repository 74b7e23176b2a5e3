//! `<emitter>` plugins (Mitsuba 3 `src/emitters/`). The runtime lights are in
//! [`crate::emitter`]. An `area` or `directionalarea` emitter is nested in a shape, or declared in the scene with an
//! `id` and referenced by one shape ([`area`]); the others stand in the scene (`build`). Colours and numbers are × D65, as in spectral Mitsuba.

pub mod area;
pub mod constant;
pub mod directional;
pub mod directionalarea;
pub mod envmap;
pub mod point;
pub mod projector;
pub mod spot;
pub mod sunsky;

use crate::plugins::{AREA_EMITTER_PLUGINS, DefaultValue, EMITTER_PLUGINS, ParamSpec, ParamType, Plugin};
use crate::scene::{AreaEmitterDesc, EmitterDesc};
use crate::xml::{Builder, ErrorKind, Location, Params, SceneError, Tag, err, unknown_plugin};

/// The medium an emitter is in, shared by every emitter.
pub const MEDIUM: ParamSpec = ParamSpec::new(
    "(nested medium)",
    ParamType::Medium,
    DefaultValue::None,
    "the `<medium>` the emitter is in, as Mitsuba's emitters take one: read and checked, unused (Mitsuba's volumetric path tracers never read it either: a shadow ray takes the medium at its origin)",
);

/// Runs an emitter plugin, having read its nested medium (row [`MEDIUM`]).
fn run_emitter<T>(b: &mut Builder<'_>, plugin: &'static Plugin<T>, idx: usize) -> Result<T, SceneError> {
    let mut p = Params::with_specs(b.doc, idx, plugin.params);
    match p.objects(Tag::Medium)?.as_slice() {
        [] => {}
        [(i, prop)] => {
            b.medium(*i, &prop.value_loc)?;
        }
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "more than one <medium> in an emitter",
            ));
        }
    }
    let v = (plugin.build)(b, &mut p)?;
    p.finish()?;
    Ok(v)
}

/// Whether the `<emitter>` object is one a shape carries (`area`, `directionalarea`).
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
    run_emitter(b, plugin, idx)
}

/// Builds the emitter object `idx` nested in a shape (at `loc`).
pub(crate) fn area(b: &mut Builder<'_>, idx: usize, loc: &Location) -> Result<AreaEmitterDesc, SceneError> {
    let obj = &b.doc.objs[idx];
    let Some(plugin) = Plugin::find(AREA_EMITTER_PLUGINS, &obj.ty) else {
        return Err(err(
            &obj.ty_loc,
            ErrorKind::UnknownPlugin,
            format!(
                "a shape can only carry an \"area\" or \"directionalarea\" emitter, found \"{}\"",
                obj.ty
            ),
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
    let e = run_emitter(b, plugin, idx)?;
    b.leave();
    Ok(e)
}
