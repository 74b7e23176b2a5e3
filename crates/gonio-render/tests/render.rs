//! The render loop: the same seed gives the same image bit for bit whatever the number of threads,
//! another seed gives another image, progress is reported to the total, a cancelled render
//! returns what it finished, and bad scenes are errors.

use gonio_render::image::RgbImage;
use gonio_render::render::{DEFAULT_SCENE, PreparedScene, RenderOptions, render};
use gonio_render::sampler::Pattern;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

fn cornell(width: u32, height: u32) -> PreparedScene {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba/scenes/cornell-spheres.xml");
    let defines = vec![
        ("width".to_string(), width.to_string()),
        ("height".to_string(), height.to_string()),
    ];
    PreparedScene::new(gonio_render::xml::load_scene_file(&path, &defines).unwrap()).unwrap()
}

fn render_with_threads(p: &PreparedScene, options: &RenderOptions, threads: usize) -> RgbImage {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| render(p, options, &|_, _| {}, &AtomicBool::new(false)).image)
}

#[test]
fn same_seed_same_image_whatever_the_thread_count() {
    // 40 × 36: tiles of 16 leave partial tiles at the right and bottom edges.
    let p = cornell(40, 36);
    for pattern in [Pattern::Sobol, Pattern::Independent] {
        let options = RenderOptions {
            spp: 20,
            seed: 7,
            pattern,
        };
        let one = render_with_threads(&p, &options, 1);
        let two = render_with_threads(&p, &options, 2);
        let three = render_with_threads(&p, &options, 3);
        assert!(
            one.data == two.data && one.data == three.data,
            "{pattern:?}: images differ between thread counts"
        );
        let other = render_with_threads(&p, &RenderOptions { seed: 8, ..options }, 2);
        assert!(
            one.data != other.data,
            "{pattern:?}: another seed must give another image"
        );
        // Finite everywhere (a single-sample colour may be slightly out of the sRGB gamut, < 0).
        assert!(one.data.iter().all(|c| c.iter().all(|v| v.is_finite())));
    }
}

#[test]
fn filters_other_than_box_are_deterministic_too() {
    // A tent filter splats across tile borders: the merge order must still be fixed.
    let mut p = cornell(40, 36);
    p.scene.sensor.film.filter = gonio_render::scene::FilterDesc::Tent { radius: 1.5 };
    let options = RenderOptions {
        spp: 8,
        seed: 3,
        pattern: Pattern::Sobol,
    };
    assert!(render_with_threads(&p, &options, 1).data == render_with_threads(&p, &options, 2).data);
}

#[test]
fn progress_reaches_the_total() {
    let p = cornell(24, 20);
    let seen = Mutex::new((0u64, 0u64));
    let options = RenderOptions {
        spp: 5,
        seed: 0,
        pattern: Pattern::Sobol,
    };
    let out = render(
        &p,
        &options,
        &|done, total| {
            let mut s = seen.lock().unwrap();
            s.0 = s.0.max(done);
            s.1 = total;
        },
        &AtomicBool::new(false),
    );
    let (done, total) = *seen.lock().unwrap();
    assert_eq!(total, 24 * 20 * 5);
    assert_eq!(done, total);
    assert_eq!(out.complete_spp, 5);
    assert!(!out.cancelled);
}

#[test]
fn cancelling_returns_the_finished_part() {
    let p = cornell(64, 64);
    let cancel = AtomicBool::new(false);
    // Cancel after the first tiles report progress: the render stops early and still returns an
    // image of the right size with some pixels rendered.
    let options = RenderOptions {
        spp: 64,
        seed: 0,
        pattern: Pattern::Sobol,
    };
    let out = render(
        &p,
        &options,
        &|done, _| {
            if done >= 64 * 64 * 16 {
                cancel.store(true, Ordering::Relaxed);
            }
        },
        &cancel,
    );
    assert!(out.cancelled);
    assert!(out.complete_spp < 64);
    assert_eq!((out.image.width, out.image.height), (64, 64));
    let lit = out.image.data.iter().filter(|c| c[0] + c[1] + c[2] > 0.0).count();
    assert!(lit > 64 * 64 / 2, "most pixels have samples: {lit}");
}

#[test]
fn the_default_scene_loads_and_renders() {
    let defines = vec![
        ("width".to_string(), "32".to_string()),
        ("height".to_string(), "16".to_string()),
        ("spp".to_string(), "2".to_string()),
    ];
    let scene = gonio_render::xml::load_scene_str(DEFAULT_SCENE, ".", &defines).expect("default scene loads");
    let p = PreparedScene::new(scene).unwrap();
    let out = render(
        &p,
        &RenderOptions::from_scene(&p.scene),
        &|_, _| {},
        &AtomicBool::new(false),
    );
    assert_eq!(out.complete_spp, 2);
    let mean: f32 = out.image.data.iter().map(|c| c[0] + c[1] + c[2]).sum::<f32>() / (3.0 * 32.0 * 16.0);
    assert!(mean > 0.05 && mean.is_finite(), "mean {mean}");
}

#[test]
fn a_scene_without_pixels_is_an_error() {
    let mut scene = gonio_render::xml::load_scene_str(
        DEFAULT_SCENE,
        ".",
        &[
            ("width".to_string(), "8".to_string()),
            ("height".to_string(), "8".to_string()),
        ],
    )
    .unwrap();
    scene.sensor.film.width = 0;
    let err = PreparedScene::new(scene).unwrap_err();
    assert!(err.to_string().contains("no pixels"), "{err}");
}

/// The render loop drives any integrator: a test integrator that writes the sample's film
/// position in named channels and splats a constant gets, per pixel, the mean position of its
/// samples (inside the pixel, box filter) plus the splat's share: N splats of c, divided by
/// the N camera samples, spread over the pixels.
#[test]
fn render_with_drives_any_integrator_with_named_channels_and_splats() {
    use gonio_render::film::Channels;
    use gonio_render::integrator::{CameraSample, Integrator};
    use gonio_render::render::render_with;

    struct Positions;
    impl Integrator for Positions {
        fn channels(&self) -> Channels {
            Channels::new(["pos.X", "pos.Y", "splat.A"])
        }
        fn splats(&self) -> bool {
            true
        }
        fn sample(
            &self,
            sample: &mut CameraSample<'_>,
            value: &mut [f32],
            splat: &mut dyn FnMut(glam::Vec2, &[f32]),
        ) {
            assert!(sample.ray.d.is_normalized());
            value.copy_from_slice(&[sample.film.x, sample.film.y, 0.0]);
            splat(sample.film, &[0.0, 0.0, 6.0]);
        }
    }
    let mut p = cornell(12, 10);
    p.scene.sensor.film.filter = gonio_render::scene::FilterDesc::Box { radius: 0.5 };
    let options = RenderOptions {
        spp: 4,
        seed: 3,
        pattern: Pattern::Sobol,
    };
    let out = render_with(&p, &Positions, &options, &|_, _| {}, &AtomicBool::new(false));
    assert_eq!(out.channels.names, ["pos.X", "pos.Y", "splat.A"]);
    assert_eq!(out.complete_spp, 4);
    for y in 0..10 {
        for x in 0..12 {
            let i = 3 * (y * 12 + x);
            let px = &out.channels.data[i..i + 3];
            assert!(
                px[0] > x as f32 && px[0] < x as f32 + 1.0,
                "pixel ({x}, {y}): {px:?}"
            );
            assert!(
                px[1] > y as f32 && px[1] < y as f32 + 1.0,
                "pixel ({x}, {y}): {px:?}"
            );
            assert!((px[2] - 6.0 / 120.0).abs() < 1e-6, "pixel ({x}, {y}): {px:?}");
        }
    }
    // No R, G, B channels: the colour image is black.
    assert!(out.image.data.iter().all(|c| *c == [0.0; 3]));
}

/// A sphere over a ground plane lit by a straight-down directional light (`direction="0,0,-1"`,
/// as in Mitsuba's own test scenes) casts a shadow. The shadow rays `-(0, 0, -1)` carry `-0.0`
/// components, which the BVH once set up with slabs of the wrong sign: the ground then came out
/// uniformly lit. The camera looks down at 45° at the shadow's centre, which the sphere does not
/// hide (the view ray passes the sphere's centre at √2 > r).
#[test]
fn straight_down_directional_light_casts_a_shadow() {
    let scene = r#"<scene version="3.0.0">
        <integrator type="path"><integer name="max_depth" value="3"/></integrator>
        <sensor type="perspective">
            <float name="fov" value="45"/>
            <transform name="to_world"><lookat origin="0,-10,10" target="0,0,0" up="0,0,1"/></transform>
            <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
            <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="64"/>
                <rfilter type="box"/></film>
        </sensor>
        <emitter type="directional"><vector name="direction" value="0,0,-1"/>
            <rgb name="irradiance" value="1"/></emitter>
        <shape type="sphere"><point name="center" value="0,0,2"/><float name="radius" value="1"/>
            <bsdf type="diffuse"/></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="20"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    </scene>"#;
    let p = PreparedScene::new(gonio_render::xml::load_scene_str(scene, ".", &[]).unwrap()).unwrap();
    let out = render(
        &p,
        &RenderOptions::from_scene(&p.scene),
        &|_, _| {},
        &AtomicBool::new(false),
    );
    let img = &out.image;
    let block_mean = |x0: usize, y0: usize| {
        let mut s = 0.0;
        for y in y0..y0 + 4 {
            for x in x0..x0 + 4 {
                s += img.data[y * img.width + x].iter().sum::<f32>() / 3.0;
            }
        }
        s / 16.0
    };
    // Lit ground: L = ρE/π = 0.5/π; the centre 4×4 block (±0.4 × ±0.5 units around the
    // origin) lies inside the unit shadow disc and sees only light reflected by the sphere.
    let lit = 0.5 / std::f32::consts::PI;
    let (left, right, centre) = (block_mean(2, 30), block_mean(58, 30), block_mean(30, 30));
    for side in [left, right] {
        assert!(
            (side - lit).abs() < 0.05 * lit,
            "lit ground {side} vs ρE/π = {lit}"
        );
    }
    assert!(
        centre < 0.1 * lit,
        "the shadow's centre {centre} should be dark (lit ground {lit})"
    );
}

/// A sphere's hits carry their uv wherever something reads it (a textured material or emitter,
/// AOVs) and skip its two inverse trigonometric functions elsewhere; the skipped uv is never
/// what an image shows.
#[test]
fn sphere_uv_is_computed_where_a_texture_or_an_aov_reads_it() {
    use gonio_render::accel::Intersect;
    use gonio_render::geometry::Ray;
    let scene = |integrator: &str| {
        format!(
            r#"<scene version="3.0.0">
    {integrator}
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>
    <shape type="sphere"><point name="center" value="-3, 0, 0"/>
        <bsdf type="diffuse"><texture type="checkerboard" name="reflectance"/></bsdf></shape>
    <shape type="sphere"><point name="center" value="0, 0, 0"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf></shape>
    <shape type="sphere"><point name="center" value="3, 0, 0"/>
        <emitter type="area"><texture type="checkerboard" name="radiance"/></emitter></shape>
</scene>"#
        )
    };
    let uv_at = |p: &PreparedScene, x: f32| {
        let ray = Ray::new(
            glam::Vec3::new(x + 0.3, 0.4, 5.0),
            glam::Vec3::new(0.0, 0.0, -1.0),
        );
        p.accel().intersect(&ray).expect("the sphere is hit").uv
    };
    let plain = PreparedScene::new(gonio_render::xml::load_scene_str(&scene(""), ".", &[]).unwrap()).unwrap();
    let flags: Vec<bool> = plain.accel().shapes().iter().map(|s| s.uv).collect();
    assert_eq!(flags, [true, false, true]);
    assert!(uv_at(&plain, -3.0).x > 0.0 && uv_at(&plain, 3.0).x > 0.0);
    assert_eq!(uv_at(&plain, 0.0), glam::Vec2::ZERO);
    let aov =
        r#"<integrator type="aov"><string name="aovs" value="uv:uv"/><integrator type="path"/></integrator>"#;
    let with_aov =
        PreparedScene::new(gonio_render::xml::load_scene_str(&scene(aov), ".", &[]).unwrap()).unwrap();
    assert!(with_aov.accel().shapes().iter().all(|s| s.uv));
    let (a, b) = (uv_at(&with_aov, 0.0), uv_at(&plain, -3.0));
    assert!(
        (a - b).abs().max_element() < 1e-6,
        "the same point of each sphere: {a} vs {b}"
    );
}
