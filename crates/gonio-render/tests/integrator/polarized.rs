//! The polarized mode against the physics (issue 12 §4), on scenes small enough to be exact:
//!
//! * **Malus's law**: unpolarized light of radiance L through two ideal linear polarizers at a
//!   relative angle θ arrives as L·½·cos²θ (Collett, *Polarized Light*, ch. 5); same seed with and
//!   without the sheets, so the ratio is exact up to round-off (the sheets are wavelength-free and
//!   the camera samples and wavelengths are drawn before the path).
//! * **Crossed polarizers** (θ = 90°) are black.
//! * **Depolarizing scenes** render the same intensity polarized as unpolarized (same seed: the
//!   same random numbers, and M₀₀ of every depolarizing matrix is the spectral value), and
//!   S1 = S2 = S3 = 0 exactly.
//! * **Brewster's angle**: light reflected by glass (η = 1.5) at θ_B = atan η is fully
//!   s-polarized: degree of polarization 1, along the `stokes` integrator's horizontal axis
//!   (x = d × up, here perpendicular to the plane of incidence), so S1 = +S0; its intensity is the
//!   unpolarized render's.

use super::*;
use gonio_render::image::ChannelImage;

/// Renders `xml` and returns every film channel; `polarized` forces the polarized mode.
fn render_channels(xml: &str, spp: u32, seed: u64, polarized: bool) -> ChannelImage {
    let mut scene = gonio_render::xml::load_scene_str(xml, ".", &[]).expect("test scene loads");
    scene.integrator.polarized |= polarized;
    let prepared = PreparedScene::new(scene).expect("test scene prepares");
    let mut options = RenderOptions::from_scene(&prepared.scene);
    options.spp = spp;
    options.seed = seed;
    render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).channels
}

/// The plane of channel `name`.
fn plane(img: &ChannelImage, name: &str) -> Vec<f64> {
    let n = img.names.len();
    let k = img
        .names
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no channel {name}: {:?}", img.names));
    img.data.iter().skip(k).step_by(n).map(|&v| v as f64).collect()
}

/// An orthographic camera on +z looking at a square area light in the plane z = 0 through
/// `sheets` (every ray at normal incidence: off it, the axes of two parallel sheets project onto
/// the beam's transverse plane at an angle other than θ, and Malus's law is not the test).
fn sheets_scene(integrator: &str, sheets: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    {integrator}
    <sensor type="orthographic">
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
            <rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="10"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
    </shape>
    {sheets}
</scene>"#
    )
}

fn polarizer_sheet(z: f32, theta: f32) -> String {
    format!(
        r#"<shape type="rectangle">
        <transform name="to_world"><scale value="10"/><translate z="{z}"/></transform>
        <bsdf type="polarizer"><spectrum name="theta" value="{theta}"/></bsdf>
    </shape>"#
    )
}

const PATH: &str = r#"<integrator type="path"/>"#;
const STOKES_PATH: &str = r#"<integrator type="stokes"><integrator type="path"/></integrator>"#;

#[test]
fn malus_law_through_two_polarizers() {
    let open = render_channels(&sheets_scene(PATH, ""), 4, 7, true);
    let reference = plane(&open, "G");
    assert!(reference.iter().all(|&v| v > 0.1), "the light is seen");
    for theta in [0.0f32, 30.0, 45.0, 60.0, 90.0] {
        let sheets = polarizer_sheet(1.0, 0.0) + &polarizer_sheet(2.0, theta);
        let img = render_channels(&sheets_scene(PATH, &sheets), 4, 7, false);
        let expected = 0.5 * (theta as f64).to_radians().cos().powi(2);
        for c in ["R", "G", "B"] {
            for (a, b) in plane(&img, c).iter().zip(plane(&open, c)) {
                assert!(
                    (a - expected * b).abs() <= 1e-4 * b.abs() + 1e-6,
                    "theta {theta}: channel {c}: {a} vs ½cos²θ·L = {}",
                    expected * b
                );
            }
        }
    }
}

#[test]
fn crossed_polarizers_are_black_and_aligned_ones_pass_half() {
    let crossed = polarizer_sheet(1.0, 20.0) + &polarizer_sheet(2.0, 110.0);
    let img = render_channels(&sheets_scene(STOKES_PATH, &crossed), 4, 3, false);
    let peak = img.data.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    assert!(peak < 1e-6, "crossed polarizers pass {peak}");
    // One polarizer: half the light, fully linearly polarized (DoP 1).
    let one = render_channels(
        &sheets_scene(STOKES_PATH, &polarizer_sheet(1.0, 20.0)),
        4,
        3,
        false,
    );
    let (s0, s1, s2, s3) = (
        plane(&one, "S0.G"),
        plane(&one, "S1.G"),
        plane(&one, "S2.G"),
        plane(&one, "S3.G"),
    );
    for i in 0..s0.len() {
        let dop = (s1[i] * s1[i] + s2[i] * s2[i] + s3[i] * s3[i]).sqrt() / s0[i];
        assert!(
            (dop - 1.0).abs() < 1e-3,
            "pixel {i}: degree of polarization {dop}"
        );
        assert!(
            s3[i].abs() < 1e-4 * s0[i],
            "pixel {i}: linear light has S3 = {}",
            s3[i]
        );
    }
}

#[test]
fn depolarizing_scene_renders_the_same_polarized() {
    let extra = r#"<shape type="sphere"><point name="center" value="0.3, 0.5, 0.2"/><float name="radius" value="0.4"/>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.4, 0.2"/></bsdf></shape>"#;
    let unpolarized_xml = scene_xml("", SQUARE_LIGHT, extra);
    let stokes_xml = unpolarized_xml.replace(
        r#"<integrator type="path"></integrator>"#,
        r#"<integrator type="stokes"><integrator type="path"/></integrator>"#,
    );
    let a = render_channels(&unpolarized_xml, 16, 5, false);
    let b = render_channels(&stokes_xml, 16, 5, false);
    for c in ["R", "G", "B"] {
        let (x, y, s0) = (plane(&a, c), plane(&b, c), plane(&b, &format!("S0.{c}")));
        for i in 0..x.len() {
            assert!(
                (x[i] - y[i]).abs() <= 1e-5 * x[i].abs() + 1e-7,
                "{c} pixel {i}: {} vs {}",
                x[i],
                y[i]
            );
            assert_eq!(y[i], s0[i], "S0 is the image");
        }
        for s in ["S1", "S2", "S3"] {
            assert!(
                plane(&b, &format!("{s}.{c}")).iter().all(|&v| v == 0.0),
                "{s}.{c} is not zero"
            );
        }
    }
}

#[test]
fn brewster_reflection_is_fully_s_polarized() {
    let tb = 1.5f64.atan();
    let (s, c) = (5.0 * tb.sin(), 5.0 * tb.cos());
    let xml = format!(
        r#"<scene version="3.0.0">
    <integrator type="stokes"><integrator type="path"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="1"/>
        <transform name="to_world"><lookat origin="0, {ny}, {c}" target="0, 0, 0" up="0, 0, 1"/></transform>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
            <rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="10"/></transform>
        <bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="2"/><lookat origin="0, {s}, {c}" target="0, 0, 0" up="0, 0, 1"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter>
    </shape>
</scene>"#,
        ny = -s
    );
    let pol = render_channels(&xml, 64, 11, false);
    let unpol = render_channels(&xml.replace(STOKES_PATH, PATH), 64, 11, false);
    let (s0, s1, s2, s3) = (
        plane(&pol, "S0.G"),
        plane(&pol, "S1.G"),
        plane(&pol, "S2.G"),
        plane(&pol, "S3.G"),
    );
    let g = plane(&unpol, "G");
    let mut seen = 0;
    for i in 0..s0.len() {
        assert!(
            (s0[i] - g[i]).abs() <= 1e-5 * g[i].abs() + 1e-7,
            "pixel {i}: S0 {} vs unpolarized {}",
            s0[i],
            g[i]
        );
        if s0[i] <= 0.0 {
            continue;
        }
        seen += 1;
        let dop = (s1[i] * s1[i] + s2[i] * s2[i] + s3[i] * s3[i]).sqrt() / s0[i];
        assert!(
            dop > 0.999,
            "pixel {i}: degree of polarization {dop} at Brewster's angle"
        );
        assert!(
            s1[i] / s0[i] > 0.999,
            "pixel {i}: S1/S0 = {} (s-polarized is horizontal)",
            s1[i] / s0[i]
        );
    }
    assert!(seen > 32, "the reflection is seen ({seen} pixels)");
}

/// A quarter-wave retarder with its fast axis at 45° to a linear polarizer turns the light
/// circular: |S3| = S0, S1 = S2 = 0 (Goldstein, *Polarized Light*, §6.4). `theta` and `delta`
/// given as Mitsuba's scenes give them, as `<spectrum>` values.
#[test]
fn quarter_wave_plate_at_45_degrees_makes_circular_light() {
    let sheets = polarizer_sheet(1.0, 0.0)
        + r#"<shape type="rectangle">
        <transform name="to_world"><scale value="10"/><translate z="2"/></transform>
        <bsdf type="retarder"><spectrum name="theta" value="45"/><spectrum name="delta" value="90"/></bsdf>
    </shape>"#;
    let img = render_channels(&sheets_scene(STOKES_PATH, &sheets), 4, 9, false);
    let (s0, s1, s2, s3) = (
        plane(&img, "S0.G"),
        plane(&img, "S1.G"),
        plane(&img, "S2.G"),
        plane(&img, "S3.G"),
    );
    for i in 0..s0.len() {
        assert!(s0[i] > 0.1, "pixel {i}: the light passes ({})", s0[i]);
        assert!(
            (s3[i].abs() - s0[i]).abs() < 1e-3 * s0[i],
            "pixel {i}: S3 {} vs S0 {}",
            s3[i],
            s0[i]
        );
        assert!(
            s1[i].abs().max(s2[i].abs()) < 1e-3 * s0[i],
            "pixel {i}: S1 {} S2 {}",
            s1[i],
            s2[i]
        );
    }
}

/// The scenes that render polarized without being told: a `stokes` integrator, or a material
/// that asks for it, also when a wrapper holds it (Mitsuba's users wrap a `pplastic` in a
/// `twosided`); a depolarizing scene does not.
#[test]
fn scenes_that_ask_for_polarization_are_recognised_through_wrappers() {
    let asks = |bsdf: &str, integrator: &str| {
        let sheet = format!(
            r#"<shape type="rectangle"><transform name="to_world"><translate z="1"/></transform>{bsdf}</shape>"#
        );
        gonio_render::xml::load_scene_str(&sheets_scene(integrator, &sheet), ".", &[])
            .expect("test scene loads")
            .asks_for_polarization()
    };
    assert!(asks(r#"<bsdf type="pplastic"/>"#, PATH));
    assert!(asks(
        r#"<bsdf type="twosided"><bsdf type="pplastic"/></bsdf>"#,
        PATH
    ));
    assert!(asks(
        r#"<bsdf type="blendbsdf"><float name="weight" value="0.5"/><bsdf type="diffuse"/><bsdf type="retarder"/></bsdf>"#,
        PATH
    ));
    assert!(asks(
        r#"<bsdf type="mask"><float name="opacity" value="0.5"/><bsdf type="circular"/></bsdf>"#,
        PATH
    ));
    assert!(asks(r#"<bsdf type="diffuse"/>"#, STOKES_PATH));
    assert!(!asks(
        r#"<bsdf type="twosided"><bsdf type="plastic"/></bsdf>"#,
        PATH
    ));
}

/// Angles are signed, as in Mitsuba: a retarder at θ = −30° is the one at 150° (a linear
/// retarder's axis is defined modulo 180°), for a float and for a one-value spectrum alike.
#[test]
fn negative_angles_load_and_mean_the_same_axis() {
    let sheet = |theta: &str| {
        format!(
            r#"<shape type="rectangle"><transform name="to_world"><scale value="10"/><translate z="1"/></transform>
            <bsdf type="retarder">{theta}<float name="delta" value="90"/></bsdf></shape>{}"#,
            polarizer_sheet(0.5, 0.0)
        )
    };
    let a = render_channels(
        &sheets_scene(STOKES_PATH, &sheet(r#"<float name="theta" value="-30"/>"#)),
        4,
        1,
        true,
    );
    let b = render_channels(
        &sheets_scene(STOKES_PATH, &sheet(r#"<spectrum name="theta" value="150"/>"#)),
        4,
        1,
        true,
    );
    for ch in ["S0.G", "S1.G", "S2.G", "S3.G"] {
        let (pa, pb) = (plane(&a, ch), plane(&b, ch));
        for (x, y) in pa.iter().zip(&pb) {
            assert!((x - y).abs() <= 1e-5 * (1.0 + x.abs()), "{ch}: {x} vs {y}");
        }
    }
    // And the retarder does something: circular light after a quarter wave at 30° off the axis.
    let s3 = plane(&a, "S3.G").iter().sum::<f64>().abs();
    assert!(s3 > 0.1 * plane(&a, "S0.G").iter().sum::<f64>(), "S3 {s3}");
}
