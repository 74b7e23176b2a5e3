//! Agreement of `roughdielectric` with Mitsuba 3.9.1
//! (`testdata/mitsuba/reference/mitsuba-roughdielectric-values.json`, made by
//! `crates/gonio-core/benches/mitsuba_roughdielectric_values.py`): each configuration is the same
//! `<bsdf>` XML Mitsuba loaded, read by gonio's XML reader. Six configurations: Beckmann and GGX,
//! isotropic and anisotropic, visible and all-normal sampling, tints, named indices, an inverted
//! interface (the denser medium outside) and a textured `alpha`; queries from outside and inside,
//! reflections and refractions, in radiance and importance transport.
//!
//! * `eval` (f without the cosine: Mitsuba's eval / |cos θo|) and `pdf` within 1e-4 relative.
//! * The textured configuration meets Mitsuba 3.9.1's checkerboard quirk recorded in the file
//!   (its `eval_1`, the float a roughness texture reads, returns the other cell than `eval`), so
//!   that query is compared at the uv shifted by half a period in u, as for `roughconductor`.
//! * Albedo (mean sample weight, reflected R and transmitted T apart) within 3 standard errors
//!   of the difference of Mitsuba's 2¹⁹-sample estimate and ours (2²⁰ samples), plus 2e-5
//!   relative for `f32` arithmetic, for the visible-normal configurations.
//! * **Deliberate deviation** (`mitsuba_all_normals_weight_omits_the_widening_ratio`): with
//!   `sample_visible = false`, Mitsuba samples normals from a distribution widened by
//!   1.2 − 0.2 √|cos θi| (Walter et al. 2007) but returns the weight of the unwidened one,
//!   G (ωi·m)/(cos θi cos θm), without D(m)/D_widened(m); its mean weight then differs from the
//!   integral of its own `eval` (which gonio matches to 1e-4). gonio's weight is f·|cos θo|/pdf,
//!   so its mean is that integral: the test checks ours against a deterministic quadrature of
//!   `eval` and shows Mitsuba's estimate away from it.

use crate::mitsuba_json::{self, mitsuba_eval_1_uv, num, vec2, vec3};
use glam::Vec3;
use gonio_core::albedo::directional_albedo;
use gonio_core::rng::Pcg32;
use gonio_core::{Bsdf, BsdfContext, SampledWavelengths, TransportMode};
use gonio_render::xml::load_bsdf_str;
use serde_json::Value;

fn reference() -> Value {
    mitsuba_json::parse(include_str!(
        "../../../testdata/mitsuba/reference/mitsuba-roughdielectric-values.json"
    ))
}

fn mode(v: &Value) -> TransportMode {
    match v["mode"].as_str().unwrap() {
        "radiance" => TransportMode::Radiance,
        "importance" => TransportMode::Importance,
        m => panic!("unknown mode {m}"),
    }
}

fn context(mode: TransportMode) -> BsdfContext {
    BsdfContext {
        mode,
        ..BsdfContext::radiance()
    }
}

fn all_normals(xml: &str) -> bool {
    xml.contains(r#"name="sample_visible" value="false""#)
}

/// Our importance-sampled albedo: (R, R's SE, T, T's SE) over `n` samples.
fn sampled_albedo(
    b: &dyn Bsdf,
    ctx: &BsdfContext,
    wi: Vec3,
    wl: SampledWavelengths,
    n: usize,
    seed: u64,
) -> [f64; 4] {
    let mut rng = Pcg32::new(seed, 3);
    let mut s = [0.0f64; 4];
    for _ in 0..n {
        let mut w = wl;
        if let Some(x) = b.sample(ctx, wi, rng.next_f32(), rng.next_vec2(), &mut w) {
            let v = x.weight[0] as f64;
            let k = if x.wo.z * wi.z > 0.0 { 0 } else { 2 };
            s[k] += v;
            s[k + 1] += v * v;
        }
    }
    let stats = |s1: f64, s2: f64| {
        let m = s1 / n as f64;
        (m, ((s2 / n as f64 - m * m).max(0.0) / n as f64).sqrt())
    };
    let (r, r_se) = stats(s[0], s[1]);
    let (t, t_se) = stats(s[2], s[3]);
    [r, r_se, t, t_se]
}

#[test]
fn mitsuba_checkerboard_eval_1_picks_the_other_cell() {
    let data = reference();
    let rows = data["checkerboard_color0_0.08_color1_0.5"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    assert!((num(&rows[0], "eval") - 0.08).abs() < 1e-6 && (num(&rows[0], "eval_1") - 0.5).abs() < 1e-6);
    assert!((num(&rows[1], "eval") - 0.5).abs() < 1e-6 && (num(&rows[1], "eval_1") - 0.08).abs() < 1e-6);
}

#[test]
fn roughdielectric_eval_and_pdf_agree_with_mitsuba() {
    let data = reference();
    let (mut checked, mut refractions, mut inside) = (0, 0, 0);
    let (mut worst_f, mut worst_pdf) = (0.0f64, 0.0f64);
    for config in data["configs"].as_array().unwrap() {
        let name = config["name"].as_str().unwrap();
        let xml = config["xml"].as_str().unwrap();
        let material = load_bsdf_str(xml).unwrap_or_else(|e| panic!("{name}: {e}"));
        for q in config["eval"].as_array().unwrap() {
            let (wi, wo) = (vec3(&q["wi"]), vec3(&q["wo"]));
            let uv = mitsuba_eval_1_uv(xml.contains("checkerboard"), vec2(&q["uv"]));
            let wl = SampledWavelengths::fixed(num(q, "lambda_nm") as f32);
            let ctx = context(mode(q));
            let (f, pdf) = material.with_bsdf(uv, |b| b.eval_pdf(&ctx, wi, wo, &wl));
            let (mf, mpdf) = (num(q, "f"), num(q, "pdf"));
            assert!(
                (f[0] as f64 - mf).abs() <= 1e-4 * mf.abs().max(1e-6),
                "{name} eval {:?} at wi {wi} wo {wo} uv {uv}: gonio {} vs Mitsuba {mf}",
                ctx.mode,
                f[0]
            );
            assert!(
                (pdf as f64 - mpdf).abs() <= 1e-4 * mpdf.abs().max(1e-6),
                "{name} pdf at wi {wi} wo {wo} uv {uv}: gonio {pdf} vs Mitsuba {mpdf}"
            );
            if mf > 1e-6 {
                worst_f = worst_f.max((f[0] as f64 / mf - 1.0).abs());
            }
            if mpdf > 1e-6 {
                worst_pdf = worst_pdf.max((pdf as f64 / mpdf - 1.0).abs());
            }
            checked += 1;
            refractions += usize::from(mf > 1e-3 && wi.z * wo.z < 0.0);
            inside += usize::from(mf > 1e-3 && wi.z < 0.0);
        }
    }
    eprintln!(
        "roughdielectric vs Mitsuba 3.9.1: max relative difference f {worst_f:.2e}, pdf {worst_pdf:.2e} over {checked} queries"
    );
    assert_eq!(checked, 6 * 26, "the reference file holds 156 eval queries");
    assert!(
        refractions >= 20 && inside >= 20,
        "refractions {refractions}, from inside {inside}"
    );
}

#[test]
fn roughdielectric_albedo_agrees_with_mitsuba() {
    let data = reference();
    let mut checked = 0;
    for (c, config) in data["configs"].as_array().unwrap().iter().enumerate() {
        let name = config["name"].as_str().unwrap();
        let xml = config["xml"].as_str().unwrap();
        if all_normals(xml) {
            continue; // see mitsuba_all_normals_weight_omits_the_widening_ratio
        }
        let material = load_bsdf_str(xml).unwrap();
        for (k, q) in config["albedo"].as_array().unwrap().iter().enumerate() {
            let (wi, uv) = (
                vec3(&q["wi"]),
                mitsuba_eval_1_uv(xml.contains("checkerboard"), vec2(&q["uv"])),
            );
            let wl = SampledWavelengths::fixed(num(q, "lambda_nm") as f32);
            let ctx = context(mode(q));
            let [r, r_se, t, t_se] = material.with_bsdf(uv, |b| {
                sampled_albedo(b, &ctx, wi, wl, 1 << 20, (c * 100 + k) as u64)
            });
            for (what, ours, se, key) in [("R", r, r_se, "R"), ("T", t, t_se, "T")] {
                let (theirs, se_theirs) = (num(q, key), num(q, &format!("{key}_se")));
                let tol = 3.0 * (se * se + se_theirs * se_theirs).sqrt() + 2e-5 * theirs;
                assert!(
                    (ours - theirs).abs() <= tol,
                    "{name} {what} {:?} at wi {wi}: gonio {ours} ± {se} vs Mitsuba {theirs} ± {se_theirs}",
                    ctx.mode
                );
            }
            eprintln!(
                "{name} {:?} θi={:.0}° {}: gonio R {r:.5} T {t:.5} (R+T {:.5}), Mitsuba R {:.5} T {:.5}",
                ctx.mode,
                wi.z.abs().acos().to_degrees(),
                if wi.z > 0.0 { "outside" } else { "inside" },
                r + t,
                num(q, "R"),
                num(q, "T")
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 4 * 10);
}

#[test]
fn mitsuba_all_normals_weight_omits_the_widening_ratio() {
    let data = reference();
    let (mut checked, mut mitsuba_off, mut worst_z) = (0, 0, 0.0f64);
    for (c, config) in data["configs"].as_array().unwrap().iter().enumerate() {
        let name = config["name"].as_str().unwrap();
        let xml = config["xml"].as_str().unwrap();
        if !all_normals(xml) {
            continue;
        }
        let material = load_bsdf_str(xml).unwrap();
        for (k, q) in config["albedo"].as_array().unwrap().iter().enumerate() {
            let (wi, uv) = (vec3(&q["wi"]), vec2(&q["uv"]));
            let wl = SampledWavelengths::fixed(num(q, "lambda_nm") as f32);
            let ctx = context(mode(q));
            // The integral of eval (gonio's eval = Mitsuba's to 1e-4), by quadrature.
            let quad = material.with_bsdf(uv, |b| directional_albedo(b, ctx.mode, wi, &wl, 4_000_000));
            let exact = (quad.r[0] + quad.t[0]) as f64;
            let [r, r_se, t, t_se] = material.with_bsdf(uv, |b| {
                sampled_albedo(b, &ctx, wi, wl, 1 << 20, (c * 100 + k) as u64)
            });
            let ours_se = (r_se * r_se + t_se * t_se).sqrt();
            // 2e-3: the quadrature's error on the narrowest lobe (α_u = 0.05).
            assert!(
                (r + t - exact).abs() <= 3.0 * ours_se + 2e-3 * exact.max(1.0),
                "{name} {:?} at wi {wi}: gonio {} ± {ours_se} vs ∫ eval {exact}",
                ctx.mode,
                r + t
            );
            let (theirs, theirs_se) = (num(q, "total"), num(q, "total_se"));
            let z = (theirs - exact).abs() / theirs_se;
            mitsuba_off += usize::from(z > 5.0 && (theirs - exact).abs() > 2e-3 * exact.max(1.0));
            worst_z = worst_z.max(z);
            eprintln!(
                "{name} {:?} θi={:.0}° {}: ∫ eval {exact:.5}, gonio sampled {:.5} ± {ours_se:.5}, Mitsuba sampled {theirs:.5} ± {theirs_se:.5} ({z:.1} σ)",
                ctx.mode,
                wi.z.abs().acos().to_degrees(),
                if wi.z > 0.0 { "outside" } else { "inside" },
                r + t
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 2 * 10);
    // Measured in the reference file: 4 of the 20 estimates lie beyond 5 σ and the quadrature
    // tolerance (the grazing ones: 80° from outside, 60° from inside), the worst at 20 σ.
    assert!(
        mitsuba_off >= 3 && worst_z > 10.0,
        "Mitsuba's all-normals albedo is off the integral of its eval in only {mitsuba_off} cases (worst {worst_z:.1} σ)"
    );
}

/// All-normal sampling of a strongly anisotropic surface is widened as in Mitsuba even when one
/// axis is nearly smooth (α = 0.52 and 0.0067; 0.004 and 0.3): one rough axis resolves the
/// sampled tilt, so only a surface smooth along both axes skips the widening
/// (`testdata/mitsuba/reference/mitsuba-spot-values.json`, `widening`; with the smaller α
/// deciding, the first pdf was 46 % below Mitsuba's).
#[test]
fn anisotropic_all_normal_pdf_is_widened_as_mitsubas() {
    let data = mitsuba_json::parse(include_str!(
        "../../../testdata/mitsuba/reference/mitsuba-spot-values.json"
    ));
    let cases = data["widening"].as_array().unwrap();
    assert_eq!(cases.len(), 2);
    for q in cases {
        let xml = q["xml"].as_str().unwrap();
        let material = load_bsdf_str(xml).unwrap_or_else(|e| panic!("{xml}: {e}"));
        let (wi, wo) = (vec3(&q["wi"]), vec3(&q["wo"]));
        let wl = SampledWavelengths::fixed(num(q, "lambda_nm") as f32);
        let mitsuba = num(q, "pdf");
        material.with_bsdf(glam::Vec2::splat(0.5), |bsdf| {
            let pdf = bsdf.pdf(&BsdfContext::radiance(), wi, wo, &wl) as f64;
            assert!(
                (pdf - mitsuba).abs() <= 1e-4 * mitsuba,
                "{xml}: pdf {pdf} vs Mitsuba's {mitsuba}"
            );
        });
    }
}
