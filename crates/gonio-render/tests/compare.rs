//! Comparison metrics on synthetic images with known answers.

use gonio_render::compare::{RELMSE_EPS, block_relmse, compare, diff_image, relmse};
use gonio_render::image::RgbImage;

fn constant(w: usize, h: usize, v: [f32; 3]) -> RgbImage {
    RgbImage::from_fn(w, h, |_, _| v)
}

#[test]
fn identical_images_have_zero_error() {
    let a = RgbImage::from_fn(13, 9, |x, y| [x as f32, y as f32 * 0.1, 1.0]);
    let m = compare(&a, &a, 8).unwrap();
    assert_eq!(
        (m.relmse, m.rmse, m.mae, m.block_relmse, m.worst.relmse),
        (0.0, 0.0, 0.0, 0.0, 0.0)
    );
    assert_eq!(m.mean_a, m.mean_b);
    assert!((m.mean_a[0] - 6.0).abs() < 1e-9 && (m.mean_a[2] - 1.0).abs() < 1e-9);
}

#[test]
fn metrics_match_hand_computed_values() {
    let b = constant(4, 2, [1.0, 0.0, 2.0]);
    let a = constant(4, 2, [1.5, 0.1, 2.0]);
    let m = compare(&a, &b, 8).unwrap();
    let want_rel = (0.25 / (1.0 + RELMSE_EPS) + 0.01 / RELMSE_EPS + 0.0) / 3.0;
    assert!((m.relmse - want_rel).abs() < 1e-6, "{} vs {want_rel}", m.relmse);
    assert!((m.rmse - ((0.25f64 + 0.01) / 3.0).sqrt()).abs() < 1e-6);
    assert!((m.mae - 0.6 / 3.0).abs() < 1e-6);
    // Constant images: block means equal the pixels.
    assert!((m.block_relmse - want_rel).abs() < 1e-6);
    assert!((m.mean_a[0] - 1.5).abs() < 1e-6 && (m.mean_b[2] - 2.0).abs() < 1e-9);
}

#[test]
fn block_means_cancel_zero_mean_noise_but_keep_bias() {
    // Checkerboard noise ±0.5 around 1 cancels in every 8×8 block; a uniform bias of 0.1 does not.
    let b = constant(32, 16, [1.0; 3]);
    let noisy = RgbImage::from_fn(32, 16, |x, y| [if (x + y) % 2 == 0 { 1.5 } else { 0.5 }; 3]);
    let biased = constant(32, 16, [1.1; 3]);
    assert!(relmse(&noisy, &b).unwrap() > 0.2);
    assert!(block_relmse(&noisy, &b, 8).unwrap() < 1e-12);
    let bias = block_relmse(&biased, &b, 8).unwrap();
    assert!((bias - 0.01 / (1.0 + RELMSE_EPS)).abs() < 1e-6, "{bias}");
    // block = 1 is the per-pixel relMSE.
    assert!((block_relmse(&noisy, &b, 1).unwrap() - relmse(&noisy, &b).unwrap()).abs() < 1e-12);
}

#[test]
fn worst_block_is_found_including_partial_edge_blocks() {
    let b = constant(20, 12, [0.5; 3]);
    let mut a = b.clone();
    // A bright spot in the partial block at the bottom right (x 16..20, y 8..12).
    a.set(18, 10, [4.5; 3]);
    let m = compare(&a, &b, 8).unwrap();
    assert_eq!((m.worst.x, m.worst.y, m.worst.size), (16, 8, 8));
    // Its mean: (15·0.5 + 4.5)/16 = 0.75; relMSE = 0.25²/(0.25 + ε).
    let want = 0.0625 / (0.25 + RELMSE_EPS);
    assert!(
        (m.worst.relmse - want).abs() < 1e-6,
        "{} vs {want}",
        m.worst.relmse
    );
    // 6 blocks, one off.
    assert!((m.block_relmse - want / 6.0).abs() < 1e-6);
}

#[test]
fn size_mismatch_and_non_finite_pixels() {
    let a = constant(4, 4, [1.0; 3]);
    let b = constant(4, 5, [1.0; 3]);
    assert!(compare(&a, &b, 8).unwrap_err().to_string().contains("4x4 vs 4x5"));
    let mut c = a.clone();
    c.set(0, 0, [f32::NAN, 0.0, 0.0]);
    c.set(1, 0, [2.0, 2.0, 2.0]);
    let m = compare(&c, &a, 8).unwrap();
    assert_eq!(m.non_finite, 1);
    assert!(m.relmse.is_finite() && m.relmse > 0.0);
    // 15 finite pixels, one of them off by 1 in each channel.
    assert!((m.mae - 1.0 / 15.0).abs() < 1e-6, "{}", m.mae);
}

#[test]
fn diff_image_is_dark_where_equal_and_bright_where_different() {
    let b = constant(3, 1, [1.0; 3]);
    let mut a = b.clone();
    a.set(1, 0, [1.001, 1.001, 1.001]);
    a.set(2, 0, [5.0, 5.0, 5.0]);
    let d = diff_image(&a, &b).unwrap();
    let lum = |p: [f32; 3]| p[0] + p[1] + p[2];
    assert_eq!(d.get(0, 0), [0.0; 3]);
    assert!(lum(d.get(1, 0)) < 0.05, "{:?}", d.get(1, 0));
    assert_eq!(
        d.get(2, 0),
        [1.0; 3],
        "relative difference ≥ 1 saturates to white"
    );
}
