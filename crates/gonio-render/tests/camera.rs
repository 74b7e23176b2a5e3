//! Mitsuba's perspective camera: look-at convention, field of view, clipping.

use glam::{Vec2, Vec3};
use gonio_render::camera::{Camera, PerspectiveCamera, look_at};

fn cam(fov: f32, w: u32, h: u32) -> PerspectiveCamera {
    // Mitsuba's usual setup: at +z looking at the origin, +y up.
    PerspectiveCamera::from_parts(
        look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y),
        fov,
        w,
        h,
        0.01,
        1000.0,
    )
}

#[test]
fn right_is_larger_x_and_up_is_smaller_y() {
    let c = cam(40.0, 200, 100);
    // Looking down −z with +y up, the camera's right is +x.
    let right = c.project(Vec3::new(1.0, 0.0, 0.0)).unwrap();
    let left = c.project(Vec3::new(-1.0, 0.0, 0.0)).unwrap();
    let up = c.project(Vec3::new(0.0, 1.0, 0.0)).unwrap();
    let centre = c.project(Vec3::ZERO).unwrap();
    assert!((centre - Vec2::new(100.0, 50.0)).length() < 1e-3, "{centre:?}");
    assert!(right.x > 100.0 && left.x < 100.0, "{right:?} {left:?}");
    assert!(up.y < 50.0 && (up.x - 100.0).abs() < 1e-3, "{up:?}");
    // Behind the camera: not on the film.
    assert!(c.project(Vec3::new(0.0, 0.0, 10.0)).is_none());
    // The ray through the left part of the image goes to −x.
    let r = c.generate_ray(Vec2::new(10.0, 50.0));
    assert!(r.d.x < 0.0 && r.d.z < 0.0);
}

#[test]
fn horizontal_fov_spans_the_width_and_aspect_the_height() {
    let fov = 60.0f32;
    let c = cam(fov, 300, 150);
    let t = (fov.to_radians() / 2.0).tan();
    // A point at the edge of the horizontal fov, 5 units in front: x = 5·tan(fov/2).
    let edge = c.project(Vec3::new(5.0 * t, 0.0, 0.0)).unwrap();
    assert!((edge.x - 300.0).abs() < 1e-2, "{edge:?}");
    // Vertical half-extent is T/aspect: the top edge (y = 0) at y = 5·T/2.
    let top = c.project(Vec3::new(0.0, 5.0 * t / 2.0, 0.0)).unwrap();
    assert!(top.y.abs() < 1e-2, "{top:?}");
    // Corner rays: the (0, 0) pixel corner ray makes the expected angles.
    let r = c.generate_ray(Vec2::ZERO);
    let want = Vec3::new(-t, t / 2.0, -1.0).normalize();
    assert!((r.d - want).length() < 1e-5, "{:?} vs {want:?}", r.d);
}

#[test]
fn generate_ray_inverts_project_and_clips() {
    let c = PerspectiveCamera::from_parts(
        look_at(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-0.5, 0.2, 0.1),
            Vec3::new(0.1, 1.0, 0.0),
        ),
        45.0,
        64,
        48,
        0.5,
        20.0,
    );
    for (x, y) in [(0.0, 0.0), (31.5, 17.25), (63.9, 47.9), (5.0, 40.0)] {
        let r = c.generate_ray(Vec2::new(x, y));
        assert!((r.d.length() - 1.0).abs() < 1e-6);
        let p = r.at(3.0);
        let back = c.project(p).unwrap();
        assert!((back - Vec2::new(x, y)).length() < 1e-3, "({x}, {y}) → {back:?}");
        // The ray starts on the near plane and ends on the far plane (depth along the view axis).
        let axis = (Vec3::new(-0.5, 0.2, 0.1) - Vec3::new(1.0, 2.0, 3.0)).normalize();
        let depth = |q: Vec3| (q - c.position()).dot(axis);
        assert!((depth(r.o) - 0.5).abs() < 1e-4, "near {}", depth(r.o));
        assert!(
            (depth(r.at(r.tmax)) - 20.0).abs() < 1e-3,
            "far {}",
            depth(r.at(r.tmax))
        );
    }
}

#[test]
fn mirrored_to_world_flips_the_image() {
    // Mitsuba allows a mirror (scale x by −1) in a camera's to_world: the image flips.
    let m = look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y)
        * glam::Affine3A::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let c = PerspectiveCamera::from_parts(m, 40.0, 100, 100, 0.01, 100.0);
    assert!(c.project(Vec3::X).unwrap().x < 50.0);
    let r = c.generate_ray(Vec2::new(90.0, 50.0));
    assert!(r.d.x < 0.0 && (r.d.length() - 1.0).abs() < 1e-6);
}

/// `connect` inverts `generate_ray`, and its importance is one over the solid angle of the pixel
/// (measured from the pixel's corner rays), so a splat of radiance L through it gives L.
#[test]
fn connect_inverts_generate_ray_and_importance_is_the_pixel_solid_angle() {
    let c = cam(40.0, 64, 48);
    let eye = c.position();
    for film in [
        Vec2::new(0.5, 0.5),
        Vec2::new(31.2, 20.7),
        Vec2::new(63.5, 47.5),
        Vec2::new(10.0, 40.0),
    ] {
        let ray = c.generate_ray(film);
        let p = ray.o + ray.d * 3.0;
        let k = c.connect(p).expect("a point in view connects");
        assert!((k.film - film).length() < 1e-3, "film {:?} vs {film:?}", k.film);
        assert!((k.dir + ray.d).length() < 1e-5);
        assert!(((p - eye).length_squared() - k.dist2).abs() < 1e-4);
        // Solid angle of the pixel around `film`: two triangles of corner directions.
        let (x, y) = (film.x.floor(), film.y.floor());
        let d = |u: f32, v: f32| {
            let r = c.generate_ray(Vec2::new(u, v));
            r.d
        };
        let tri = |a: Vec3, b: Vec3, cc: Vec3| {
            // Van Oosterom–Strackee.
            let num = a.dot(b.cross(cc)).abs();
            let den = 1.0 + a.dot(b) + b.dot(cc) + cc.dot(a);
            2.0 * num.atan2(den)
        };
        let (a, b, cc, dd) = (d(x, y), d(x + 1.0, y), d(x + 1.0, y + 1.0), d(x, y + 1.0));
        let omega = tri(a, b, cc) + tri(a, cc, dd);
        assert!(
            (k.importance * omega - 1.0).abs() < 2e-3,
            "importance {} × pixel solid angle {omega} = {}",
            k.importance,
            k.importance * omega
        );
        // The film density is the importance shared over all pixels.
        assert!((k.film_pdf * 64.0 * 48.0 / k.importance - 1.0).abs() < 1e-5);
    }
    // Behind the camera, beyond the far plane, or off the film: no connection.
    assert!(c.connect(Vec3::new(0.0, 0.0, 6.0)).is_none());
    assert!(c.connect(Vec3::new(0.0, 0.0, -2000.0)).is_none());
    assert!(c.connect(Vec3::new(50.0, 0.0, 0.0)).is_none());
}

// ---------------------------------------------------------------------------------------------
// `orthographic` and `thinlens` (Mitsuba 3 `src/sensors/orthographic.cpp`, `thinlens.cpp`).

use gonio_render::camera::{OrthographicCamera, ThinLensCamera};
use gonio_render::scene::Projection;

#[test]
fn orthographic_rays_are_parallel_from_the_scaled_near_plane() {
    // At +z looking at the origin, +y up, scaled by 2: the film covers x ∈ [−2, 2],
    // y ∈ [−1, 1] (aspect 2); camera-space +x is world −x.
    let m =
        look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y) * glam::Affine3A::from_scale(Vec3::splat(2.0));
    let c = OrthographicCamera::from_parts(m, 200, 100, 0.01, 1000.0);
    for (film, x, y) in [
        (Vec2::new(0.0, 0.0), -2.0f32, 1.0f32),
        (Vec2::new(100.0, 50.0), 0.0, 0.0),
        (Vec2::new(50.0, 50.0), -1.0, 0.0),
        (Vec2::new(200.0, 100.0), 2.0, -1.0),
        (Vec2::new(150.0, 25.0), 1.0, 0.5),
    ] {
        let r = c.generate_ray(film);
        // The near plane is scaled with the rest: z = 5 − 2·0.01.
        let o = Vec3::new(x, y, 5.0 - 0.02);
        assert!(
            (r.o - o).length() < 1e-5,
            "{film:?}: origin {:?}, expected {o:?}",
            r.o
        );
        assert!((r.d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6, "{:?}", r.d);
        assert!((r.tmax - (1000.0 - 0.01)).abs() < 1e-3, "{}", r.tmax);
        // project inverts it (for a point anywhere along the ray).
        let back = c.project(r.o + r.d * 3.0).unwrap();
        assert!((back - film).length() < 1e-3, "{back:?} vs {film:?}");
    }
    // Light tracing connects a point straight along the axis (`ptracer`); the caustic light
    // paths' MIS cannot weigh that delta direction, so the camera does not offer it to them.
    assert!(!c.connects());
    let k = c.connect(Vec3::new(1.0, 0.5, 0.0)).expect("in front of the film");
    assert!((k.film - Vec2::new(150.0, 25.0)).length() < 1e-3, "{:?}", k.film);
    assert!(
        (k.dir - Vec3::Z).length() < 1e-6 && k.film_pdf == 0.0,
        "{:?}",
        k.dir
    );
    // Importance d²/A_pix: the film spans 4 × 2 world units over 200 × 100 pixels.
    assert!(
        (k.importance / k.dist2 - 1.0 / (8.0 / 20_000.0)).abs() < 1e-2 * 2500.0,
        "{}",
        k.importance
    );
    assert!(c.connect(Vec3::new(0.0, 0.0, 6.0)).is_none(), "behind the camera");
}

#[test]
fn thin_lens_rays_meet_on_the_focus_plane_and_start_on_the_lens() {
    let to_world = look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y);
    let pinhole = PerspectiveCamera::from_parts(to_world, 60.0, 200, 100, 0.01, 1000.0);
    let (radius, focus) = (0.5f32, 4.0f32);
    let c = ThinLensCamera::from_pinhole(pinhole.clone(), radius, focus);
    assert!(c.needs_lens_sample() && !c.connects());
    for film in [
        Vec2::new(100.0, 50.0),
        Vec2::new(50.0, 50.0),
        Vec2::new(13.0, 91.0),
    ] {
        let centre = pinhole.generate_ray(film);
        // The point in focus: the pinhole ray at camera depth `focus` (camera z is world −z).
        let f = Vec3::new(0.0, 0.0, 5.0) + centre.d * (focus / -centre.d.z);
        for u in [
            Vec2::new(0.5, 0.5),
            Vec2::new(1.0, 0.5),
            Vec2::new(0.5, 1.0),
            Vec2::new(0.9, 0.2),
            Vec2::new(0.03, 0.77),
        ] {
            let r = c.generate_ray_lens(film, u);
            assert!((r.d.length() - 1.0).abs() < 1e-5);
            // The ray starts on the near plane (camera z = 0.01) ...
            assert!((r.o.z - (5.0 - 0.01)).abs() < 1e-4, "{:?}", r.o);
            // ... from a lens point within the aperture (back on z = 5) ...
            let lens = r.o - r.d * (0.01 / -r.d.z);
            let d = Vec3::new(lens.x, lens.y, 0.0).length();
            assert!(d <= radius * (1.0 + 1e-5), "lens point {lens:?}");
            // ... through the point in focus ...
            let at_focus = r.o + r.d * ((5.0 - focus - r.o.z) / r.d.z);
            assert!((at_focus - f).length() < 1e-4, "{at_focus:?} vs {f:?}");
            // ... and ends on the far plane.
            let end = r.o + r.d * r.tmax;
            assert!((end.z - (5.0 - 1000.0)).abs() < 1e-2, "{end:?}");
        }
        // The concentric map: u = (1, 0.5) is the lens's rim on camera +x (world −x).
        let r = c.generate_ray_lens(film, Vec2::new(1.0, 0.5));
        let lens = r.o - r.d * (0.01 / -r.d.z);
        assert!((lens - Vec3::new(-radius, 0.0, 5.0)).length() < 1e-4, "{lens:?}");
        // Through the lens centre it is the pinhole ray.
        let r = c.generate_ray_lens(film, Vec2::splat(0.5));
        assert!((r.d - centre.d).length() < 1e-5 && (r.o - centre.o).length() < 1e-4);
    }
}

#[test]
fn sensors_are_read_with_mitsubas_parameters() {
    let load = |sensor: &str| {
        gonio_render::xml::load_scene_str(&format!(r#"<scene version="3.0.0">{sensor}</scene>"#), ".", &[])
    };
    let s = load(
        r#"<sensor type="thinlens"><float name="aperture_radius" value="0.2"/><float name="fov" value="40"/></sensor>"#,
    )
    .unwrap();
    // focus_distance defaults to far_clip.
    assert_eq!(
        s.sensor.projection,
        Projection::ThinLens {
            aperture_radius: 0.2,
            focus_distance: 10000.0
        }
    );
    let s = load(
        r#"<sensor type="orthographic"><transform name="to_world"><scale value="3"/></transform></sensor>"#,
    )
    .unwrap();
    assert_eq!(s.sensor.projection, Projection::Orthographic);
    let e = load(r#"<sensor type="thinlens"/>"#).unwrap_err().to_string();
    assert!(e.contains("needs an aperture_radius") && e.contains(":1:"), "{e}");
    let e = load(r#"<sensor type="thinlens"><float name="aperture_radius" value="-1"/></sensor>"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("invalid aperture_radius -1"), "{e}");
    let e = load(
        r#"<sensor type="thinlens"><float name="aperture_radius" value="1"/><float name="focus_distance" value="0"/></sensor>"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("invalid focus_distance 0"), "{e}");
    let e = load(r#"<sensor type="orthographic"><float name="fov" value="40"/></sensor>"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("unused parameter \"fov\""), "{e}");
    let e = load(
        r#"<sensor type="thinlens"><float name="aperture_radius" value="1"/><transform name="to_world"><scale value="2"/></transform></sensor>"#,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("scale factors"), "{e}");
}

/// `radiancemeter` (Mitsuba 3 `src/sensors/radiancemeter.cpp`): the radiance along one ray into
/// a film of one pixel. Looking at the sky it reads the sky's radiance; at a diffuse plane under
/// a uniform sky, ρ·L; the ray comes from `origin`/`direction` or from `to_world`, not both; other
/// film sizes are refused, as Mitsuba refuses them.
#[test]
fn radiancemeter_reads_the_radiance_along_its_ray() {
    let scene = |sensor: &str| {
        format!(
            r#"<scene version="3.0.0"><integrator type="path"/>
            <sensor type="radiancemeter">{sensor}<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film></sensor>
            <emitter type="constant"><rgb name="radiance" value="1, 0.8, 0.6"/></emitter>
            <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.3, 0.2"/></bsdf></shape>
            </scene>"#
        )
    };
    let meter = |sensor: &str, spp: u32| crate::integrator::render_xml(&scene(sensor), spp, 3).data[0];
    // Up, at the sky: its radiance (the RGB emitter renders as its own colour; the wavelengths
    // drawn per sample leave colour noise, 1 % at this count).
    let sky = meter(
        r#"<point name="origin" x="0" y="0" z="1"/><vector name="direction" x="0.2" y="0" z="1"/>"#,
        4096,
    );
    for (v, e) in sky.iter().zip([1.0, 0.8, 0.6]) {
        assert!((v - e).abs() < 0.01, "sky {sky:?}");
    }
    // Down, at the plane: Mitsuba 3.9.1's `scalar_spectral` reading of the same meter (65 536
    // samples; ρ·L per channel would be 0.5, 0.24, 0.12: the spectra multiply, not the colours).
    let plane = meter(
        r#"<transform name="to_world"><lookat origin="0.3, 0.2, 5" target="0, 0, 0" up="0, 1, 0"/></transform>"#,
        4096,
    );
    for (v, e) in plane.iter().zip([0.49004, 0.23911, 0.11649]) {
        assert!((v / e - 1.0).abs() < 0.01, "plane {plane:?}");
    }
    let load = |text: &str| {
        gonio_render::xml::load_scene_str(text, ".", &[])
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = load(&scene(
        r#"<point name="origin" x="0" y="0" z="1"/><transform name="to_world"><translate z="1"/></transform>"#,
    ));
    assert!(e.contains("not both"), "{e}");
    let e = load(&scene("").replace(
        r#"<integer name="width" value="1"/>"#,
        r#"<integer name="width" value="2"/>"#,
    ));
    assert!(e.contains("1 × 1") && e.contains("2 × 1"), "{e}");
    let e = load(&scene(r#"<vector name="direction" x="0" y="0" z="0"/>"#));
    assert!(e.contains("direction"), "{e}");
}

/// A 1 × 1 `irradiancemeter` on `shape` (its transform and BSDF inside), the rest of the scene
/// around it.
fn irradiance_scene(shape: &str, rest: &str, film: &str) -> String {
    format!(
        r#"<scene version="3.0.0"><integrator type="path"><integer name="max_depth" value="8"/></integrator>
        {rest}
        <shape type="{shape}"><bsdf type="diffuse"/>
            <sensor type="irradiancemeter">{film}<sampler type="independent"/></sensor>
        </shape></scene>"#
    )
}

/// Mitsuba 3.9.1 `scalar_spectral`'s reading of the second meter of
/// `irradiancemeter_reads_the_irradiance_over_its_shape`: the mean of 64 renders (`mi.render`,
/// seeds 100–163) of 65 536 samples each, standard error of the mean 0.13 %, 0.11 %, 0.10 %.
const MITSUBA_IRRADIANCE: [f32; 3] = [2.054_770_5, 1.851_636_6, 1.550_775_2];

const ONE_PIXEL: &str = r#"<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/><rfilter type="box"/></film>"#;

#[test]
fn irradiancemeter_reads_the_irradiance_over_its_shape() {
    // Under a uniform sky of radiance L, every point of a convex shape receives E = π L.
    let sky = r#"<emitter type="constant"><rgb name="radiance" value="0.3, 0.5, 0.9"/></emitter>"#;
    let e = crate::integrator::render_xml(&irradiance_scene("sphere", sky, ONE_PIXEL), 16_384, 1).data[0];
    for (v, l) in e.iter().zip([0.3f32, 0.5, 0.9]) {
        assert!(
            (v / (std::f32::consts::PI * l) - 1.0).abs() < 0.01,
            "sphere under the sky: {e:?}"
        );
    }
    // The `rectangle` (2 × 2) under a small lamp, with a red cube casting a shadow and a
    // coloured bounce onto it, in a dim sky: [`MITSUBA_IRRADIANCE`].
    let rest = r#"<emitter type="constant"><rgb name="radiance" value="0.2, 0.25, 0.3"/></emitter>
        <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="180"/><translate y="0.3" z="2"/></transform>
            <emitter type="area"><rgb name="radiance" value="10, 8, 5"/></emitter></shape>
        <shape type="cube"><transform name="to_world"><scale value="0.3"/><translate x="0.6" z="0.8"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.2, 0.2"/></bsdf></shape>"#;
    let e =
        crate::integrator::render_xml(&irradiance_scene("rectangle", rest, ONE_PIXEL), 1 << 22, 2).data[0];
    for (v, m) in e.iter().zip(MITSUBA_IRRADIANCE) {
        assert!(
            (v / m - 1.0).abs() < 0.01,
            "square under the lamp: {e:?} against Mitsuba's {MITSUBA_IRRADIANCE:?}"
        );
    }
}

#[test]
fn irradiancemeter_is_refused_where_mitsuba_refuses_it() {
    let load = |text: &str| {
        gonio_render::xml::load_scene_str(text, ".", &[])
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    // On its own, not nested in a shape.
    let e = load(&format!(
        r#"<scene version="3.0.0"><sensor type="irradiancemeter">{ONE_PIXEL}</sensor></scene>"#
    ));
    assert!(e.contains("nested in the <shape>") && e.contains(":1:"), "{e}");
    // With a transform of its own.
    let e = load(&irradiance_scene(
        "sphere",
        "",
        &format!(r#"<transform name="to_world"><translate z="1"/></transform>{ONE_PIXEL}"#),
    ));
    assert!(e.contains("no to_world"), "{e}");
    // A camera nested in a shape.
    let e = load(&irradiance_scene("sphere", "", ONE_PIXEL).replace("irradiancemeter", "perspective"));
    assert!(e.contains("cannot be nested in a shape"), "{e}");
}

#[test]
fn batch_renders_its_sensors_side_by_side() {
    // Two views of a lit scene: the batch (film 2w × h) against each camera alone (w × h). The
    // left share is keyed by the same pixels as the first camera alone, so with nothing that
    // depends on the whole film (no light subpaths, a box filter) it is that render, bit for bit;
    // the right share is the second view, drawn from other pixels' numbers: the same image
    // within noise, and far from the first view.
    let camera = |origin: &str, fov_axis: &str, film: &str| {
        format!(
            r#"<sensor type="perspective"><float name="fov" value="40"/><string name="fov_axis" value="{fov_axis}"/>
            <transform name="to_world"><lookat origin="{origin}" target="0, 0, 0" up="0, 1, 0"/></transform>{film}</sensor>"#
        )
    };
    let film = |w: u32| {
        format!(
            r#"<film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="24"/><rfilter type="box"/></film>"#
        )
    };
    let scene = |sensor: &str| {
        format!(
            r#"<scene version="3.0.0"><integrator type="path"><boolean name="caustic_paths" value="false"/></integrator>
            {sensor}
            <emitter type="constant"><rgb name="radiance" value="0.4, 0.5, 0.6"/></emitter>
            <shape type="sphere"><float name="radius" value="0.6"/><bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.3, 0.2"/></bsdf></shape>
            <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/><translate y="-0.6"/></transform>
                <bsdf type="diffuse"/></shape>
            </scene>"#
        )
    };
    // `fov_axis` y: the field of view converts at the share's aspect ratio, not the whole film's.
    let (a, b) = (camera("0, 0.5, 3", "y", ""), camera("2.5, 1, 1.5", "y", ""));
    let batch = scene(&format!(r#"<sensor type="batch">{a}{b}{}</sensor>"#, film(64)));
    let whole = crate::integrator::render_xml(&batch, 64, 5);
    let alone = |c: &str| {
        crate::integrator::render_xml(
            &scene(&c.replace("</sensor>", &format!("{}</sensor>", film(32)))),
            64,
            5,
        )
    };
    let (first, second) = (alone(&a), alone(&b));
    assert_eq!((whole.width, whole.height), (64, 24));
    let share = |img: &gonio_render::image::RgbImage, x0: usize| -> Vec<[f32; 3]> {
        (0..24)
            .flat_map(|y| (x0..x0 + 32).map(move |x| (x, y)))
            .map(|(x, y)| img.data[y * img.width + x])
            .collect()
    };
    assert_eq!(
        share(&whole, 0),
        first.data,
        "the left share is the first camera's render"
    );
    let right = share(&whole, 32);
    let diff = |p: &[[f32; 3]], q: &[[f32; 3]]| -> f64 {
        p.iter()
            .zip(q)
            .map(|(u, v)| (0..3).map(|k| ((u[k] - v[k]) as f64).powi(2)).sum::<f64>())
            .sum::<f64>()
            / p.len() as f64
    };
    let (same, other) = (diff(&right, &second.data), diff(&right, &first.data));
    assert!(
        same * 20.0 < other,
        "right share vs second camera {same:.2e}, vs first {other:.2e}"
    );
    // Refusals: a width the sensors do not divide, no sensor at all.
    let load = |text: &str| {
        gonio_render::xml::load_scene_str(text, ".", &[])
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = load(&scene(&format!(
        r#"<sensor type="batch">{a}{b}{}</sensor>"#,
        film(63)
    )));
    assert!(e.contains("63") && e.contains("multiple"), "{e}");
    let e = load(&scene(&format!(r#"<sensor type="batch">{}</sensor>"#, film(64))));
    assert!(e.contains("at least one"), "{e}");
}

#[test]
fn distant_sensor_reads_the_radiance_leaving_its_target() {
    // A diffuse plane under a coloured sky, seen along (0.2, 0, −1): through a point of it, over a
    // rectangle of it (a target shape, not part of the scene), or across the scene's bounding
    // sphere (partly the plane, partly the sky below it). Mitsuba 3.9.1 `scalar_spectral`, the
    // mean of 4 renders of 262 144 samples (standard errors ≤ 0.1 %).
    let scene = |target: &str, film: &str| {
        format!(
            r#"<scene version="3.0.0"><integrator type="path"/>
            <sensor type="distant"><vector name="direction" x="0.2" y="0" z="-1"/>{target}{film}</sensor>
            <emitter type="constant"><rgb name="radiance" value="1, 0.8, 0.6"/></emitter>
            <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.3, 0.2"/></bsdf></shape>
            </scene>"#
        )
    };
    let cases = [
        (
            r#"<point name="target" x="0.1" y="0.2" z="0"/>"#,
            [0.48995, 0.23891, 0.11637],
        ),
        (
            r#"<shape type="rectangle" name="target"><transform name="to_world"><scale value="0.5"/><translate x="0.2"/></transform></shape>"#,
            [0.48995, 0.23891, 0.11637],
        ),
        ("", [0.68174, 0.44979, 0.29802]),
        // A target shape beside the plane: only the sky.
        (
            r#"<shape type="disk" name="target"><transform name="to_world"><translate x="5"/></transform></shape>"#,
            [1.0, 0.8, 0.6],
        ),
    ];
    for (target, mitsuba) in cases {
        let v = crate::integrator::render_xml(&scene(target, ONE_PIXEL), 65_536, 1).data[0];
        for (a, m) in v.iter().zip(mitsuba) {
            assert!(
                (a / m - 1.0).abs() < 0.005,
                "target {target:?}: {v:?} against {mitsuba:?}"
            );
        }
    }
    let load = |text: &str| {
        gonio_render::xml::load_scene_str(text, ".", &[])
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = load(&scene(
        "",
        &ONE_PIXEL.replace(r#"name="width" value="1""#, r#"name="width" value="3""#),
    ));
    assert!(e.contains("1 × 1") && e.contains("3 × 1"), "{e}");
    let e = load(&scene(
        r#"<transform name="to_world"><rotate x="1" angle="90"/></transform>"#,
        ONE_PIXEL,
    ));
    assert!(e.contains("not both"), "{e}");
    let e = load(&scene(
        r#"<shape type="rectangle" name="target"><sensor type="irradiancemeter"/></shape>"#,
        ONE_PIXEL,
    ));
    assert!(e.contains("cannot hold a sensor"), "{e}");
}
