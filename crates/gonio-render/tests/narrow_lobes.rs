//! Lights left to BSDF sampling at narrow lobes (`narrow_lobes`, `emitter::Lights::left_to_bsdf`)
//! against next-event estimation at every vertex (Mitsuba's way).
//!
//! A rough glass sphere (Beckmann α = 0.02, as Mitsuba's `bsdf_roughdielectric_glass` preview)
//! and a rough gold one (GGX α = 0.005: GGX's heavier tails need a narrower lobe) on a diffuse
//! floor under the preview's environment map (its largest density 5.2 per sr), with a small lamp
//! beside them: at the spheres the map is not sampled, the lamp is. Both estimators are unbiased: the
//! image means agree within four standard errors of independent renders, and leaving the map to
//! BSDF sampling there costs no noise (what it saves is the light samples' time).

use crate::render_stats::{FLOOR_AND_LAMP, MUSEUM, SENSOR, prepare, same_mean_less_noise};

fn scene(narrow: bool, split_lights: u32) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path">
        <boolean name="narrow_lobes" value="{narrow}"/>
        <integer name="split_lights" value="{split_lights}"/>
    </integrator>
    {SENSOR}
    <shape type="sphere">
        <point name="center" value="-0.6, 0.5, 0"/><float name="radius" value="0.5"/>
        <bsdf type="roughdielectric"><float name="alpha" value="0.02"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.6, 0.5, 0.2"/><float name="radius" value="0.5"/>
        <bsdf type="roughconductor"><string name="material" value="Au"/><string name="distribution" value="ggx"/><float name="alpha" value="0.005"/></bsdf>
    </shape>
    {FLOOR_AND_LAMP}
    {MUSEUM}
</scene>"#
    )
}

/// Every light sampled at each vertex (`split_lights` 2, the default) and one chosen per vertex
/// (0): the same mean within four standard errors, and the pixels' variance within 1.25 times
/// next-event estimation's everywhere.
#[test]
fn narrow_lobes_keep_the_expectation() {
    for split_lights in [2, 0] {
        let on = prepare(&scene(true, split_lights), false);
        let off = prepare(&scene(false, split_lights), false);
        assert!(on.scene.integrator.narrow_lobes && !off.scene.integrator.narrow_lobes);
        same_mean_less_noise(
            &on,
            &off,
            16,
            &format!("rough spheres under the museum, split_lights {split_lights}"),
            1.25,
        );
    }
}

/// A rough metal sphere (Beckmann α = 0.2) under a constant sky (its density 1/4π everywhere,
/// which the lobe resolves: 0.05/(4π α²) ≈ 0.099 ≥ 0.080), filling most of the frame: BSDF
/// sampling alone is nearly free of noise there, so the means are compared to a fraction of a
/// percent, and the pixel variance is at most 0.6 times next-event estimation's (measured 0.28:
/// the sky's light samples only add noise to such a lobe). Had the light's samples been skipped
/// without giving the BSDF samples their whole weight, the image would lose the light samples'
/// share of the power heuristic (7 % here, a hundred standard errors).
#[test]
fn narrow_lobes_keep_the_expectation_under_a_constant_sky() {
    let scene = |narrow: bool| {
        format!(
            r#"<scene version="3.0.0">
    <integrator type="path"><boolean name="narrow_lobes" value="{narrow}"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="sphere">
        <float name="radius" value="1"/>
        <bsdf type="roughconductor"><string name="material" value="none"/><float name="alpha" value="0.2"/></bsdf>
    </shape>
    <emitter type="constant"/>
</scene>"#
        )
    };
    let on = prepare(&scene(true), false);
    let off = prepare(&scene(false), false);
    same_mean_less_noise(&on, &off, 16, "a rough metal sphere under a constant sky", 0.6);
}
