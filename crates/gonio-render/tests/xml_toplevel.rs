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

/// `merge` (Mitsuba 3 merges the nested meshes that share a BSDF, for speed) places its shapes as
/// if written one by one: the same scene shapes, in order, with their own BSDFs and emitters,
/// also nested and inside a `shapegroup`; elsewhere it is refused by name.
#[test]
fn merge_places_its_shapes_one_by_one() {
    let shapes = r#"<shape type="sphere"><bsdf type="conductor"/></shape>
        <shape type="rectangle"><bsdf type="dielectric"/></shape>
        <shape type="disk"><emitter type="area"/></shape>"#;
    let plain = load(shapes).unwrap();
    let merged = load(&format!(
        r#"<shape type="merge">{}</shape>"#,
        shapes
            .replacen(
                "<shape type=\"disk\">",
                "<shape type=\"merge\"><shape type=\"disk\">",
                1
            )
            .replacen(
                "<emitter type=\"area\"/></shape>",
                "<emitter type=\"area\"/></shape></shape>",
                1
            )
    ))
    .unwrap();
    assert_eq!(merged.shapes.len(), 3);
    for (a, b) in plain.shapes.iter().zip(&merged.shapes) {
        assert_eq!(format!("{:?}", a.geometry), format!("{:?}", b.geometry));
        assert_eq!(a.emitter.is_some(), b.emitter.is_some());
        assert_eq!(
            format!("{:?}", plain.materials[a.material]),
            format!("{:?}", merged.materials[b.material])
        );
    }
    let grouped = load(
        r#"<shape type="shapegroup" id="g"><shape type="merge"><shape type="sphere"/><shape type="rectangle"/></shape></shape>
        <shape type="instance"><ref id="g"/></shape>"#,
    )
    .unwrap();
    assert_eq!(grouped.shapes.len(), 2, "one instanced shape per merged member");
    let e = load(r#"<shape type="merge"><float name="radius" value="2"/><shape type="sphere"/></shape>"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("radius"), "{e}");
    let e = load(r#"<shape type="instance"><shape type="merge"><shape type="sphere"/></shape></shape>"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("merge") && e.contains(":1:"), "{e}");
}
