//! Samplers: uniformity (χ² of 1D and 2D projections), determinism, stratification, and lower
//! integration error than independent sampling at equal sample counts.

use glam::UVec2;
use gonio_render::sampler::{Pattern, Sampler};

const PATTERNS: [Pattern; 6] = [
    Pattern::Independent,
    Pattern::Stratified { jitter: true },
    Pattern::Stratified { jitter: false },
    Pattern::MultiJitter { jitter: true },
    Pattern::MultiJitter { jitter: false },
    Pattern::Sobol,
];

/// Upper-tail χ² test through the Wilson–Hilferty normal approximation: z > 4.5 (p ≈ 3·10⁻⁶)
/// rejects. Stratified patterns are *more* uniform than random, which this one-sided test allows.
fn chi2_ok(counts: &[u64], expected: f64) -> (bool, f64) {
    let chi2: f64 = counts
        .iter()
        .map(|&c| (c as f64 - expected).powi(2) / expected)
        .sum();
    let k = (counts.len() - 1) as f64;
    let z = ((chi2 / k).powf(1.0 / 3.0) - (1.0 - 2.0 / (9.0 * k))) / (2.0 / (9.0 * k)).sqrt();
    (z < 4.5, z)
}

const BINS: usize = 32;

/// Histograms of the samples of a 64 × 64 image at `spp` samples a pixel: dimension 0 (32 bins),
/// the pair 1–2 (32 × 32 cells) and dimensions 0 × 3 (32 × 32, two dimensions that are not a
/// pair: decorrelated?).
fn histograms(s: &mut Sampler, spp: u32) -> [(Vec<u64>, &'static str); 3] {
    histograms_of(s, spp, 0..64, 0..64)
}

/// [`histograms`] of the pixels `xs × ys`.
fn histograms_of(
    s: &mut Sampler,
    spp: u32,
    xs: std::ops::Range<u32>,
    ys: std::ops::Range<u32>,
) -> [(Vec<u64>, &'static str); 3] {
    let mut c1 = vec![0u64; BINS];
    let mut c2 = vec![0u64; BINS * BINS];
    let mut c_cross = vec![0u64; BINS * BINS];
    for py in ys {
        for px in xs.clone() {
            for i in 0..spp {
                s.start_pixel_sample(UVec2::new(px, py), i);
                let a = s.next_1d();
                let b = s.next_2d();
                let c = s.next_1d();
                for v in [a, b.x, b.y, c] {
                    assert!((0.0..1.0).contains(&v), "{:?}: {v}", s.pattern());
                }
                let bin = |v: f32| (v * BINS as f32) as usize;
                c1[bin(a)] += 1;
                c2[bin(b.x) * BINS + bin(b.y)] += 1;
                c_cross[bin(a) * BINS + bin(c)] += 1;
            }
        }
    }
    [(c1, "1D"), (c2, "2D"), (c_cross, "dims 0×3")]
}

/// The χ² check of a histogram whose cells all expect the same count.
fn assert_uniform(counts: &[u64], what: &str) {
    let n: u64 = counts.iter().sum();
    let (ok, z) = chi2_ok(counts, n as f64 / counts.len() as f64);
    assert!(ok, "{what}: χ² z = {z}");
}

#[test]
fn projections_are_uniform() {
    // Jittered patterns only: without jitter, samples sit at stratum centres by design.
    let jittered = PATTERNS.into_iter().filter(|p| {
        !matches!(
            p,
            Pattern::Stratified { jitter: false } | Pattern::MultiJitter { jitter: false }
        )
    });
    for pattern in jittered {
        for spp in [1u32, 7, 16] {
            let mut s = Sampler::new(pattern, spp, 3);
            for (counts, name) in histograms(&mut s, spp) {
                assert_uniform(&counts, &format!("{pattern:?} spp {spp} {name}"));
            }
        }
    }
}

/// The Z-ordered Sobol pattern (`Sampler::z_ordered`): its 1D and 2D projections over a whole
/// image are uniform as the others'; two dimensions that are not a pair share the index's
/// structure image-wide, so their joint histogram is tested over eight scrambles (seeds) at
/// once: decorrelated over the scrambles, not within one image as with per-pixel keys (over
/// 200 seeds one image's χ² z spread with a standard deviation of 2.3–2.6 instead of 1; eight
/// images together stay below 3).
///
/// Over the aligned 64 × 64 image the 1D and 2D histograms are near-perfect by construction
/// (whole nets), so the test also takes a window that cuts the tile's squares (pixels
/// 3..58 × 5..52), where what the nets leave out must still be spread evenly.
#[test]
fn z_ordered_projections_are_uniform() {
    for spp in [1u32, 7, 16] {
        for (xs, ys) in [(0..64, 0..64), (3..58, 5..52)] {
            let mut cross = vec![0u64; BINS * BINS];
            for seed in 0..8u64 {
                let mut s = Sampler::new(Pattern::Sobol, spp, seed).z_ordered(true);
                let [one, pair, (c, _)] = histograms_of(&mut s, spp, xs.clone(), ys.clone());
                for (counts, name) in [one, pair] {
                    assert_uniform(&counts, &format!("spp {spp} seed {seed} {xs:?}×{ys:?} {name}"));
                }
                for (sum, x) in cross.iter_mut().zip(c) {
                    *sum += x;
                }
            }
            assert_uniform(
                &cross,
                &format!("spp {spp} {xs:?}×{ys:?} dims 0×3 over eight seeds"),
            );
        }
    }
}

#[test]
fn same_inputs_same_samples_whatever_the_order() {
    for pattern in PATTERNS {
        let mut a = Sampler::new(pattern, 16, 99);
        let mut b = Sampler::new(pattern, 16, 99);
        let draw = |s: &mut Sampler, px: u32, i: u32| {
            s.start_pixel_sample(UVec2::new(px, 5), i);
            (s.next_1d(), s.next_2d(), s.next_2d(), s.next_1d())
        };
        let forward: Vec<_> = (0..16).map(|i| draw(&mut a, 3, i)).collect();
        // Interleave other pixels in b, in reverse order: values depend only on (pixel, index).
        let mut backward: Vec<_> = (0..16)
            .rev()
            .map(|i| {
                draw(&mut b, 7, i);
                draw(&mut b, 3, i)
            })
            .collect();
        backward.reverse();
        assert_eq!(forward, backward, "{pattern:?}");
        // A different seed or pixel changes them.
        let mut c = Sampler::new(pattern, 16, 100);
        assert_ne!(forward[0], draw(&mut c, 3, 0), "{pattern:?} seed");
        assert_ne!(forward[0], draw(&mut a, 4, 0), "{pattern:?} pixel");
    }
}

#[test]
fn stratified_patterns_put_one_sample_per_stratum() {
    for pattern in [
        Pattern::Stratified { jitter: true },
        Pattern::MultiJitter { jitter: true },
        Pattern::Sobol,
    ] {
        let spp = 16;
        let mut s = Sampler::new(pattern, spp, 1);
        let mut strata_1d = vec![0; 16];
        let mut cells_2d = vec![0; 16];
        let mut rows = vec![0; 16];
        for i in 0..spp {
            s.start_pixel_sample(UVec2::new(2, 9), i);
            let a = s.next_1d();
            let b = s.next_2d();
            strata_1d[(a * 16.0) as usize] += 1;
            cells_2d[(b.x * 4.0) as usize * 4 + (b.y * 4.0) as usize] += 1;
            rows[(b.y * 16.0) as usize] += 1;
        }
        assert!(strata_1d.iter().all(|&c| c == 1), "{pattern:?} 1D {strata_1d:?}");
        assert!(cells_2d.iter().all(|&c| c == 1), "{pattern:?} 2D {cells_2d:?}");
        if pattern != (Pattern::Stratified { jitter: true }) {
            // Multi-jitter and Sobol are also stratified in the 1D projections of a 2D pair.
            assert!(rows.iter().all(|&c| c == 1), "{pattern:?} rows {rows:?}");
        }
    }
}

/// The Sobol pattern's pixels in Z order (module docs of `sampler`): the 16 pixels of an
/// aligned 4 × 4 square at 64 spp are one (0, 10, 2)-net in a dimension pair (exactly one of
/// their 1024 points in each cell of a 32 × 32 grid) and 1024 strata in one dimension, while each
/// pixel's own 64 points stay one per cell of an 8 × 8 grid.
#[test]
fn sobol_pixels_of_an_aligned_square_are_one_net() {
    for seed in [1u64, 2] {
        let mut s = Sampler::new(Pattern::Sobol, 64, seed).z_ordered(true);
        let mut film = vec![0u32; 1024];
        let mut wavelength = vec![0u32; 1024];
        let mut vertex = vec![0u32; 1024];
        for py in 4..8 {
            for px in 8..12 {
                let mut own = vec![0u32; 64];
                for i in 0..64 {
                    s.start_pixel_sample(UVec2::new(px, py), i);
                    let f = s.next_2d();
                    let w = s.next_1d();
                    let v = s.next_2d();
                    film[(f.x * 32.0) as usize * 32 + (f.y * 32.0) as usize] += 1;
                    wavelength[(w * 1024.0) as usize] += 1;
                    vertex[(v.x * 32.0) as usize * 32 + (v.y * 32.0) as usize] += 1;
                    own[(v.x * 8.0) as usize * 8 + (v.y * 8.0) as usize] += 1;
                }
                assert!(
                    own.iter().all(|&c| c == 1),
                    "seed {seed}, pixel ({px}, {py}): {own:?}"
                );
            }
        }
        for (name, counts) in [("film", &film), ("wavelength", &wavelength), ("vertex", &vertex)] {
            assert!(
                counts.iter().all(|&c| c == 1),
                "seed {seed}, {name}: not one point a cell"
            );
        }
        // The vertex pair's 32 × 32 cells over the pixels xs × 4..8.
        let square = |s: &mut Sampler, xs: std::ops::Range<u32>| {
            let mut cells = vec![0u32; 1024];
            for py in 4..8 {
                for px in xs.clone() {
                    for i in 0..64 {
                        s.start_pixel_sample(UVec2::new(px, py), i);
                        let _ = (s.next_2d(), s.next_1d());
                        let v = s.next_2d();
                        cells[(v.x * 32.0) as usize * 32 + (v.y * 32.0) as usize] += 1;
                    }
                }
            }
            cells
        };
        // An unaligned square (pixels 9..13) is not one net: the property is the Z order's.
        let shifted = square(&mut s, 9..13);
        assert!(shifted.iter().any(|&c| c != 1), "seed {seed}");
        // Nor is the aligned square with per-pixel keys (the Z order off): sixteen nets of their
        // own do not make one.
        let unordered = square(&mut Sampler::new(Pattern::Sobol, 64, seed), 8..12);
        assert!(unordered.iter().any(|&c| c != 1), "seed {seed}, per-pixel keys");
    }
}

/// Samples past the Sobol pattern's block of a pixel (index ≥ B) start a new round with keys of
/// their own: stratified again within the round, and not the first round's points.
#[test]
fn sobol_rounds_past_the_block_are_stratified_anew() {
    let mut s = Sampler::new(Pattern::Sobol, 16, 5).z_ordered(true);
    let round = |s: &mut Sampler, r: u32| -> Vec<(f32, f32)> {
        (0..16)
            .map(|i| {
                s.start_pixel_sample(UVec2::new(3, 2), 16 * r + i);
                let v = s.next_2d();
                (v.x, v.y)
            })
            .collect()
    };
    let first = round(&mut s, 0);
    for r in 1..3 {
        let next = round(&mut s, r);
        let mut cells = vec![0; 16];
        for &(x, y) in &next {
            cells[(x * 4.0) as usize * 4 + (y * 4.0) as usize] += 1;
            assert!(!first.contains(&(x, y)), "round {r} repeats a point of round 0");
        }
        assert!(cells.iter().all(|&c| c == 1), "round {r}: {cells:?}");
    }
}

/// ∫∫ exp(a·x·y) dx dy over the unit square = Σ_{n≥0} aⁿ / (n!·(n+1)²).
fn exp_xy_integral(a: f64) -> f64 {
    let mut sum = 0.0;
    let mut term = 1.0; // aⁿ/n!
    for n in 0..40 {
        if n > 0 {
            term *= a / n as f64;
        }
        sum += term / ((n + 1) * (n + 1)) as f64;
    }
    sum
}

fn exact() -> f64 {
    exp_xy_integral(1.0)
}

fn rms_error(pattern: Pattern, spp: u32) -> f64 {
    let want = exact();
    let mut s = Sampler::new(pattern, spp, 17);
    let mut sq = 0.0;
    let pixels = 4096;
    for p in 0..pixels {
        let mut est = 0.0f64;
        for i in 0..spp {
            s.start_pixel_sample(UVec2::new(p % 64, p / 64), i);
            let _lens = s.next_2d(); // a path's first dimensions, then the one we integrate
            let _wl = s.next_1d();
            let u = s.next_2d();
            est += (u.x as f64 * u.y as f64).exp();
        }
        est /= spp as f64;
        sq += (est - want).powi(2);
    }
    (sq / pixels as f64).sqrt()
}

#[test]
fn stratified_and_sobol_integrate_with_lower_error_than_independent() {
    for spp in [16, 64] {
        let ind = rms_error(Pattern::Independent, spp);
        // Independent: the RMS error is σ/√spp, σ² = ∫∫exp(2xy) − (∫∫exp(xy))².
        let var = exp_xy_integral(2.0) - exact().powi(2);
        let predicted = (var / spp as f64).sqrt();
        assert!(
            (ind / predicted - 1.0).abs() < 0.1,
            "independent rms {ind} vs σ/√n {predicted}"
        );
        let strat = rms_error(Pattern::Stratified { jitter: true }, spp);
        let cmj = rms_error(Pattern::MultiJitter { jitter: true }, spp);
        let sobol = rms_error(Pattern::Sobol, spp);
        eprintln!(
            "spp {spp}: independent {ind:.2e} stratified {strat:.2e} multijitter {cmj:.2e} sobol {sobol:.2e}"
        );
        // Jittered sampling of a smooth 2D integrand converges as n^(-1) instead of n^(-1/2).
        let factor = (spp as f64).sqrt() / 2.0;
        assert!(strat * factor < ind, "stratified {strat} vs independent {ind}");
        assert!(cmj * factor < ind, "multijitter {cmj} vs independent {ind}");
        assert!(sobol * factor < ind, "sobol {sobol} vs independent {ind}");
    }
}

/// The padded sampler hands out the pattern's own dimensions up to `STRUCTURED_DIMS`, then a
/// PCG32 stream keyed by the sample (a pure function of seed, pixel and index); with the
/// independent pattern it never switches.
#[test]
fn padded_sampler_switches_to_a_keyed_stream_after_the_structured_dimensions() {
    use gonio_render::sampler::{PathSampler, STRUCTURED_DIMS};
    let (pixel, index) = (UVec2::new(5, 9), 3);
    for pattern in [Pattern::Sobol, Pattern::MultiJitter { jitter: true }] {
        let mut plain = Sampler::new(pattern, 16, 11);
        plain.start_pixel_sample(pixel, index);
        let mut reference: Vec<f32> = (0..STRUCTURED_DIMS).map(|_| plain.next_1d()).collect();
        let mut s = Sampler::new(pattern, 16, 11);
        s.start_pixel_sample(pixel, index);
        let head = [s.next_1d(), s.next_1d(), s.next_1d()];
        assert_eq!(head[..], reference[..3]);
        let mut p = s.padded();
        let key = p.key();
        let got: Vec<f32> = (3..STRUCTURED_DIMS).map(|_| p.next_1d()).collect();
        assert_eq!(got[..], reference[3..]);
        // Beyond: the keyed stream, not the pattern.
        let mut rng = gonio_render::sampler::Pcg32::new(key, key.rotate_left(17) ^ 0x9e37_79b9_7f4a_7c15);
        let tail: Vec<f32> = (0..8).map(|_| p.next_1d()).collect();
        let want: Vec<f32> = (0..8).map(|_| rng.next_f32()).collect();
        assert_eq!(tail, want);
        reference.push(plain.next_1d());
        assert_ne!(tail[0], reference[STRUCTURED_DIMS as usize]);
        // The key depends on the sample.
        let mut other = Sampler::new(pattern, 16, 11);
        other.start_pixel_sample(pixel, index + 1);
        assert_ne!(other.sample_key(), key);
        other.start_pixel_sample(pixel, index);
        assert_eq!(other.sample_key(), key);
    }
    let mut ind = Sampler::new(Pattern::Independent, 4, 2);
    ind.start_pixel_sample(UVec2::new(1, 1), 0);
    let mut plain = ind.clone();
    let mut p = ind.padded();
    for _ in 0..40 {
        assert_eq!(p.next_1d(), plain.next_1d());
    }
}

/// `ldsampler` and `orthogonal` (Mitsuba 3 `src/samplers/`): read with Mitsuba's parameters and
/// count rounding (the counts Mitsuba 3.9.1 prints for sample_count 1, 10, 16, 17, 26, 50), and
/// rendered with our Sobol and multi-jittered patterns.
#[test]
fn ldsampler_and_orthogonal_round_their_counts_as_mitsuba() {
    use gonio_render::plugins::sampler::{ldsampler, orthogonal};
    let ld: Vec<u32> = [1, 10, 16, 17, 26, 50]
        .iter()
        .map(|&n| ldsampler::rounded_count(n))
        .collect();
    assert_eq!(ld, [4, 16, 16, 64, 64, 64]);
    let oa: Vec<u32> = [1, 10, 16, 17, 26, 50]
        .iter()
        .map(|&n| orthogonal::rounded_count(n))
        .collect();
    assert_eq!(oa, [4, 25, 25, 25, 49, 121]);

    let load = |sampler: &str| {
        gonio_render::xml::load_scene_str_with_warnings(
            &format!(r#"<scene version="3.0.0"><sensor type="perspective">{sampler}</sensor></scene>"#),
            ".",
            &[],
        )
    };
    let l = load(r#"<sampler type="ldsampler"><integer name="sample_count" value="10"/></sampler>"#).unwrap();
    assert_eq!(l.scene.sensor.sampler.sample_count, 16);
    assert!(
        l.warnings.iter().any(|w| w.contains("rounding to 16")),
        "{:?}",
        l.warnings
    );
    assert_eq!(Pattern::from(l.scene.sensor.sampler.kind), Pattern::Sobol);
    let l = load(
        r#"<sampler type="orthogonal"><integer name="sample_count" value="25"/><boolean name="jitter" value="false"/><integer name="strength" value="2"/></sampler>"#,
    )
    .unwrap();
    assert_eq!(l.scene.sensor.sampler.sample_count, 25);
    assert!(
        !l.warnings.iter().any(|w| w.contains("rounding")),
        "{:?}",
        l.warnings
    );
    assert_eq!(
        Pattern::from(l.scene.sensor.sampler.kind),
        Pattern::MultiJitter { jitter: false }
    );
    let e = load(r#"<sampler type="ldsampler"><boolean name="jitter" value="false"/></sampler>"#)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("unused parameter \"jitter\"") && e.contains(":1:"),
        "{e}"
    );
    let e = load(r#"<sampler type="orthogonal"><integer name="strength" value="1"/></sampler>"#)
        .unwrap_err()
        .to_string();
    assert!(e.contains("strength"), "{e}");
}
