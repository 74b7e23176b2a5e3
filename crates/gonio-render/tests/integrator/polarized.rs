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
    // The spectral render with the polarized one's estimator: the polarized path tracer
    // chooses between reflection and refraction by the Fresnel coin, where the spectral one
    // would add the lamp's reflection whole (`split_escapes`) and follow both lobes of the glass
    // it sees (`split_visible_glass`).
    let unpol = render_channels(
        &xml.replace(
            STOKES_PATH,
            r#"<integrator type="path"><boolean name="split_escapes" value="false"/><boolean name="split_visible_glass" value="false"/></integrator>"#,
        ),
        64,
        11,
        false,
    );
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

// ---------------------------------------------------------------------------------------------
// Caustic light subpaths in polarized mode (`integrator/caustics`: the subpath carries Mueller
// matrices in importance mode, joined to the camera path and to the camera in light order).

/// The mirror scene of `tests/caustics.rs` (a Lambertian floor lit by a small sphere and by its
/// image in a perfect mirror, `max_depth` 3), smaller, under `integrator`.
fn caustic_mirror_scene(integrator: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    {integrator}
    <sensor type="perspective">
        <float name="fov" value="22"/>
        <transform name="to_world"><lookat origin="-0.5, 4, 0" target="-0.5, 0, 0" up="0, 0, -1"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="100"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale x="2" y="1.5"/><rotate y="1" angle="-90"/><translate x="1"/></transform>
        <bsdf type="conductor"><string name="material" value="none"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.3, 1, 0"/><float name="radius" value="0.1"/>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter>
    </shape>
</scene>"#
    )
}

const CAUSTIC_PATH: &str = r#"<integrator type="path"><integer name="max_depth" value="3"/></integrator>"#;
const CAUSTIC_STOKES: &str = r#"<integrator type="stokes"><integrator type="path"><integer name="max_depth" value="3"/></integrator></integrator>"#;

/// True when the scene's path tracer traces light subpaths (polarized or not).
fn traces_caustics(xml: &str) -> bool {
    let scene = gonio_render::xml::load_scene_str(xml, ".", &[]).expect("test scene loads");
    let prepared = PreparedScene::new(scene).expect("test scene prepares");
    prepared.integrator().traces_caustics()
}

/// Through a perfect mirror (which keeps unpolarized light unpolarized) onto a Lambertian floor,
/// the polarized render with light subpaths is the spectral one, pixel by pixel (same seed: the
/// same camera samples, light subpaths and MIS weights; M₀₀ of every matrix on these paths is the
/// spectral value), so it keeps `tests/caustics.rs`'s closed form; the floor depolarizes, so
/// S1 = S2 = S3 = 0 exactly. Both renders trace light subpaths.
#[test]
fn polarized_light_subpaths_through_a_mirror_equal_the_spectral_ones() {
    let (spectral, stokes) = (
        caustic_mirror_scene(CAUSTIC_PATH),
        caustic_mirror_scene(CAUSTIC_STOKES),
    );
    assert!(traces_caustics(&spectral) && traces_caustics(&stokes));
    let a = render_channels(&spectral, 16, 3, false);
    let b = render_channels(&stokes, 16, 3, false);
    let off = render_channels(
        &stokes.replace(
            "<integer name=\"max_depth\" value=\"3\"/>",
            "<integer name=\"max_depth\" value=\"3\"/><boolean name=\"caustic_paths\" value=\"false\"/>",
        ),
        16,
        3,
        false,
    );
    let mut differs = 0;
    for c in ["R", "G", "B"] {
        let (x, y, s0, z) = (
            plane(&a, c),
            plane(&b, c),
            plane(&b, &format!("S0.{c}")),
            plane(&off, c),
        );
        for i in 0..x.len() {
            assert!(
                (x[i] - y[i]).abs() <= 1e-5 * x[i].abs() + 1e-7,
                "{c} pixel {i}: spectral {} vs polarized {}",
                x[i],
                y[i]
            );
            assert_eq!(y[i], s0[i], "S0 is the image");
            differs += ((y[i] - z[i]).abs() > 1e-4 * y[i].abs()) as u32;
        }
        for s in ["S1", "S2", "S3"] {
            assert!(
                plane(&b, &format!("{s}.{c}")).iter().all(|&v| v == 0.0),
                "{s}.{c} is not zero behind a Lambertian floor"
            );
        }
    }
    // The light subpaths did take part (without them the same seed gives another image: 51 of
    // the 768 values differ at this seed).
    assert!(
        differs > 10,
        "only {differs} pixel values changed with light subpaths"
    );
}

/// A small light, its reflection in a vertical glass-like mirror (a conductor of real index 1.5:
/// R_s > R_p, p vanishing at Brewster's angle, here reached near x = 0.5 on the floor) and a
/// rough glass-like floor, which keeps much of the s polarization towards the camera: `L S D E`
/// caustics whose Stokes vectors matter.
fn brewster_caustic_scene(caustics: bool) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="stokes"><integrator type="path"><integer name="max_depth" value="3"/>
        <boolean name="caustic_paths" value="{caustics}"/></integrator></integrator>
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <transform name="to_world"><lookat origin="-0.7, 2, 0" target="0.5, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
            <rfilter type="box"/></film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="100"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="roughconductor"><float name="alpha" value="0.3"/>
            <spectrum name="eta" value="1.5"/><spectrum name="k" value="0"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale x="2" y="2"/><rotate y="1" angle="-90"/><translate x="1"/></transform>
        <bsdf type="conductor"><spectrum name="eta" value="1.5"/><spectrum name="k" value="0"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" value="0.7, 1.2, 0"/><float name="radius" value="0.1"/>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter>
    </shape>
</scene>"#
    )
}

/// Image means of channels `names` over `runs` renders (seeds `seed0..`): (mean, standard error
/// of the mean) per channel.
fn channel_means(xml: &str, names: &[&str], spp: u32, seed0: u64, runs: u64) -> Vec<(f64, f64)> {
    let per_run: Vec<Vec<f64>> = (0..runs)
        .map(|k| {
            let img = render_channels(xml, spp, seed0 + k, false);
            names
                .iter()
                .map(|c| {
                    let p = plane(&img, c);
                    p.iter().sum::<f64>() / p.len() as f64
                })
                .collect()
        })
        .collect();
    (0..names.len())
        .map(|j| {
            let xs: Vec<f64> = per_run.iter().map(|r| r[j]).collect();
            let m = xs.iter().sum::<f64>() / runs as f64;
            let var = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (runs as f64 - 1.0);
            (m, (var / runs as f64).sqrt())
        })
        .collect()
}

/// With and without light subpaths the polarized render has the same expectation in every
/// Stokes component (4 standard errors of the difference of the means over independent renders):
/// the subpath's Mueller matrices, their frames and its connections in light order estimate what
/// the path tracer alone estimates. The image is polarized (S1, S2 well away from zero), so a
/// rotation or an order error would show.
#[test]
fn polarized_light_subpaths_keep_the_expectation_of_every_stokes_component() {
    let names = ["S0.G", "S1.G", "S2.G"];
    let on = channel_means(&brewster_caustic_scene(true), &names, 16, 10, 6);
    let off = channel_means(&brewster_caustic_scene(false), &names, 16, 20, 6);
    for (k, c) in names.iter().enumerate() {
        let ((m_on, se_on), (m_off, se_off)) = (on[k], off[k]);
        let se = (se_on * se_on + se_off * se_off).sqrt();
        println!("{c}: with light subpaths {m_on:.5} ± {se_on:.1e}, without {m_off:.5} ± {se_off:.1e}");
        assert!(
            (m_on - m_off).abs() < 4.0 * se,
            "{c}: {m_on} with light subpaths, {m_off} without (se {se})"
        );
    }
    let dop = (on[1].0.powi(2) + on[2].0.powi(2)).sqrt() / on[0].0;
    assert!(
        dop > 0.02,
        "the image should be polarized: mean S1, S2 / S0 = {dop}"
    );
}

/// The light subpaths' own contribution (their connections to the camera, summed over many
/// subpaths) is polarized where the physics says so: after the glass-like mirror's reflection
/// (s enhanced) and the floor's, the summed Stokes vector has a clear linear part; every splat is a
/// physical Stokes vector (|S1..S3| ≤ S0) in the basis of the beam towards the camera.
#[test]
fn light_subpath_splats_carry_physical_polarized_stokes_vectors() {
    use gonio_core::mueller::Mueller;
    use gonio_core::weight::Weight;
    use gonio_render::integrator::caustics::LightSubpath;
    use gonio_render::integrator::polarized::stokes_at_sensor;
    let scene =
        gonio_render::xml::load_scene_str(&brewster_caustic_scene(true), ".", &[]).expect("test scene loads");
    let up = scene.sensor.to_world.transform_vector3(glam::Vec3::Y);
    let prepared = PreparedScene::new(scene).expect("test scene prepares");
    let pt = prepared.integrator();
    assert!(pt.is_polarized() && pt.traces_caustics());
    let (mut sum, mut splats) = ([0.0f64; 4], 0u32);
    let n = 50_000u64;
    for k in 0..n {
        let mut rng = gonio_core::rng::Pcg32::new(k, 7);
        let mut wl = gonio_core::SampledWavelengths::sample_visible((k as f32 + 0.5) / n as f32);
        let mut light = LightSubpath::<Mueller>::empty();
        let mut to_film = |_p: glam::Vec2, m: Mueller, _wl: &gonio_core::SampledWavelengths| {
            let (_, out) = m.frames().expect("a matrix after the glass has frames");
            let s = stokes_at_sensor(&m, -out.forward(), up);
            let s = gonio_core::mueller::Stokes::new(
                s,
                gonio_core::mueller::StokesBasis::implicit(out.forward()),
            );
            assert!(s.is_physical(1e-3), "splat {k}: {:?}", s.components());
            let c = s.components();
            for i in 0..4 {
                sum[i] += c[i][0] as f64;
            }
            assert!(m.intensity()[0] >= 0.0);
            splats += 1;
        };
        pt.trace_light_path(&mut rng, &mut wl, &mut to_film, &mut light);
    }
    let dop = (sum[1] * sum[1] + sum[2] * sum[2]).sqrt() / sum[0];
    println!("{splats} splats, summed Stokes {sum:?}, linear degree of polarization {dop:.3}");
    assert!(
        splats > 100,
        "only {splats} light-subpath connections to the camera (168 at these seeds)"
    );
    assert!(
        dop > 0.2,
        "the caustic seen by the camera should be polarized: {dop}"
    );
    // The mirror's s axis is the world z axis (the planes of incidence contain x and y), which is
    // the sensor's horizontal axis (d × up for a camera in the x-y plane): S1 > 0.
    assert!(
        sum[1] > 0.5 * sum[0],
        "s-polarized light should give S1 > 0: {sum:?}"
    );
    assert!(sum[3].abs() < sum[0], "S3 {}", sum[3]);
}

/// The glass and mirror balls of `tests/caustics.rs`, where most of the light on the floor comes
/// through light subpaths: polarized (`stokes`) and spectral renders agree in S0 within noise.
/// Measure: relMSE of 4 × 4-block means (`compare::block_relmse`); the threshold is 1.5 × the
/// level of two independent renders of the same mode (the mean of the spectral and the polarized
/// pairs), the level a difference of expectations would exceed.
#[test]
fn polarized_caustics_equal_the_spectral_image_in_s0_within_noise() {
    use gonio_render::compare::block_relmse;
    let xml = |integrator: &str| {
        format!(
            r#"<scene version="3.0.0">
    {integrator}
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0.2, 3.2" target="0, -0.3, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/></film>
    </sensor>
    <bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.7"/></bsdf>
    <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/><translate y="-1"/></transform><ref id="white"/></shape>
    <shape type="rectangle"><transform name="to_world"><translate z="-1"/></transform><ref id="white"/></shape>
    <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="90"/><translate y="1"/></transform><ref id="white"/></shape>
    <shape type="sphere"><point name="center" value="0.4, -0.6, 0"/><float name="radius" value="0.4"/><bsdf type="dielectric"/></shape>
    <shape type="sphere"><point name="center" value="-0.45, -0.65, -0.3"/><float name="radius" value="0.35"/>
        <bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.15"/><rotate x="1" angle="90"/><translate y="0.99"/></transform>
        <emitter type="area"><rgb name="radiance" value="20"/></emitter>
    </shape>
</scene>"#
        )
    };
    let (spectral, stokes) = (
        xml(r#"<integrator type="path"/>"#),
        xml(r#"<integrator type="stokes"><integrator type="path"/></integrator>"#),
    );
    assert!(traces_caustics(&stokes));
    let s0 = |seed| {
        render_channels(&stokes, 32, seed, false)
            .layer_rgb("S0")
            .expect("S0 layer")
    };
    let rgb = |seed| {
        render_channels(&spectral, 32, seed, false)
            .layer_rgb("")
            .expect("image")
    };
    let (p1, p2, u1, u2) = (s0(1), s0(2), rgb(3), rgb(4));
    let e = |a, b| block_relmse(a, b, 4).expect("same size");
    let same = 0.5 * (e(&p1, &p2) + e(&u1, &u2));
    let cross = 0.25 * (e(&p1, &u1) + e(&p1, &u2) + e(&p2, &u1) + e(&p2, &u2));
    println!("S0 polarized vs spectral: relMSE {cross:.3e}; same mode {same:.3e}");
    assert!(
        cross < 1.5 * same,
        "polarized S0 vs spectral: {cross:.3e} ≥ 1.5 × {same:.3e}"
    );
}

// ---------------------------------------------------------------------------------------------
// `normalmap` carries polarization: the nested BSDF's matrix in the perturbed frame, mapped back.

/// An orthographic camera looking down −z at `plane` under a constant sky: every camera ray
/// reflects once (a delta lobe) into the sky, so each pixel is exact (no noise), and its Stokes
/// vector is the reflection's Mueller matrix applied to unpolarized light.
fn sky_mirror_scene(plane: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="stokes"><integrator type="path"><integer name="max_depth" value="2"/></integrator></integrator>
    <sensor type="orthographic">
        <transform name="to_world"><scale value="0.5"/><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/>
            <rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
    {plane}
</scene>"#
    )
}

/// A conductor of real index 1.5 (a glass-like reflection without transmission: strongly
/// polarizing, R_s ≫ R_p at 40°).
const GLASSY_CONDUCTOR: &str =
    r#"<bsdf type="conductor"><spectrum name="eta" value="1.5"/><spectrum name="k" value="0"/></bsdf>"#;

/// The four Stokes planes (green) of a render.
fn stokes_planes(img: &ChannelImage) -> [Vec<f64>; 4] {
    ["S0.G", "S1.G", "S2.G", "S3.G"].map(|c| plane(img, c))
}

/// A 2 × 2 EXR of one colour, written for a test into Cargo's folder for test files
/// (`CARGO_TARGET_TMPDIR`: the reader takes a constant normal map only as a bitmap); returns its
/// path.
fn constant_bitmap(tag: &str, rgb: [f32; 3]) -> String {
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("gonio-test-{}-{tag}.exr", std::process::id()));
    gonio_render::image::RgbImage::from_fn(2, 2, |_, _| rgb)
        .write(&path)
        .expect("temporary bitmap writes");
    path.to_string_lossy().into_owned()
}

/// A `normalmap` of constant `rgb` around `nested`.
fn constant_normalmap(tag: &str, rgb: [f32; 3], nested: &str) -> String {
    constant_normalmap_with(tag, rgb, "", nested)
}

/// A `normalmap` of constant `rgb` around `nested`, with further `options` (XML properties).
fn constant_normalmap_with(tag: &str, rgb: [f32; 3], options: &str, nested: &str) -> String {
    format!(
        r#"<bsdf type="normalmap">{options}<texture type="bitmap" name="normalmap"><string name="filename" value="{}"/>
            <boolean name="raw" value="true"/></texture>{nested}</bsdf>"#,
        constant_bitmap(tag, rgb)
    )
}

/// A flat normal map ((0.5, 0.5, 1) everywhere) changes nothing, polarization included; a
/// constant tilted normal map on a flat mirror gives the Stokes image of the mirror tilted by the
/// same rotation (the mapped normal n = 2·rgb − 1, here 40° off the axis at azimuth 30°, so the
/// plane of incidence is turned against the sensor's axes and both S1 and S2 are large): the
/// nested matrix's frames are carried from the perturbed frame back to the surface's. That
/// holds with the terminator's shadowing off; with it on (Mitsuba's default) the whole Stokes
/// vector is scaled by the one factor G < 1 of the grazing reflected direction.
#[test]
fn normal_maps_carry_the_nested_polarization() {
    let bare = render_channels(
        &sky_mirror_scene(&format!(
            r#"<shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>{GLASSY_CONDUCTOR}</shape>"#
        )),
        4,
        1,
        false,
    );
    let flat = render_channels(
        &sky_mirror_scene(&format!(
            r#"<shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>{}</shape>"#,
            constant_normalmap("flat", [0.5, 0.5, 1.0], GLASSY_CONDUCTOR)
        )),
        4,
        1,
        false,
    );
    for (k, (a, b)) in stokes_planes(&bare)
        .iter()
        .zip(stokes_planes(&flat).iter())
        .enumerate()
    {
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= 1e-6, "S{k}: bare {x} vs flat normal map {y}");
        }
    }

    let (tilt, azimuth) = (40f64.to_radians(), 30f64.to_radians());
    let n = [tilt.sin() * azimuth.cos(), tilt.sin() * azimuth.sin(), tilt.cos()];
    let rgb = n.map(|c| (0.5 * (c + 1.0)) as f32);
    let mapped_with = |options: &str| {
        render_channels(
            &sky_mirror_scene(&format!(
                r#"<shape type="rectangle"><transform name="to_world"><scale value="10"/></transform>{}</shape>"#,
                constant_normalmap_with("tilted", rgb, options, GLASSY_CONDUCTOR)
            )),
            4,
            1,
            false,
        )
    };
    let mapped = mapped_with(r#"<boolean name="use_shadowing_function" value="false"/>"#);
    let shadowed = mapped_with("");
    // The same mirror tilted: the rectangle's +z turned onto n (lookat from the origin to n).
    let tilted = render_channels(
        &sky_mirror_scene(&format!(
            r#"<shape type="rectangle"><transform name="to_world"><scale value="10"/>
            <lookat origin="0, 0, 0" target="{}, {}, {}" up="0, 1, 0"/></transform>{GLASSY_CONDUCTOR}</shape>"#,
            n[0], n[1], n[2]
        )),
        4,
        1,
        false,
    );
    let (m, t, g) = (
        stokes_planes(&mapped),
        stokes_planes(&tilted),
        stokes_planes(&shadowed),
    );
    for i in 0..m[0].len() {
        let s0 = t[0][i];
        let factor = g[0][i] / m[0][i];
        assert!(
            factor > 0.3 && factor < 0.9,
            "pixel {i}: the shadowing's factor {factor}"
        );
        for k in 1..4 {
            assert!(
                (g[k][i] - factor * m[k][i]).abs() <= 1e-4 * s0,
                "pixel {i} S{k}: shadowed {} vs {factor} × unshadowed {}",
                g[k][i],
                m[k][i]
            );
        }
        assert!(s0 > 0.02, "pixel {i}: the reflection is seen ({s0})");
        for k in 0..4 {
            assert!(
                (m[k][i] - t[k][i]).abs() <= 1e-4 * s0,
                "pixel {i} S{k}: normal-mapped {} vs tilted mirror {}",
                m[k][i],
                t[k][i]
            );
        }
        assert!(
            t[1][i].abs() > 0.1 * s0 && t[2][i].abs() > 0.1 * s0,
            "pixel {i}: S1 {} and S2 {} should both be large (S0 {s0})",
            t[1][i],
            t[2][i]
        );
    }
}
