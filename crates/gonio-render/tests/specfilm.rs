//! `specfilm`: one channel per spectral band, cⱼ = ∫ Sⱼ(λ) L(λ) dλ, against Mitsuba 3.9.1 and
//! against the integral itself; its errors and its combinations with other plugins. And a
//! sensor's `srf`, one response function that filters the radiance before its colour.
//!
//! The scene (`testdata/specfilm/bands.xml`, ours): four bands (three triangles in the visible,
//! one flat band at 780–900 nm), a diffuse sphere of reflectance rgb (0.8, 0.3, 0.1) under a
//! uniform sky of radiance 1. Mitsuba's render, `bands.exr`, is the mean of four seeds at 4096
//! spp (`make_reference.py`).

use gonio_render::image::ChannelImage;
use gonio_render::render::{PreparedScene, RenderOptions, render};
use gonio_render::xml::{ErrorKind, load_scene_file, load_scene_str};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

fn testdata() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/specfilm")
}

const BANDS: [&str; 4] = ["band1_blue", "band2_green", "band3_red", "band4_nir"];

fn render_scene(scene: gonio_render::scene::Scene, spp: u32, seed: u64) -> ChannelImage {
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let mut options = RenderOptions::from_scene(&prepared.scene);
    options.spp = spp;
    options.seed = seed;
    render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).channels
}

fn channel(img: &ChannelImage, name: &str) -> Vec<f64> {
    crate::layers::channel(img, name)
        .into_iter()
        .map(f64::from)
        .collect()
}

/// The mean over the pixels (x, y) with `x0 ≤ x < x1`, `y0 ≤ y < y1` of a 32-pixel-wide image.
fn block(v: &[f64], (x0, x1): (usize, usize), (y0, y1): (usize, usize)) -> f64 {
    let mut s = 0.0;
    for y in y0..y1 {
        for x in x0..x1 {
            s += v[y * 32 + x];
        }
    }
    s / ((x1 - x0) * (y1 - y0)) as f64
}

#[test]
fn a_spectral_film_records_each_band_as_mitsuba_does() {
    let scene = || load_scene_file(testdata().join("bands.xml"), &[]).expect("bands.xml loads");
    let reference = ChannelImage::read(testdata().join("bands.exr")).expect("Mitsuba's render reads");
    assert_eq!(reference.names, BANDS);
    // Two seeds: their mean is the estimate, their difference its noise.
    let (a, b) = (render_scene(scene(), 256, 1), render_scene(scene(), 256, 2));
    assert_eq!(a.names, BANDS, "the channels are the bands, in the file's order");
    // The sphere's centre (it covers about ±10 pixels around (16, 12)), the sky's corner, all.
    let regions = [
        ("sphere", (12, 20), (8, 16)),
        ("sky", (0, 4), (0, 4)),
        ("image", (0, 32), (0, 24)),
    ];
    for name in BANDS {
        let (ca, cb, cr) = (channel(&a, name), channel(&b, name), channel(&reference, name));
        for (region, xs, ys) in regions {
            let ours = 0.5 * (block(&ca, xs, ys) + block(&cb, xs, ys));
            let mitsuba = block(&cr, xs, ys);
            // Standard error of the two renders' block mean from their pixels' differences:
            // var(mean of two) ≈ (a − b)²/4 per pixel. Mitsuba's (32× the samples) adds ≲ 1/5.
            let diff: Vec<f64> = ca.iter().zip(&cb).map(|(x, y)| (x - y) * (x - y) / 4.0).collect();
            let n = ((xs.1 - xs.0) * (ys.1 - ys.0)) as f64;
            let se = (block(&diff, xs, ys) / n).sqrt() * 1.2;
            // 4σ, and 0.1 % for the reflectance's uplift (gonio refines the RGB table's
            // coefficients, Mitsuba interpolates them).
            let tolerance = 4.0 * se + 1e-3 * mitsuba;
            assert!(
                (ours - mitsuba).abs() < tolerance,
                "{name}, {region}: gonio {ours:.5} against Mitsuba {mitsuba:.5} (± {tolerance:.5})"
            );
        }
    }
}

/// A single band under a flat spectrum: the wavelengths are drawn in proportion to the band, so
/// every sample records exactly its integral times the radiance (no spectral noise), here
/// 2 × ∫ of a triangle of height 3 over 500–600 nm on a pedestal of 1 = 2 × 200.
#[test]
fn one_band_under_a_uniform_sky_records_its_integral_in_every_pixel() {
    let xml = r#"<scene version="3.0.0">
        <sensor type="perspective">
            <film type="specfilm"><integer name="width" value="6"/><integer name="height" value="4"/>
                <spectrum name="band" value="500:1, 550:3, 600:1"/></film>
        </sensor>
        <emitter type="constant"><spectrum name="radiance" value="2"/></emitter>
    </scene>"#;
    let img = render_scene(load_scene_str(xml, ".", &[]).unwrap(), 16, 3);
    assert_eq!(img.names, ["band"]);
    for v in channel(&img, "band") {
        assert!((v - 400.0).abs() < 400.0 * 1e-4, "{v}");
    }
}

/// The `stokes` integrator on a spectral film: S0..S3 in the bands' channels, S0 equal to the
/// image (a depolarizing scene: S1..S3 are 0).
#[test]
fn the_stokes_layers_of_a_spectral_film_are_per_band() {
    let xml = r#"<scene version="3.0.0">
        <integrator type="stokes"><integrator type="path"/></integrator>
        <sensor type="perspective">
            <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
            <film type="specfilm"><integer name="width" value="4"/><integer name="height" value="3"/>
                <spectrum name="a" value="400:1, 500:1"/><spectrum name="b" value="550:0, 650:2"/></film>
        </sensor>
        <emitter type="constant"><spectrum name="radiance" value="1"/></emitter>
        <shape type="sphere"><bsdf type="diffuse"/></shape>
    </scene>"#;
    let img = render_scene(load_scene_str(xml, ".", &[]).unwrap(), 16, 1);
    let mut expected = vec!["a".to_string(), "b".to_string()];
    for s in ["S0", "S1", "S2", "S3"] {
        expected.extend(["a", "b"].map(|c| format!("{s}.{c}")));
    }
    assert_eq!(img.names, expected);
    for c in ["a", "b"] {
        assert_eq!(channel(&img, c), channel(&img, &format!("S0.{c}")));
        assert!(channel(&img, &format!("S1.{c}")).iter().all(|v| v.abs() < 1e-5));
    }
    assert!(
        channel(&img, "a").iter().all(|&v| v > 0.0),
        "{:?}",
        channel(&img, "a")
    );
}

fn film_error(film: &str, integrator: &str) -> gonio_render::xml::SceneError {
    let xml = format!(
        "<scene version=\"3.0.0\">\n{integrator}\n<sensor type=\"perspective\">\n{film}\n</sensor>\n</scene>\n"
    );
    match load_scene_str(&xml, ".", &[]) {
        Ok(_) => panic!("expected an error for\n{xml}"),
        Err(e) => e,
    }
}

#[test]
fn a_spectral_film_without_usable_bands_is_refused_with_its_location() {
    // No band.
    let e = film_error(r#"<film type="specfilm"/>"#, "");
    assert_eq!((e.kind, e.location.line), (ErrorKind::BadValue, 4), "{e}");
    assert!(e.to_string().contains("at least one spectral band"), "{e}");
    // Bands that are zero everywhere.
    let e = film_error(
        r#"<film type="specfilm"><spectrum name="x" value="400:0, 500:0"/></film>"#,
        "",
    );
    assert!(e.to_string().contains("zero everywhere"), "{e}");
    // A wavelength that is not positive.
    let e = film_error(
        r#"<film type="specfilm"><spectrum name="x" value="-100:1, 500:1"/></film>"#,
        "",
    );
    assert!(e.to_string().contains("-100 nm"), "{e}");
    // A negative value, named.
    let e = film_error(
        r#"<film type="specfilm"><spectrum name="x" value="400:1, 500:-2"/></film>"#,
        "",
    );
    assert_eq!(e.kind, ErrorKind::BadValue, "{e}");
    assert!(e.to_string().contains("-2"), "{e}");
    // A number is not a band (Mitsuba's film takes spectrum objects only).
    let e = film_error(
        r#"<film type="specfilm"><spectrum name="x" value="400:1, 500:1"/><float name="y" value="1"/></film>"#,
        "",
    );
    assert_eq!(e.kind, ErrorKind::UnusedParameter, "{e}");
    // hdrfilm's own parameters are not specfilm's.
    let e = film_error(
        r#"<film type="specfilm"><spectrum name="x" value="400:1, 500:1"/><string name="pixel_format" value="rgb"/></film>"#,
        "",
    );
    assert_eq!(e.kind, ErrorKind::UnusedParameter, "{e}");
    // The layered integrators read colour.
    let e = film_error(
        r#"<film type="specfilm"><spectrum name="x" value="400:1, 500:1"/></film>"#,
        r#"<integrator type="aov"><string name="aovs" value="d:depth"/></integrator>"#,
    );
    assert_eq!((e.kind, e.location.line), (ErrorKind::BadValue, 2), "{e}");
    assert!(e.to_string().contains("specfilm"), "{e}");
}

/// A sensor's spectral response function (`srf`): the image is the colour of S(λ)·L(λ). A
/// radiance meter aimed at a diffuse sphere under a uniform sky of radiance 1 sees L = ρ(λ)
/// exactly, so its value is linear sRGB of ∫ x̄ȳz̄ ρ S dλ / ∫ ȳ dλ. Mitsuba 3.9.1
/// `scalar_spectral` on the same scene (8 × 65536 samples): (0.050229, 0.189304, −0.021738)
/// ± (7e-5, 6e-5, 9e-6), within 0.4 % of this integral (its normalization of Y by 106.7503
/// instead of 106.857, and its tabulated uplift of ρ, account for such differences).
#[test]
fn a_sensors_response_function_filters_the_radiance_before_the_colour() {
    use gonio_core::color::{CIE_Y_INTEGRAL, cie_xyz, linear_srgb_from_xyz};
    use gonio_core::spectra::{Extrapolation, PiecewiseLinear, Spectrum};
    let xml = r#"<scene version="3.0.0">
        <integrator type="path"/>
        <sensor type="radiancemeter">
            <point name="origin" x="0" y="0" z="3"/>
            <vector name="direction" x="0" y="0" z="-1"/>
            <spectrum name="srf" value="500:0.0, 550:1.0, 600:0.0"/>
            <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>
                <rfilter type="box"/></film>
        </sensor>
        <emitter type="constant"><spectrum name="radiance" value="1.0"/></emitter>
        <shape type="sphere"><bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.3, 0.1"/></bsdf></shape>
    </scene>"#;
    let img = render_scene(load_scene_str(xml, ".", &[]).unwrap(), 4096, 1);
    assert_eq!(img.names, ["R", "G", "B"]);
    let srf = Spectrum::piecewise(
        PiecewiseLinear::new(
            vec![500.0, 550.0, 600.0],
            vec![0.0, 1.0, 0.0],
            Extrapolation::Zero,
        )
        .unwrap(),
    );
    let rho = Spectrum::rgb_albedo([0.8, 0.3, 0.1]);
    let n = 100_000;
    let mut xyz = glam::DVec3::ZERO;
    for i in 0..n {
        let l = 500.0 + 100.0 * (i as f32 + 0.5) / n as f32;
        xyz += cie_xyz(l).as_dvec3() * (rho.eval(l) * srf.eval(l)) as f64 * (100.0 / n as f64);
    }
    let exact = linear_srgb_from_xyz((xyz / CIE_Y_INTEGRAL as f64).as_vec3());
    let mitsuba = [0.050229, 0.189304, -0.021738];
    for c in 0..3 {
        let v = img.data[c];
        assert!(
            (v - exact[c]).abs() < 1e-4 * exact.abs().max_element(),
            "channel {c}: {v} vs {}",
            exact[c]
        );
        assert!(
            (v - mitsuba[c]).abs() < 4e-3 * 0.19,
            "channel {c}: {v} vs Mitsuba's {}",
            mitsuba[c]
        );
    }
    // Not with a spectral film, which has its own bands (Mitsuba refuses it too).
    let both = xml.replace(
        r#"<film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/>"#,
        r#"<film type="specfilm"><integer name="width" value="1"/><integer name="height" value="1"/><spectrum name="b" value="400:1, 500:1"/>"#,
    );
    let e = load_scene_str(&both, ".", &[]).unwrap_err();
    assert_eq!((e.kind, e.location.line), (ErrorKind::BadValue, 6), "{e}");
    assert!(e.to_string().contains("srf"), "{e}");
}

/// The bands recorded by light paths: `ptracer` splats every connection to the camera through
/// the film's bands, and must see the sphere as `path` does (the centre block's mean of each
/// band, two seeds of each, within 4 standard errors of their difference).
#[test]
fn light_paths_splat_the_same_bands_as_camera_paths() {
    use gonio_render::scene::IntegratorKind;
    let render_with = |kind: IntegratorKind, seed: u64| {
        let mut scene = load_scene_file(testdata().join("bands.xml"), &[]).expect("bands.xml loads");
        scene.integrator.kind = kind;
        render_scene(scene, 1024, seed)
    };
    let (xs, ys) = ((12, 20), (8, 16));
    let mean_and_var = |a: &ChannelImage, b: &ChannelImage, name: &str| {
        let (ca, cb) = (channel(a, name), channel(b, name));
        let diff: Vec<f64> = ca.iter().zip(&cb).map(|(x, y)| (x - y) * (x - y) / 4.0).collect();
        let n = ((xs.1 - xs.0) * (ys.1 - ys.0)) as f64;
        (
            0.5 * (block(&ca, xs, ys) + block(&cb, xs, ys)),
            block(&diff, xs, ys) / n,
        )
    };
    let (p1, p2) = (
        render_with(IntegratorKind::Path, 1),
        render_with(IntegratorKind::Path, 2),
    );
    let (t1, t2) = (
        render_with(IntegratorKind::PTracer, 1),
        render_with(IntegratorKind::PTracer, 2),
    );
    assert_eq!(t1.names, BANDS);
    for name in BANDS {
        let (path, var_path) = mean_and_var(&p1, &p2, name);
        let (light, var_light) = mean_and_var(&t1, &t2, name);
        let se = (var_path + var_light).sqrt();
        assert!(
            (path - light).abs() < 4.0 * se,
            "{name}: path {path:.4}, ptracer {light:.4} (± {se:.4})"
        );
        assert!(light > 0.0, "{name}: no light path reached the film");
    }
}
