//! Objects declared at the top of a scene with an `id` and referenced later, as Mitsuba's
//! documentation scenes do (`<sampler id="my_sampler">` … `<ref id="my_sampler"/>` in the sensor).

use gonio_render::scene::{FilterDesc, SamplerKind};

fn load(body: &str) -> Result<gonio_render::scene::Scene, gonio_render::xml::SceneError> {
    gonio_render::xml::load_scene_str(&format!(r#"<scene version="3.0.0">{body}</scene>"#), ".", &[])
}

#[test]
fn top_level_sampler_film_and_filter_are_used_where_referenced() {
    let s = load(
        r#"<sampler type="stratified" id="s"><integer name="sample_count" value="25"/></sampler>
        <rfilter type="tent" id="f"/>
        <film type="hdrfilm" id="film"><integer name="width" value="40"/><integer name="height" value="30"/>
            <ref id="f"/></film>
        <sensor type="perspective"><ref id="s"/><ref id="film"/></sensor>"#,
    )
    .unwrap();
    let sensor = &s.sensor;
    assert!(
        matches!(sensor.sampler.kind, SamplerKind::Stratified { .. }),
        "{:?}",
        sensor.sampler.kind
    );
    assert_eq!(sensor.sampler.sample_count, 25);
    assert_eq!((sensor.film.width, sensor.film.height), (40, 30));
    assert!(
        matches!(sensor.film.filter, FilterDesc::Tent { .. }),
        "{:?}",
        sensor.film.filter
    );
}

#[test]
fn an_unreferenced_top_level_sampler_is_still_an_error() {
    let e = load(r#"<sampler type="independent" id="unused"/>"#)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("<sampler> must be nested in a sensor") && e.contains(":1:"),
        "{e}"
    );
}

#[test]
fn a_top_level_area_emitter_is_attached_to_the_shape_that_references_it() {
    // Mitsuba's `scenes/cbox/cbox-rgb.xml`: the emitter is declared after the shape that uses it.
    let s = load(
        r#"<shape type="rectangle" id="light"><ref id="area-emitter"/></shape>
        <shape type="sphere"/>
        <emitter type="area" id="area-emitter"><rgb name="radiance" value="18.4, 11.0, 2.75"/></emitter>"#,
    )
    .unwrap();
    assert_eq!(s.shapes.len(), 2);
    assert!(s.shapes[0].emitter.is_some(), "the rectangle emits");
    assert!(s.shapes[1].emitter.is_none(), "the sphere does not");
    assert!(s.emitters.is_empty(), "no emitter stands on its own");
}

#[test]
fn an_area_emitter_attached_twice_or_to_nothing_is_an_error() {
    let e = load(
        r#"<emitter type="area" id="e"/>
        <shape type="sphere"><ref id="e"/></shape>
        <shape type="sphere"><ref id="e"/></shape>"#,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("already attached") && e.contains("single shape") && e.contains(":3:"),
        "{e}"
    );
    let e = load(r#"<emitter type="area" id="e"/>"#).unwrap_err().to_string();
    assert!(
        e.contains("must be nested in a <shape>") && e.contains(":1:"),
        "{e}"
    );
}
