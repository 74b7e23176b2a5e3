//! The `aov` and `moment` integrators (film layers) and `hdrfilm`'s `sample_border`.

use gonio_render::image::ChannelImage;
use gonio_render::render::{PreparedScene, RenderOptions, render};
use gonio_render::sampler::Pattern;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// Renders `xml` (its files resolved in `tests/data`) at `spp` with `seed` and Mitsuba's
/// independent sampler.
fn render_xml(xml: &str, spp: u32, seed: u64) -> ChannelImage {
    let scene = gonio_render::xml::load_scene_str(xml, data_dir(), &[]).expect("test scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let options = RenderOptions {
        spp,
        seed,
        pattern: Pattern::Independent,
    };
    render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).channels
}

/// The values of channel `name`, pixel by pixel (also the spectral film tests').
pub(crate) fn channel(img: &ChannelImage, name: &str) -> Vec<f32> {
    let k = img
        .names
        .iter()
        .position(|n| n == name)
        .unwrap_or_else(|| panic!("no channel {name} in {:?}", img.names));
    let n = img.names.len();
    img.data.chunks_exact(n).map(|p| p[k]).collect()
}

/// The known scene of the AOV tests (also `testdata/mitsuba-corpus/probe_aov.py`'s): a pinhole
/// at z = 5 looking down −z (fov 40° across 6 pixels, 4 rows), a rectangle [−0.8, 0.8] × [−3, 3]
/// in the plane z = 1 (shape 1) before an OBJ square [−4, 4]² of two triangles in the plane
/// z = −4 (shape 2); a sphere far to the side (shape 0) is never seen.
fn known_scene(integrator: &str, filter: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
 {integrator}
 <sensor type="perspective"><float name="fov" value="40"/>
  <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
  <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
  <film type="hdrfilm"><integer name="width" value="6"/><integer name="height" value="4"/>
   <rfilter type="{filter}"/></film></sensor>
 <shape type="sphere"><transform name="to_world"><translate x="10"/></transform></shape>
 <shape type="rectangle"><transform name="to_world"><translate z="1"/><scale x="0.8" y="3"/></transform></shape>
 <shape type="obj"><string name="filename" value="aov_quad.obj"/>
  <transform name="to_world"><translate z="-1"/><scale value="4"/></transform></shape>
 <emitter type="constant"/>
</scene>"#
    )
}

const ALL_AOVS: &str = "d:depth, p:position, uv:uv, ng:geo_normal, ns:sh_normal, dpdu:dp_du, dpdv:dp_dv, dx:duv_dx, dy:duv_dy, prim:prim_index, shape:shape_index";

#[test]
fn aov_channel_names_follow_mitsuba() {
    let xml = known_scene(
        &format!(
            r#"<integrator type="aov"><string name="aovs" value="{ALL_AOVS}"/><integrator type="direct" name="b"/><integrator type="path" name="a"/></integrator>"#
        ),
        "box",
    );
    let img = render_xml(&xml, 1, 0);
    // Mitsuba 3.9.1 (`testdata/mitsuba-corpus/probe_aov.py`): the film's R, G, B, then the
    // nested images with alpha in document order, then the AOVs in the order written.
    let expected = [
        "R", "G", "B", "b.R", "b.G", "b.B", "b.A", "a.R", "a.G", "a.B", "a.A", "d.T", "p.X", "p.Y", "p.Z",
        "uv.U", "uv.V", "ng.X", "ng.Y", "ng.Z", "ns.X", "ns.Y", "ns.Z", "dpdu.X", "dpdu.Y", "dpdu.Z",
        "dpdv.X", "dpdv.Y", "dpdv.Z", "dx.U", "dx.V", "dy.U", "dy.V", "prim.I", "shape.I",
    ];
    assert_eq!(img.names, expected);
    // The film's image is the first nested integrator's (`b`, direct), sample for sample.
    for c in ["R", "G", "B"] {
        assert_eq!(channel(&img, c), channel(&img, &format!("b.{c}")));
    }
}

/// Every AOV on the known scene, one camera ray per pixel (box filter, 1 spp), against closed
/// forms: depth = the distance from the near plane (z = 4.99) along the ray; the rectangle at
/// z = 1, uv = ((x + 0.8)/1.6, (y + 3)/6),
/// ∂p/∂u = (1.6, 0, 0), ∂p/∂v = (0, 6, 0); the OBJ square at z = −4, uv from its vertices with v
/// flipped as Mitsuba reads OBJ files, ∂p/∂u = (8, 0, 0), ∂p/∂v = (0, −8, 0); normals +z; the
/// triangle index from the diagonal; the shape index in document order. ∂uv/∂x and ∂uv/∂y are
/// Mitsuba 3.9.1's values on the same scene (`testdata/mitsuba-corpus/probe_aov.py`: constant
/// over each plane, 0.302550 and −0.080680 on the rectangle, 0.136337 and 0.136337 on the square
/// at 1 spp, halved at 4 spp by Mitsuba's 1/√spp).
#[test]
fn aov_values_on_a_known_scene() {
    let xml = known_scene(
        &format!(r#"<integrator type="aov"><string name="aovs" value="{ALL_AOVS}"/></integrator>"#),
        "box",
    );
    for spp in [1, 4] {
        let img = render_xml(&xml, spp, 3);
        let get = |name: &str| channel(&img, name);
        let (d, px, py, pz) = (get("d.T"), get("p.X"), get("p.Y"), get("p.Z"));
        let (u, v) = (get("uv.U"), get("uv.V"));
        let (prim, shape) = (get("prim.I"), get("shape.I"));
        let (dxu, dxv, dyu, dyv) = (get("dx.U"), get("dx.V"), get("dy.U"), get("dy.V"));
        let scale = 1.0 / (spp as f32).sqrt();
        let mut seen = [0; 2];
        for i in 0..img.width * img.height {
            let close = |a: f32, b: f32, tol: f32, what: &str| {
                assert!(
                    (a - b).abs() <= tol,
                    "pixel {i} at {spp} spp: {what} {a}, expected {b}"
                )
            };
            let on_rect = (pz[i] - 1.0).abs() < 1e-4;
            let on_quad = (pz[i] + 4.0).abs() < 1e-4;
            // Pixels whose samples all hit one plane (the others mix the two under the box).
            if !(on_rect || on_quad) {
                continue;
            }
            seen[on_quad as usize] += 1;
            if spp == 1 {
                // Camera rays start on the near plane (z = 5 − 0.01), as Mitsuba's do.
                let dist = ((px[i]).powi(2) + (py[i]).powi(2) + (pz[i] - 5.0).powi(2)).sqrt();
                close(d[i], dist * (1.0 - 0.01 / (5.0 - pz[i])), 1e-4, "depth");
            }
            for (name, want) in [("ng", [0.0, 0.0, 1.0]), ("ns", [0.0, 0.0, 1.0])] {
                for (c, w) in ["X", "Y", "Z"].iter().zip(want) {
                    close(get(&format!("{name}.{c}"))[i], w, 1e-5, name);
                }
            }
            let (dpdu, dpdv, uv, duv_dx, duv_dy, shape_index) = if on_rect {
                (
                    [1.6, 0.0, 0.0],
                    [0.0, 6.0, 0.0],
                    [(px[i] + 0.8) / 1.6, (py[i] + 3.0) / 6.0],
                    [0.302550, 0.0],
                    [0.0, -0.080680],
                    1.0,
                )
            } else {
                (
                    [8.0, 0.0, 0.0],
                    [0.0, -8.0, 0.0],
                    [(px[i] + 4.0) / 8.0, 1.0 - (py[i] + 4.0) / 8.0],
                    [0.136337, 0.0],
                    [0.0, 0.136337],
                    2.0,
                )
            };
            for (c, (a, b)) in ["X", "Y", "Z"].iter().zip(dpdu.iter().zip(dpdv)) {
                close(get(&format!("dpdu.{c}"))[i], *a, 1e-4, "dp_du");
                close(get(&format!("dpdv.{c}"))[i], b, 1e-4, "dp_dv");
            }
            close(u[i], uv[0], 1e-4, "u");
            close(v[i], uv[1], 1e-4, "v");
            // Mitsuba's differentials, to its printed precision (relative 1e-4), at 1 spp where
            // they were measured. At 4 spp the expectation is Mitsuba's 1/√spp scaling of the
            // same values, not measured in Mitsuba; gonio sits up to 1.3 % above it at the
            // image corner (unexplained, issue #10 closing note), so 2 % there.
            let rel = if spp == 1 { 1e-4 } else { 2e-2 };
            close(
                dxu[i],
                duv_dx[0] * scale,
                rel * duv_dx[0].abs() + 1e-6,
                "duv_dx.u",
            );
            close(dxv[i], duv_dx[1] * scale, 1e-5, "duv_dx.v");
            close(dyu[i], duv_dy[0] * scale, 1e-5, "duv_dy.u");
            close(
                dyv[i],
                duv_dy[1] * scale,
                rel * duv_dy[1].abs() + 1e-6,
                "duv_dy.v",
            );
            close(shape[i], shape_index, 0.0, "shape index");
            if spp == 1 {
                // Triangle 0 is (0,0),(1,0),(1,1) in uv before the flip: u > 1 − v after it.
                let tri = if on_quad && u[i] < 1.0 - v[i] { 1.0 } else { 0.0 };
                close(prim[i], tri, 0.0, "prim index");
            }
        }
        assert!(
            seen[0] >= 4 && seen[1] >= 4,
            "both planes seen at {spp} spp: {seen:?}"
        );
    }
}

/// An orthographic camera at z = 5 looking down −z over world x, y ∈ [−1, 1] (`n` × `n`
/// pixels, film x growing with world x), `filter`, `sample_border`, and `body`.
fn ortho_scene(n: u32, integrator: &str, filter: &str, sample_border: bool, body: &str) -> String {
    format!(
        r#"<scene version="3.0.0">
 {integrator}
 <sensor type="orthographic">
  <transform name="to_world"><lookat origin="0,0,5" target="0,0,0" up="0,1,0"/></transform>
  <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
  <film type="hdrfilm"><integer name="width" value="{n}"/><integer name="height" value="{n}"/>
   <boolean name="sample_border" value="{sample_border}"/>{filter}</film></sensor>
 {body}
</scene>"#
    )
}

/// `moment` over the `depth` AOV of a plane covering exactly the left half of one pixel column
/// (world x < 0.125 is film x < 4.5 on an 8 × 8 film, box filter): each camera sample's value is
/// D·B with B ~ Bernoulli(½), so per pixel m2 = D·m1 exactly (B² = B), and m2 − m1² (the
/// biased sample variance of N samples, mean D²(¼ − 1/(4N))) stays within its standard error
/// (√2·D²/(4N) per pixel at p = ½) of the Bernoulli variance.
#[test]
fn moment_gives_the_bernoulli_variance_of_a_half_covered_pixel() {
    let plane = r#"<shape type="rectangle"><transform name="to_world"><scale x="5" y="5"/><translate x="-4.875"/></transform></shape>"#;
    let integrator = r#"<integrator type="moment"><integrator type="aov" name="x"><string name="aovs" value="dd:depth"/></integrator></integrator>"#;
    let xml = ortho_scene(8, integrator, r#"<rfilter type="box"/>"#, false, plane);
    let n = 256u32;
    let img = render_xml(&xml, n, 11);
    assert_eq!(
        img.names,
        [
            "R",
            "G",
            "B",
            "x.dd.T",
            "x.X",
            "x.Y",
            "x.Z",
            "m2_x.dd.T",
            "m2_x.X",
            "m2_x.Y",
            "m2_x.Z"
        ],
        "Mitsuba's channel names for a moment of an aov"
    );
    let (m1, m2) = (channel(&img, "x.dd.T"), channel(&img, "m2_x.dd.T"));
    // The depth of the covered columns (every sample on the plane).
    let d = m1[0];
    assert!(d > 4.0 && d < 5.5, "depth {d}");
    let mut var = Vec::new();
    for y in 0..8 {
        for x in 0..8 {
            let i = y * 8 + x;
            match x {
                0..=3 => assert!(
                    (m1[i] - d).abs() < 1e-5 && (m2[i] - d * d).abs() < 1e-3,
                    "covered pixel {x},{y}"
                ),
                4 => {
                    assert!(
                        (m2[i] - d * m1[i]).abs() < 1e-4 * d * d,
                        "B² = B at pixel {x},{y}: {} vs {}",
                        m2[i],
                        d * m1[i]
                    );
                    var.push((m2[i] - m1[i] * m1[i]) / (d * d));
                }
                _ => assert!(m1[i] == 0.0 && m2[i] == 0.0, "empty pixel {x},{y}"),
            }
        }
    }
    let nf = n as f32;
    let expected = 0.25 - 0.25 / nf;
    let se = 2f32.sqrt() / (4.0 * nf) / (var.len() as f32).sqrt();
    let mean = var.iter().sum::<f32>() / var.len() as f32;
    println!("half-covered pixels: (m2 − m1²)/D² = {mean:.5} (expected {expected:.5} ± {se:.5})");
    assert!((mean - expected).abs() < 4.0 * se, "{mean} vs {expected} ± {se}");
}

/// `moment` of a spectral integrator: its XYZ layer is the image's colour in XYZ, and the
/// second moment is at least the squared first moment in every channel (Cauchy–Schwarz).
#[test]
fn moment_of_the_path_tracer_writes_xyz_and_its_square() {
    let body = r#"<shape type="rectangle"><bsdf type="diffuse"/></shape><emitter type="constant"/>"#;
    let integrator = r#"<integrator type="moment"><integrator type="path" name="p"/><integrator type="depth" name="d"/></integrator>"#;
    let img = render_xml(
        &ortho_scene(6, integrator, r#"<rfilter type="gaussian"/>"#, false, body),
        16,
        2,
    );
    assert_eq!(
        img.names,
        [
            "R", "G", "B", "p.X", "p.Y", "p.Z", "d.X", "d.Y", "d.Z", "m2_p.X", "m2_p.Y", "m2_p.Z", "m2_d.X",
            "m2_d.Y", "m2_d.Z"
        ]
    );
    let (r, g, b) = (channel(&img, "R"), channel(&img, "G"), channel(&img, "B"));
    for (k, c) in ["X", "Y", "Z"].iter().enumerate() {
        let (m1, m2) = (
            channel(&img, &format!("p.{c}")),
            channel(&img, &format!("m2_p.{c}")),
        );
        for i in 0..m1.len() {
            let xyz = gonio_core::color::xyz_from_linear_srgb(glam::Vec3::new(r[i], g[i], b[i]));
            assert!(
                (m1[i] - xyz[k]).abs() <= 1e-5 * (1.0 + xyz[k].abs()),
                "p.{c} at {i}: {} vs {}",
                m1[i],
                xyz[k]
            );
            assert!(m2[i] >= m1[i] * m1[i] * (1.0 - 1e-5), "m2_p.{c} at {i}");
            assert!(m1[i] > 0.0, "the lit plane covers the film");
        }
    }
}

/// A malformed `aovs` string or an unknown type is an error naming the line, column and value.
#[test]
fn aov_errors_name_the_place_and_value() {
    for (aovs, quote) in [
        ("dd:deep", "\"deep\""),
        ("depth", "\"depth\" is not a <name>:<type> pair"),
        ("a:b:depth", "\"a:b:depth\""),
        (":depth", "\":depth\""),
        ("x:albedo", "unsupported AOV type \"albedo\""),
        ("a:depth, a:uv", "\"a\" is used twice"),
        ("", "writes nothing"),
    ] {
        let text = format!(
            "<scene version=\"3.0.0\">\n  <integrator type=\"aov\">\n    <string name=\"aovs\" value=\"{aovs}\"/>\n  </integrator>\n</scene>\n"
        );
        let e = gonio_render::xml::load_scene_str(&text, data_dir(), &[]).expect_err("a bad aovs string");
        let msg = e.to_string();
        assert!(msg.starts_with("<string>:3:"), "{msg}");
        assert!(msg.contains(quote), "{msg:?} should contain {quote:?}");
    }
    let text = "<scene version=\"3.0.0\">\n  <integrator type=\"aov\"/>\n</scene>\n";
    let msg = gonio_render::xml::load_scene_str(text, data_dir(), &[])
        .expect_err("no aovs")
        .to_string();
    assert!(msg.starts_with("<string>:2:") && msg.contains("aovs"), "{msg}");
}

/// `sample_border` (Mitsuba's meaning): the band of ⌈r − ½⌉ = 2 pixels around the image that a
/// tent filter of radius 2 reaches is sampled too. A plane at depth D₁ covers world x < −1 (left
/// of the film), one at D₂ = D₁ + 1 the rest: without the border the left column sees D₂ only;
/// with it, its filter-weighted mean takes the fraction ∫₋₁.₅⁰ tent(x − ½) dx / ∫ tent = 0.5625/2
/// = 0.28125 of its weight from D₁ (0.03125 for the second column), so the depth there is
/// D₂ − 0.28125. (Mitsuba 3.9.1 on the same scene at 1024 spp, `probe_aov.py`: 0.2847 and 0.0343
/// below the far plane's depth with the border, 0 without.) Pixels whose filter stays inside the image get exactly the same samples in the
/// same order: bit-identical, the image of a nested path tracer included.
#[test]
fn sample_border_feeds_the_edge_pixels_through_the_filter() {
    let body = r#"<shape type="rectangle"><transform name="to_world"><scale x="5" y="5"/><translate x="-6"/></transform><bsdf type="diffuse"/></shape>
 <shape type="rectangle"><transform name="to_world"><scale x="5" y="5"/><translate x="4" z="-1"/></transform><bsdf type="diffuse"/></shape>
 <emitter type="constant"/>"#;
    let integrator = r#"<integrator type="aov"><string name="aovs" value="dd:depth"/><integrator type="path" name="img"/></integrator>"#;
    let filter = r#"<rfilter type="tent"><float name="radius" value="2"/></rfilter>"#;
    let n = 8usize;
    let off = render_xml(&ortho_scene(n as u32, integrator, filter, false, body), 256, 5);
    let on = render_xml(&ortho_scene(n as u32, integrator, filter, true, body), 256, 5);
    let (d_off, d_on) = (channel(&off, "dd.T"), channel(&on, "dd.T"));
    let d2 = d_off[n / 2];
    for y in 0..n {
        let d = d_off[y * n];
        assert!(
            (d - d2).abs() < 1e-5,
            "without the border the left column sees the far plane only: {d}"
        );
    }
    for (col, fraction) in [(0, 0.28125f32), (1, 0.03125)] {
        let vals: Vec<f32> = (0..n).map(|y| d_on[y * n + col]).collect();
        let mean = vals.iter().sum::<f32>() / n as f32;
        let sd = (vals.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / (n as f32 - 1.0)).sqrt();
        let expected = d2 - fraction;
        println!("column {col}: depth {mean:.4} ± {sd:.4} (expected {expected:.4})");
        assert!(
            (mean - expected).abs() < 4.0 * sd / (n as f32).sqrt() + 1e-4,
            "column {col}: {mean} vs {expected}"
        );
    }
    for name in &off.names {
        let (a, b) = (channel(&off, name), channel(&on, name));
        for y in 2..n - 2 {
            for x in 2..n - 2 {
                assert_eq!(
                    a[y * n + x].to_bits(),
                    b[y * n + x].to_bits(),
                    "{name} at ({x}, {y})"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Mitsuba's `integrator_aov.xml` (issue #10 corpus): `aov` with `nn:sh_normal, position:position,
// depth.y:depth` around a `path` integrator named `image`, over `include/integrator_scene.xml`
// (the material-preview scene: serialized meshes, museum environment, Gaussian filter) with its
// film reduced to 120 × 90. Reference: Mitsuba 3.9.1 `scalar_spectral`, 256 spp, seed 0, all 14
// channels (`testdata/mitsuba-corpus/make_layer_references.py`).

/// Samples per pixel in CI.
const AOV_SPP: u32 = 16;

fn corpus() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../testdata/mitsuba-corpus")
}

fn render_corpus_aov(spp: u32, seed: u64) -> ChannelImage {
    let path = corpus().join("docs/scenes/integrator_aov.xml");
    let scene = gonio_render::xml::load_scene_file(&path, &[]).expect("scene loads");
    let prepared = PreparedScene::new(scene).expect("scene prepares");
    let mut options = RenderOptions::from_scene(&prepared.scene);
    options.spp = spp;
    options.seed = seed;
    render(&prepared, &options, &|_, _| {}, &AtomicBool::new(false)).channels
}

/// Pixels away from silhouettes and creases: over the 5 × 5 pixels the Gaussian filter (radius
/// 2) reaches, the reference's depth stays within 2 % of the pixel's and its shading normal
/// within 0.1, and something is hit.
fn smooth_pixels(r: &ChannelImage) -> Vec<bool> {
    let (w, h) = (r.width as i64, r.height as i64);
    let d = channel(r, "depth.y.T");
    let n: Vec<Vec<f32>> = ["nn.X", "nn.Y", "nn.Z"].iter().map(|c| channel(r, c)).collect();
    let mut out = vec![false; d.len()];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            let mut ok = d[i] > 0.0;
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let (qx, qy) = (x + dx, y + dy);
                    if !ok || qx < 0 || qy < 0 || qx >= w || qy >= h {
                        continue;
                    }
                    let q = (qy * w + qx) as usize;
                    ok = (d[q] - d[i]).abs() < 0.02 * d[i] && n.iter().all(|c| (c[q] - c[i]).abs() < 0.1);
                }
            }
            out[i] = ok;
        }
    }
    out
}

/// Largest |a − b| per deterministic layer over the smooth pixels.
fn layer_errors(a: &ChannelImage, b: &ChannelImage, mask: &[bool]) -> Vec<(&'static str, f32)> {
    [
        "depth.y.T",
        "position.X",
        "position.Y",
        "position.Z",
        "nn.X",
        "nn.Y",
        "nn.Z",
    ]
    .iter()
    .map(|&c| {
        let (x, y) = (channel(a, c), channel(b, c));
        let e = (0..x.len())
            .filter(|&i| mask[i])
            .map(|i| (x[i] - y[i]).abs())
            .fold(0.0f32, f32::max);
        (c, e)
    })
    .collect()
}

fn image_relmse(a: &ChannelImage, b: &ChannelImage) -> f64 {
    let (x, y) = (a.layer_rgb("image").unwrap(), b.layer_rgb("image").unwrap());
    gonio_render::compare::block_relmse(&x, &y, 8).unwrap()
}

#[test]
#[ignore = "measurement, run by hand: the noise levels of the integrator_aov thresholds"]
fn measure_corpus_aov() {
    let r = ChannelImage::read(corpus().join("reference/integrator_aov.exr")).expect("reference");
    let mask = smooth_pixels(&r);
    println!(
        "smooth pixels: {} of {}",
        mask.iter().filter(|&&m| m).count(),
        mask.len()
    );
    let (a, b, c) = (
        render_corpus_aov(AOV_SPP, 1),
        render_corpus_aov(AOV_SPP, 2),
        render_corpus_aov(AOV_SPP, 0),
    );
    println!(
        "image: gonio-vs-gonio {:.3e}, gonio-vs-reference {:.3e} / {:.3e} / {:.3e}",
        image_relmse(&a, &b),
        image_relmse(&a, &r),
        image_relmse(&b, &r),
        image_relmse(&c, &r)
    );
    println!("layers gonio-vs-gonio {:?}", layer_errors(&a, &b, &mask));
    for x in [&a, &b, &c] {
        println!("layers gonio-vs-reference {:?}", layer_errors(x, &r, &mask));
    }
}

/// Thresholds, measured by [`measure_corpus_aov`] at [`AOV_SPP`] (seeds 1 and 2 for
/// gonio-vs-gonio, 1, 2 and 0 against the reference; Mitsuba-vs-Mitsuba from
/// `make_layer_references.py --noise`, two 32-spp renders):
///
/// | layer | gonio-gonio | gonio-reference | Mitsuba-Mitsuba (32 spp) | threshold |
/// |---|---|---|---|---|
/// | image (8 × 8-block relMSE) | 2.08e-3 | 1.01e-3 1.41e-3 1.03e-3 | 1.71e-3 | 2.08e-3 |
/// | depth.y.T (largest difference) | 1.39e-3 | 2.20e-3 2.21e-3 2.12e-3 | median 1.2e-3 (all pixels) | 5e-3 |
/// | position.X | 1.56e-3 | 2.63e-3 2.31e-3 2.37e-3 | median 1.2e-3 | 5e-3 |
/// | position.Y | 1.52e-3 | 2.42e-3 2.22e-3 2.45e-3 | median 1.2e-3 | 5e-3 |
/// | position.Z | 0.83e-3 | 1.72e-3 1.80e-3 1.60e-3 | median 3.4e-4 | 5e-3 |
/// | nn.X | 5.8e-4 | 8.1e-4 8.7e-4 9.8e-4 | median 2.5e-4 | 2.5e-3 |
/// | nn.Y | 6.8e-4 | 8.4e-4 9.2e-4 1.18e-3 | median 2.5e-4 | 2.5e-3 |
/// | nn.Z | 7.4e-4 | 1.17e-3 1.12e-3 1.12e-3 | median 1.6e-4 | 2.5e-3 |
///
/// The deterministic layers are compared pixel by pixel on the 4880 smooth pixels (of 10800):
/// their differences come from where each renderer's samples fall inside the Gaussian filter
/// (jitter, largest where the depth changes fastest) and sit about 1.5× above gonio's own
/// level against the reference, a small systematic part (0.03 % of a depth) that the threshold,
/// twice the largest gonio-vs-reference value, admits; half a pixel of misregistration
/// (depth slopes of 0.02–0.05 per pixel on the plane) or a wrong normal would exceed it.
const AOV_IMAGE_THRESHOLD: f64 = 2.08e-3;
const AOV_LAYER_THRESHOLDS: [(&str, f32); 7] = [
    ("depth.y.T", 5e-3),
    ("position.X", 5e-3),
    ("position.Y", 5e-3),
    ("position.Z", 5e-3),
    ("nn.X", 2.5e-3),
    ("nn.Y", 2.5e-3),
    ("nn.Z", 2.5e-3),
];

#[test]
fn corpus_aov_matches_mitsuba_channel_by_channel() {
    let r = ChannelImage::read(corpus().join("reference/integrator_aov.exr")).expect("reference");
    let img = render_corpus_aov(AOV_SPP, 0);
    assert_eq!(
        img.names,
        [
            "R",
            "G",
            "B",
            "image.R",
            "image.G",
            "image.B",
            "image.A",
            "nn.X",
            "nn.Y",
            "nn.Z",
            "position.X",
            "position.Y",
            "position.Z",
            "depth.y.T"
        ],
        "Mitsuba 3.9.1's channel names, in its order"
    );
    let mut names = r.names.clone();
    names.sort();
    let mut ours = img.names.clone();
    ours.sort();
    assert_eq!(names, ours, "the reference has the same channels");
    assert!(
        channel(&img, "image.A").iter().all(|&a| a == 1.0),
        "the environment covers every pixel"
    );
    let e = image_relmse(&img, &r);
    println!("integrator_aov image: relMSE vs Mitsuba {e:.3e} (threshold {AOV_IMAGE_THRESHOLD:.3e})");
    assert!(e < AOV_IMAGE_THRESHOLD, "image layer: {e:.3e}");
    let mask = smooth_pixels(&r);
    assert!(
        mask.iter().filter(|&&m| m).count() > 4000,
        "most pixels are smooth"
    );
    for ((name, e), (_, t)) in layer_errors(&img, &r, &mask)
        .into_iter()
        .zip(AOV_LAYER_THRESHOLDS)
    {
        println!("integrator_aov {name}: largest difference {e:.3e} (threshold {t:.3e})");
        assert!(e < t, "{name}: {e:.3e} ≥ {t:.3e}");
    }
}
