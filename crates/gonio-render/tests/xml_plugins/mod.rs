//! Every plugin the reader knows, with its defaults and parameters, and the materials' per-hit
//! BSDFs.

use glam::{Vec2, Vec3};
use gonio_core::bsdf::BsdfContext;
use gonio_core::{BsdfFlags, Ior, SampledWavelengths, Spectrum};
use gonio_render::material::{
    BlendMaterial, ConductorMaterial, DielectricMaterial, DiffuseMaterial, Material, PlasticMaterial,
    ThinDielectricMaterial,
};
use gonio_render::scene::{EmitterDesc, FilterDesc, Geometry, SamplerKind, Scene};
use gonio_render::texture::Texture;
use gonio_render::xml::{load_bsdf_str, load_scene_str};
use std::f32::consts::FRAC_1_PI;
use std::path::PathBuf;

/// The integrators' names and settings, and what `--mitsuba-estimators` restores.
mod integrators;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn load_full(text: &str) -> Scene {
    load_scene_str(text, data(), &[]).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn load(body: &str) -> Scene {
    load_full(&format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{body}\n</scene>"
    ))
}

fn sensor(body: &str) -> Scene {
    load_full(&format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">{body}</sensor>\n</scene>"
    ))
}

/// f(wi, wo) at normal incidence/exitance, one wavelength.
fn f_normal(m: &Material, uv: Vec2, lambda: f32) -> f32 {
    let wl = SampledWavelengths::fixed(lambda);
    m.with_bsdf(uv, |b| b.eval(&BsdfContext::default(), Vec3::Z, Vec3::Z, &wl)[0])
}

#[test]
fn integrator_path() {
    let s = load_full(
        "<scene version=\"3.0.0\"><integrator type=\"path\"/><sensor type=\"perspective\"/></scene>",
    );
    assert_eq!((s.integrator.max_depth, s.integrator.rr_depth), (-1, 5));
    assert!(!s.integrator.hide_emitters && s.integrator.thin_shadows && s.integrator.caustic_paths);
    let s = load_full(
        r#"<scene version="3.0.0"><integrator type="path">
            <integer name="max_depth" value="3"/><integer name="rr_depth" value="2"/>
            <boolean name="hide_emitters" value="TRUE"/><boolean name="thin_shadows" value="false"/>
            <boolean name="caustic_paths" value="false"/>
            <integer name="samples_per_pass" value="4"/><float name="timeout" value="10"/>
        </integrator><sensor type="perspective"/></scene>"#,
    );
    assert_eq!((s.integrator.max_depth, s.integrator.rr_depth), (3, 2));
    assert!(s.integrator.hide_emitters && !s.integrator.thin_shadows && !s.integrator.caustic_paths);
}

#[test]
fn sensor_defaults_and_fov_axes() {
    let s = sensor("");
    assert_eq!((s.sensor.film.width, s.sensor.film.height), (768, 576));
    assert_eq!(s.sensor.film.filter, FilterDesc::Gaussian { stddev: 0.5 });
    assert_eq!(s.sensor.sampler.kind, SamplerKind::Independent);
    assert_eq!((s.sensor.sampler.sample_count, s.sensor.sampler.seed), (4, 0));
    // focal_length 50mm at 768×576 → 38.1848° (Mitsuba 3 src/render/sensor.cpp).
    assert!(
        (s.sensor.fov_x_deg - 38.1848).abs() < 1e-3,
        "{}",
        s.sensor.fov_x_deg
    );
    let s = sensor("<string name=\"focal_length\" value=\"50mm\"/>");
    assert!((s.sensor.fov_x_deg - 38.1848).abs() < 1e-3);
    let s = sensor("<string name=\"focal_length\" value=\"28\"/>");
    assert!(
        s.sensor.fov_x_deg > 60.0 && s.sensor.fov_x_deg < 70.0,
        "{}",
        s.sensor.fov_x_deg
    );

    let film = "<film type=\"hdrfilm\"><integer name=\"width\" value=\"200\"/><integer name=\"height\" value=\"100\"/></film>";
    let fov = |axis: &str| {
        sensor(&format!(
            "<float name=\"fov\" value=\"30\"/><string name=\"fov_axis\" value=\"{axis}\"/>{film}"
        ))
        .sensor
        .fov_x_deg as f64
    };
    let t = 15f64.to_radians().tan();
    assert!((fov("x") - 30.0).abs() < 1e-4);
    assert!((fov("y") - 2.0 * (2.0 * t).atan().to_degrees()).abs() < 1e-4);
    assert!((fov("diagonal") - 2.0 * (t / (1.25f64).sqrt()).atan().to_degrees()).abs() < 1e-4);
    assert!((fov("smaller") - fov("y")).abs() < 1e-6);
    assert!((fov("larger") - 30.0).abs() < 1e-6);

    let s = sensor(
        r#"<float name="fov" value="45"/><float name="near_clip" value="0.5"/><float name="far_clip" value="50"/>
        <transform name="to_world"><translate z="-3"/></transform>
        <sampler type="stratified"><integer name="sample_count" value="16"/><integer name="seed" value="7"/><boolean name="jitter" value="false"/></sampler>
        <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/>
            <string name="pixel_format" value="rgba"/><string name="component_format" value="float32"/>
            <string name="file_format" value="openexr"/><rfilter type="tent"><float name="radius" value="1.5"/></rfilter></film>"#,
    );
    assert_eq!((s.sensor.near_clip, s.sensor.far_clip), (0.5, 50.0));
    assert_eq!(
        s.sensor.to_world.transform_point3(Vec3::ZERO),
        Vec3::new(0.0, 0.0, -3.0)
    );
    assert_eq!(s.sensor.sampler.kind, SamplerKind::Stratified { jitter: false });
    assert_eq!((s.sensor.sampler.sample_count, s.sensor.sampler.seed), (16, 7));
    assert_eq!(s.sensor.film.filter, FilterDesc::Tent { radius: 1.5 });
    let s = sensor(
        "<sampler type=\"multijitter\"/><film type=\"hdrfilm\"><rfilter type=\"gaussian\"><float name=\"stddev\" value=\"0.25\"/></rfilter></film>",
    );
    assert_eq!(s.sensor.sampler.kind, SamplerKind::MultiJitter { jitter: true });
    assert_eq!(s.sensor.film.filter, FilterDesc::Gaussian { stddev: 0.25 });
    assert_eq!(s.sensor.film.filter.radius(), 1.0);
    let s = sensor("<film type=\"hdrfilm\"><rfilter type=\"box\"/></film>");
    assert_eq!(s.sensor.film.filter, FilterDesc::Box { radius: 0.5 });
}

#[test]
fn shapes() {
    let s = load(
        r#"<shape type="sphere"/>
<shape type="sphere"><point name="center" value="1, 2, 3"/><float name="radius" value="0.5"/>
    <transform name="to_world"><rotate y="1" angle="10"/><scale value="2"/></transform></shape>
<shape type="rectangle" id="r"><boolean name="flip_normals" value="true"/></shape>
<shape type="disk"><transform name="to_world"><scale x="1.5" y="2.5"/></transform></shape>
<shape type="cube"><boolean name="face_normals" value="true"/></shape>
<shape type="obj"><string name="filename" value="quad.obj"/></shape>
<shape type="ply"><string name="filename" value="quad_ascii.ply"/><boolean name="flip_tex_coords" value="true"/></shape>
<shape type="obj"><string name="filename" value="quad.obj"/><boolean name="flip_tex_coords" value="false"/></shape>
<shape type="obj"><string name="filename" value="two_tris.obj"/></shape>
<shape type="obj"><string name="filename" value="two_tris.obj"/><boolean name="face_normals" value="true"/></shape>"#,
    );
    assert_eq!(s.shapes.len(), 10);
    assert!(matches!(
        s.shapes[0].geometry,
        Geometry::Sphere {
            center: Vec3::ZERO,
            radius: 1.0
        }
    ));
    assert!(matches!(
        s.shapes[1].geometry,
        Geometry::Sphere { radius: 0.5, .. }
    ));
    assert!(s.shapes[2].flip_normals && s.shapes[2].id.as_deref() == Some("r"));
    assert!(matches!(s.shapes[2].geometry, Geometry::Rectangle));
    // An ellipse, as Mitsuba renders a disk under a non-uniform scale.
    assert!(matches!(s.shapes[3].geometry, Geometry::Disk));
    assert_eq!(s.shapes[3].to_world.matrix3.y_axis.y, 2.5);
    assert!(s.shapes[4].face_normals);
    let mesh = |i: usize| match &s.shapes[i].geometry {
        Geometry::Mesh(m) => m.clone(),
        g => panic!("{g:?}"),
    };
    assert_eq!(mesh(4).indices.len(), 12);
    // OBJ flips v by default: vt (0, 0) becomes (0, 1).
    let obj = mesh(5);
    assert_eq!(obj.indices.len(), 2);
    let i0 = obj.positions.iter().position(|p| *p == Vec3::ZERO).unwrap();
    assert_eq!(obj.uvs[i0], Vec2::new(0.0, 1.0));
    let obj_noflip = mesh(7);
    let j0 = obj_noflip
        .positions
        .iter()
        .position(|p| *p == Vec3::ZERO)
        .unwrap();
    assert_eq!(obj_noflip.uvs[j0], Vec2::new(0.0, 0.0));
    // PLY with flip_tex_coords = true: t of vertex 0 (0) becomes 1.
    let ply = mesh(6);
    assert_eq!(ply.uvs[0], Vec2::new(0.0, 1.0));
    assert_eq!(ply.normals.len(), 4);
    // A mesh without normals is smoothed (Mitsuba), unless face_normals is set.
    assert_eq!(mesh(8).normals, vec![Vec3::Z; 6]);
    assert!(mesh(9).normals.is_empty() && s.shapes[9].face_normals);
    // Default materials: one shared diffuse 0.5 for all shapes without a BSDF.
    assert!(s.shapes.iter().all(|x| x.material == s.shapes[0].material));
    let Some(DiffuseMaterial { reflectance, .. }) = s.materials[s.shapes[0].material].get() else {
        panic!()
    };
    assert_eq!(reflectance.as_spectrum().unwrap().as_constant(), Some(0.5));
}

#[test]
fn emitters() {
    let s = load(
        r#"<emitter type="point"><transform name="to_world"><translate x="1" y="2" z="3"/></transform></emitter>
<emitter type="spot"><float name="cutoff_angle" value="30"/><transform name="to_world"><lookat origin="0, 5, 0" target="0, 0, 0" up="1, 0, 0"/></transform></emitter>
<emitter type="directional"><vector name="direction" value="0, -2, 0"/><float name="irradiance" value="3"/></emitter>
<emitter type="directional"><transform name="to_world"><rotate x="1" angle="90"/></transform></emitter>
<emitter type="constant"/>
<emitter type="envmap"><string name="filename" value="rgbw.png"/><float name="scale" value="2"/></emitter>
<shape type="rectangle"><emitter type="area"/></shape>"#,
    );
    assert_eq!(s.emitters.len(), 6);
    let EmitterDesc::Point { position, intensity } = &s.emitters[0] else {
        panic!()
    };
    assert_eq!(*position, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(intensity, &Spectrum::d65());
    let EmitterDesc::Spot {
        to_world,
        cutoff_angle_deg,
        beam_width_deg,
        ..
    } = &s.emitters[1]
    else {
        panic!()
    };
    assert_eq!((*cutoff_angle_deg, *beam_width_deg), (30.0, 22.5));
    assert!((to_world.transform_vector3(Vec3::Z) - Vec3::NEG_Y).length() < 1e-6);
    let EmitterDesc::Directional {
        direction,
        irradiance,
    } = &s.emitters[2]
    else {
        panic!()
    };
    assert_eq!(*direction, Vec3::NEG_Y);
    assert!((irradiance.eval(550.0) - 3.0 * Spectrum::d65().eval(550.0)).abs() < 1e-4);
    let EmitterDesc::Directional { direction, .. } = &s.emitters[3] else {
        panic!()
    };
    assert!((*direction - Vec3::NEG_Y).length() < 1e-6, "{direction}");
    let EmitterDesc::Constant { radiance } = &s.emitters[4] else {
        panic!()
    };
    assert_eq!(radiance, &Spectrum::d65());
    let EmitterDesc::EnvMap { image, scale, .. } = &s.emitters[5] else {
        panic!()
    };
    assert_eq!((image.width, image.height, *scale), (2, 2, 2.0));
    let area = s.shapes[0].emitter.as_ref().unwrap();
    assert_eq!(area.radiance.as_spectrum(), Some(&Spectrum::d65()));
}

#[test]
fn textures() {
    let s = load(
        r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
    <string name="filename" value="rgbw.png"/><string name="filter_type" value="nearest"/>
</texture></bsdf></shape>
<shape type="rectangle"><bsdf type="diffuse"><texture type="bitmap" name="reflectance">
    <string name="filename" value="rgbw.png"/><string name="wrap_mode" value="clamp"/>
    <transform name="to_uv"><scale x="0.5"/></transform>
</texture></bsdf></shape>
<shape type="rectangle"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf></shape>"#,
    );
    let m = |i: usize| &s.materials[s.shapes[i].material];
    // Nearest: top-left texel (uv near 0, 0) is red, bottom-right (near 1, 1) white.
    let red_at = |uv: Vec2| f_normal(m(0), uv, 650.0) * std::f32::consts::PI;
    let blue_at = |uv: Vec2| f_normal(m(0), uv, 450.0) * std::f32::consts::PI;
    assert!(red_at(Vec2::new(0.1, 0.1)) > 0.7 && blue_at(Vec2::new(0.1, 0.1)) < 0.2);
    assert!(blue_at(Vec2::new(0.1, 0.9)) > 0.6 && red_at(Vec2::new(0.1, 0.9)) < 0.2);
    assert!(red_at(Vec2::new(0.9, 0.9)) > 0.95 && blue_at(Vec2::new(0.9, 0.9)) > 0.95);
    // Repeat wrap by default: u = 1.1 is u = 0.1.
    assert!((red_at(Vec2::new(1.1, 0.1)) - red_at(Vec2::new(0.1, 0.1))).abs() < 1e-6);
    // Bilinear with to_uv scale 0.5 and clamp: u = 0.5 → 0.25, the centre of the left column.
    let Some(DiffuseMaterial {
        reflectance: Texture::Bitmap(b),
        ..
    }) = m(1).get()
    else {
        panic!()
    };
    let c = b.eval_rgb(Vec2::new(0.5, 0.25));
    assert!((c[0] - 1.0).abs() < 1e-6 && c[1].abs() < 1e-6, "{c:?}");
    // u = 1.5 → 0.75: the centre of the right column (green over white), halfway down.
    let c = b.eval_rgb(Vec2::new(1.5, 0.5));
    assert!(
        (c[0] - 0.5).abs() < 1e-5 && (c[1] - 1.0).abs() < 1e-5 && (c[2] - 0.5).abs() < 1e-5,
        "{c:?}"
    );
    // Clamp: far outside stays on the edge texels (bottom-right white).
    let c = b.eval_rgb(Vec2::new(9.0, 9.0));
    assert_eq!(c, [1.0, 1.0, 1.0]);
    // Checkerboard defaults 0.4 / 0.2.
    let checker = |uv: Vec2| f_normal(m(2), uv, 550.0) * std::f32::consts::PI;
    assert!((checker(Vec2::new(0.25, 0.25)) - 0.4).abs() < 1e-6);
    assert!((checker(Vec2::new(0.75, 0.25)) - 0.2).abs() < 1e-6);
    assert!((checker(Vec2::new(0.75, 0.75)) - 0.4).abs() < 1e-6);
}

#[test]
fn bsdf_defaults_and_parameters() {
    let wl = SampledWavelengths::fixed(550.0);
    // diffuse default 0.5: f = 0.5/π.
    let d = load_bsdf_str("<bsdf type=\"diffuse\"/>").unwrap();
    assert!((f_normal(&d, Vec2::ZERO, 550.0) - 0.5 * FRAC_1_PI).abs() < 1e-6);
    // conductor default: ideal mirror.
    let c = load_bsdf_str("<bsdf version=\"3.0.0\" type=\"conductor\"/>").unwrap();
    let Some(ConductorMaterial { model, .. }) = c.get() else {
        panic!()
    };
    assert_eq!(model.reflectance(0.7, &wl)[0], 1.0);
    // conductor with eta/k values and our ext_ior.
    let c = load_bsdf_str(
        "<bsdf type=\"conductor\"><float name=\"eta\" value=\"0.2\"/><float name=\"k\" value=\"3\"/><string name=\"ext_ior\" value=\"water\"/></bsdf>",
    )
    .unwrap();
    let Some(ConductorMaterial { model, .. }) = c.get() else {
        panic!()
    };
    assert_eq!(
        (model.eta.as_constant(), model.k.as_constant()),
        (Some(0.2), Some(3.0))
    );
    assert_eq!(model.ext_ior, Ior::Constant(1.333));
    // dielectric defaults bk7/air; presets by name; dispersive glass by name; spectrum.
    let g = load_bsdf_str("<bsdf type=\"dielectric\"/>").unwrap();
    let Some(DielectricMaterial { model, .. }) = g.get() else {
        panic!()
    };
    assert_eq!(
        (&model.int_ior, &model.ext_ior),
        (&Ior::Constant(1.5046), &Ior::Constant(1.000277))
    );
    let g = load_bsdf_str(
        "<bsdf type=\"thindielectric\"><string name=\"int_ior\" value=\"Diamond\"/><string name=\"ext_ior\" value=\"water\"/></bsdf>",
    )
    .unwrap();
    let Some(ThinDielectricMaterial { model, .. }) = g.get() else {
        panic!()
    };
    assert_eq!(
        (&model.int_ior, &model.ext_ior),
        (&Ior::Constant(2.419), &Ior::Constant(1.333))
    );
    let g =
        load_bsdf_str("<bsdf type=\"dielectric\"><string name=\"int_ior\" value=\"SF11\"/></bsdf>").unwrap();
    let Some(DielectricMaterial { model, .. }) = g.get() else {
        panic!()
    };
    assert!(model.int_ior.is_dispersive());
    assert!(model.int_ior.eval(450.0) > model.int_ior.eval(650.0) && model.int_ior.eval(589.3) > 1.7);
    let g = load_bsdf_str(
        "<bsdf type=\"dielectric\"><spectrum name=\"int_ior\" value=\"400:1.55, 700:1.5\"/></bsdf>",
    )
    .unwrap();
    let Some(DielectricMaterial { model, .. }) = g.get() else {
        panic!()
    };
    assert!((model.int_ior.eval(550.0) - 1.525).abs() < 1e-6);
    assert!(
        (model.int_ior.eval(800.0) - 1.5).abs() < 1e-6,
        "an index keeps its end value outside the table"
    );
    // plastic defaults: polypropylene/air, linear, ρ 0.5.
    let p = load_bsdf_str("<bsdf type=\"plastic\"/>").unwrap();
    let Some(PlasticMaterial { model, .. }) = p.get() else {
        panic!()
    };
    assert_eq!(
        (model.int_ior(), model.ext_ior(), model.nonlinear),
        (1.49, 1.000277, false)
    );
    assert!((model.specular_sampling_weight() - 2.0 / 3.0).abs() < 1e-6);
    let p = load_bsdf_str(
        "<bsdf type=\"plastic\"><boolean name=\"nonlinear\" value=\"true\"/><float name=\"int_ior\" value=\"1.5\"/><float name=\"ext_ior\" value=\"1\"/><spectrum name=\"diffuse_reflectance\" value=\"0.8\"/></bsdf>",
    )
    .unwrap();
    let Some(PlasticMaterial { model, .. }) = p.get() else {
        panic!()
    };
    assert!(model.nonlinear && model.int_ior() == 1.5 && model.ext_ior() == 1.0);
    assert_eq!(model.diffuse_reflectance.as_constant(), Some(0.8));
}

#[test]
fn twosided_and_blend() {
    let ctx = BsdfContext::default();
    let wl = SampledWavelengths::fixed(550.0);
    let up = Vec3::Z;
    let down = Vec3::NEG_Z;
    // Single child: the same diffuse on both sides.
    let t = load_bsdf_str("<bsdf type=\"twosided\"><bsdf type=\"diffuse\"><float name=\"reflectance\" value=\"0.8\"/></bsdf></bsdf>")
        .unwrap();
    let back = t.with_bsdf(Vec2::ZERO, |b| b.eval(&ctx, down, down, &wl)[0]);
    assert!((back - 0.8 * FRAC_1_PI).abs() < 1e-6);
    // Two children: front 0.2, back 0.6 (document order).
    let t = load_bsdf_str(
        "<bsdf type=\"twosided\"><bsdf type=\"diffuse\"><float name=\"reflectance\" value=\"0.2\"/></bsdf><bsdf type=\"diffuse\"><float name=\"reflectance\" value=\"0.6\"/></bsdf></bsdf>",
    )
    .unwrap();
    let (f, b) = t.with_bsdf(Vec2::ZERO, |x| {
        (x.eval(&ctx, up, up, &wl)[0], x.eval(&ctx, down, down, &wl)[0])
    });
    assert!((f - 0.2 * FRAC_1_PI).abs() < 1e-6 && (b - 0.6 * FRAC_1_PI).abs() < 1e-6);
    // Blend: weight 0.25 → 0.75·f0 + 0.25·f1, children in document order whatever their names
    // (Mitsuba 3.9.1: `blendbsdf` of weight 0 with children named "b" (ρ 0.2) then "a" (ρ 0.8)
    // evaluates to 0.063662 = 0.2/π; its documentation says alphanumeric order).
    let bl = load_bsdf_str(
        r#"<bsdf type="blendbsdf"><float name="weight" value="0.25"/>
            <bsdf type="diffuse" name="zz"><float name="reflectance" value="1"/></bsdf>
            <bsdf type="diffuse" name="aa"><float name="reflectance" value="0"/></bsdf></bsdf>"#,
    )
    .unwrap();
    // bsdf0 = "zz" (ρ 1), bsdf1 = "aa" (ρ 0) → 0.75/π.
    assert!((f_normal(&bl, Vec2::ZERO, 550.0) - 0.75 * FRAC_1_PI).abs() < 1e-6);
    let Some(BlendMaterial { bsdf0, .. }) = bl.get() else {
        panic!()
    };
    assert!(bsdf0.get::<DiffuseMaterial>().is_some());
    // The same for `twosided`: Mitsuba 3.9.1 gives 0.2/π in front and 0.8/π behind for
    // children named "b" (ρ 0.2) then "a" (ρ 0.8).
    let t = load_bsdf_str(
        r#"<bsdf type="twosided"><bsdf name="b" type="diffuse"><rgb name="reflectance" value="0.2"/></bsdf>
            <bsdf name="a" type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf></bsdf>"#,
    )
    .unwrap();
    let (f, b) = t.with_bsdf(Vec2::ZERO, |x| {
        (x.eval(&ctx, up, up, &wl)[0], x.eval(&ctx, down, down, &wl)[0])
    });
    assert!(
        (f - 0.063662).abs() < 1e-5 && (b - 0.254648).abs() < 1e-5,
        "front {f}, back {b}"
    );
    let flags = bl.with_bsdf(Vec2::ZERO, |b| b.flags());
    assert!(flags.contains(BsdfFlags::DIFFUSE_REFLECTION));
    // Unnamed children keep document order.
    let bl = load_bsdf_str(
        r#"<bsdf type="blendbsdf"><float name="weight" value="0.25"/>
            <bsdf type="diffuse"><float name="reflectance" value="1"/></bsdf>
            <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf></bsdf>"#,
    )
    .unwrap();
    assert!((f_normal(&bl, Vec2::ZERO, 550.0) - 0.75 * FRAC_1_PI).abs() < 1e-6);
    // A textured weight is evaluated per hit.
    let bl = load_bsdf_str(
        r#"<bsdf type="blendbsdf"><texture type="checkerboard" name="weight"><float name="color0" value="0"/><float name="color1" value="1"/></texture>
            <bsdf type="diffuse"><float name="reflectance" value="1"/></bsdf>
            <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf></bsdf>"#,
    )
    .unwrap();
    assert!((f_normal(&bl, Vec2::new(0.25, 0.25), 550.0) - FRAC_1_PI).abs() < 1e-6);
    assert!(f_normal(&bl, Vec2::new(0.75, 0.25), 550.0).abs() < 1e-6);
}

#[test]
fn values_roles_follow_mitsuba() {
    // A uniform reflectance above 1 is accepted (Mitsuba does not check it).
    let d =
        load_bsdf_str("<bsdf type=\"diffuse\"><float name=\"reflectance\" value=\"1.2\"/></bsdf>").unwrap();
    assert!((f_normal(&d, Vec2::ZERO, 500.0) - 1.2 * FRAC_1_PI).abs() < 1e-6);
    // A top-level texture with bright colours used as an emitter's radiance is built as an
    // illuminant, not checked as a reflectance.
    let s = load(
        r#"<texture type="checkerboard" id="glow"><rgb name="color0" value="4, 2, 1"/><rgb name="color1" value="0"/></texture>
<shape type="rectangle"><emitter type="area"><ref name="radiance" id="glow"/></emitter></shape>"#,
    );
    let Texture::Checkerboard { color0, .. } = &s.shapes[0].emitter.as_ref().unwrap().radiance else {
        panic!()
    };
    let c0 = color0.as_spectrum().unwrap();
    assert!(
        c0.eval(650.0) > 2.5 && c0.eval(650.0) > c0.eval(450.0),
        "{}",
        c0.eval(650.0)
    );
}

#[test]
fn textured_plastic_uses_texture_means_for_sampling() {
    let p = load_bsdf_str(
        r#"<bsdf type="plastic"><texture type="checkerboard" name="diffuse_reflectance">
            <float name="color0" value="0.9"/><float name="color1" value="0.1"/></texture></bsdf>"#,
    )
    .unwrap();
    let Some(PlasticMaterial { model, .. }) = p.get() else {
        panic!()
    };
    // mean(ρ) = 0.5, mean(spec) = 1: s = 1/1.5.
    assert!((model.specular_sampling_weight() - 2.0 / 3.0).abs() < 1e-6);
    // The per-hit model sees the texel value: brighter on color0 squares.
    let wl = SampledWavelengths::fixed(550.0);
    let ctx = BsdfContext::default();
    let f0 = p.with_bsdf(Vec2::new(0.25, 0.25), |b| b.eval(&ctx, Vec3::Z, Vec3::Z, &wl)[0]);
    let f1 = p.with_bsdf(Vec2::new(0.75, 0.25), |b| b.eval(&ctx, Vec3::Z, Vec3::Z, &wl)[0]);
    assert!(f0 > 5.0 * f1 && f1 > 0.0, "{f0} {f1}");
    assert!(p.is_textured());
}

/// `cylinder` (Mitsuba 3 `src/shapes/cylinder.cpp`): the lateral surface between p0 and p1,
/// normals away from the axis, uv = (φ/2π, z along the axis), no caps.
#[test]
fn cylinder_is_the_lateral_surface_between_its_end_points() {
    use gonio_render::accel::Intersect;
    use gonio_render::geometry::Ray;
    use gonio_render::render::PreparedScene;
    let scene = load_scene_str(
        r#"<scene version="3.0.0"><shape type="cylinder">
            <point name="p0" value="1, 2, 3"/><point name="p1" value="1, 2, 5"/><float name="radius" value="0.5"/>
        </shape></scene>"#,
        ".",
        &[],
    )
    .unwrap();
    let prepared = PreparedScene::new(scene).unwrap();
    let accel = prepared.accel();
    // From +x at mid-height: hits x = 1.5, normal +x, v = 1/2; the tessellation's chord is at
    // most r(1 − cos(π/256)) inside the circle.
    let hit = accel
        .intersect(&Ray::new(Vec3::new(10.0, 2.0, 4.0), Vec3::NEG_X))
        .expect("hits the side");
    assert!((hit.t - 8.5).abs() < 1e-4, "t = {}", hit.t);
    // The shading normal is the radial direction; the facet's own normal is within π/256 of it.
    assert!(
        (hit.shading.n - Vec3::X).length() < 1e-3,
        "n = {:?}",
        hit.shading.n
    );
    assert!((hit.n - Vec3::X).length() < 1.3e-2, "n = {:?}", hit.n);
    assert!((hit.uv.y - 0.5).abs() < 1e-5, "uv = {:?}", hit.uv);
    // From −y the angle is φ = 3π/2 around the axis frame's z = +z: u is a quarter turn from
    // the +x hit's, one way or the other.
    let side = accel
        .intersect(&Ray::new(Vec3::new(1.0, -10.0, 3.5), Vec3::Y))
        .expect("hits the side");
    assert!(
        (side.p.y - 1.5).abs() < 1e-4 && (side.uv.y - 0.25).abs() < 1e-5,
        "{side:?}"
    );
    let du = (side.uv.x - hit.uv.x).rem_euclid(1.0);
    assert!((du - 0.25).abs() < 1e-3 || (du - 0.75).abs() < 1e-3, "du = {du}");
    // No caps: along the axis the ray passes through; beyond p1 it misses.
    assert!(
        accel
            .intersect(&Ray::new(Vec3::new(1.0, 2.0, 0.0), Vec3::Z))
            .is_none()
    );
    assert!(
        accel
            .intersect(&Ray::new(Vec3::new(10.0, 2.0, 5.5), Vec3::NEG_X))
            .is_none()
    );
    // From inside, the ray meets the far wall.
    let inside = accel
        .intersect(&Ray::new(Vec3::new(1.0, 2.0, 4.0), Vec3::X))
        .expect("hits the wall from inside");
    assert!((inside.t - 0.5).abs() < 1e-4);

    let e = load_scene_str(
        r#"<scene version="3.0.0"><shape type="cylinder"><point name="p1" value="0, 0, 0"/></shape></scene>"#,
        ".",
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("must differ") && e.contains(":1:"), "{e}");
    let e = load_scene_str(
        r#"<scene version="3.0.0"><shape type="cylinder"><float name="radius" value="0"/></shape></scene>"#,
        ".",
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("radius") && e.contains("positive"), "{e}");
}
