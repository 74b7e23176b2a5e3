//! Unit tests of the sampler's private helpers: the Sobol tables, the folded scrambles, the key
//! caches and the Z-order layout.

use super::*;

/// The direct definition: XOR of the direction numbers of the set bits.
fn sobol_y_loop(i: u32) -> u32 {
    let (mut y, mut v, mut bits) = (0u32, 1u32 << 31, i);
    while bits != 0 {
        if bits & 1 != 0 {
            y ^= v;
        }
        bits >>= 1;
        v ^= v >> 1;
    }
    y
}

#[test]
fn table_sobol_matches_the_definition() {
    let mut r = Pcg32::new(1, 2);
    for i in (0..4096).chain((0..10_000).map(|_| r.next_u32())) {
        assert_eq!(sobol_y_rev(i).reverse_bits(), sobol_y_loop(i), "index {i}");
    }
    // First points of dimension 1: 0, 1/2, 3/4, 1/4 (·2³²).
    let first: Vec<u32> = (0..4).map(sobol_y_loop).collect();
    assert_eq!(first, vec![0, 1 << 31, 3 << 30, 1 << 30]);
}

#[test]
fn folded_scrambles_equal_the_plain_composition() {
    let mut r = Pcg32::new(3, 4);
    for _ in 0..10_000 {
        let (i, k) = (r.next_u32() % 4096, r.next_u32());
        let idx = owen_scramble(i, k);
        let x = owen_scramble(idx.reverse_bits(), k.wrapping_mul(0x2545_f491) ^ 0x68bc_21eb);
        let y = owen_scramble(sobol_y_loop(idx), k.wrapping_mul(0x9e37_79b9) ^ 0x02e5_be93);
        assert_eq!(owen_sobol(i, k), (x, y));
    }
}

/// The per-pixel key cache: a sampler that has visited other pixels has each dimension's
/// key as the definition gives it, and draws, for a pixel sample, exactly the numbers of a
/// fresh sampler started there, over the cached dimensions and past them.
#[test]
fn a_rewound_path_sampler_repeats_its_numbers() {
    // Marked in the pattern's dimensions and past them (the independent stream, started
    // lazily or already running): every number after the mark comes again, and the
    // numbers after it differ from those before.
    for pattern in [
        Pattern::Sobol,
        Pattern::Independent,
        Pattern::Stratified { jitter: true },
    ] {
        for skip in [0u32, 5, STRUCTURED_DIMS - 1, STRUCTURED_DIMS + 3] {
            let mut sampler = Sampler::new(pattern, 16, 3);
            sampler.start_pixel_sample(UVec2::new(2, 7), 5);
            let mut padded = sampler.padded();
            let before: Vec<f32> = (0..skip).map(|_| padded.next_1d()).collect();
            let mark = padded.mark();
            let draw = |p: &mut PaddedSampler| -> Vec<f32> {
                (0..12)
                    .flat_map(|_| {
                        let v = p.next_2d();
                        [v.x, v.y, p.next_1d()]
                    })
                    .collect()
            };
            let first = draw(&mut padded);
            padded.rewind(mark);
            assert_eq!(draw(&mut padded), first, "{pattern:?}, mark after {skip}");
            assert!(before.iter().all(|b| !first.contains(b)), "{pattern:?}, {skip}");
        }
    }
    let mut rng = Pcg32::new(1, 2);
    let mark = rng.mark();
    let a = [rng.next_1d(), rng.next_1d()];
    rng.rewind(mark);
    assert_eq!([rng.next_1d(), rng.next_1d()], a);
}

#[test]
fn cached_dimension_keys_give_the_numbers_of_a_fresh_sampler() {
    for (pattern, z) in [
        (Pattern::Sobol, false),
        (Pattern::Sobol, true),
        (Pattern::MultiJitter { jitter: true }, false),
    ] {
        let draw = |s: &mut Sampler| -> Vec<f32> {
            (0..2 * CACHED_KEYS)
                .flat_map(|_| {
                    let v = s.next_2d();
                    [v.x, v.y, s.next_1d()]
                })
                .collect()
        };
        let mut walked = Sampler::new(pattern, 16, 9).z_ordered(z);
        // Z order: the second pixel in another tile (b = 14 bits at 16 spp), then a
        // sample of the next round (index >= 16), then back.
        for (pixel, index) in [
            (UVec2::new(3, 4), 0),
            (UVec2::new(1 << 14, 6), 1),
            (UVec2::new(3, 4), 21),
            (UVec2::new(3, 5), 2),
        ] {
            walked.start_pixel_sample(pixel, index);
            // The keys by their definition: the pixel's, or in Z order the tile's and the
            // round's.
            let key = if z {
                let tile = Sampler::pixel_key(9, UVec2::new(pixel.x >> 14, pixel.y >> 14));
                let round = (index / 16) as u64;
                if round == 0 {
                    mix64(tile)
                } else {
                    mix64(mix64(tile) ^ ROUND_SALT ^ round.wrapping_mul(GOLDEN_GAMMA))
                }
            } else {
                Sampler::pixel_key(9, pixel)
            };
            for dim in 0..2 * CACHED_KEYS as u32 {
                assert_eq!(walked.key(dim), Sampler::dim_key(key, dim), "{pixel}, {dim}");
            }
            let mut fresh = Sampler::new(pattern, 16, 9).z_ordered(z);
            fresh.start_pixel_sample(pixel, index);
            assert_eq!(
                draw(&mut walked),
                draw(&mut fresh),
                "{pattern:?} at {pixel}, {index}"
            );
        }
    }
}

/// The Z order's layout at its edges: block bits and tile bits for sample counts from 1 to
/// u32::MAX (indices stay within 32 bits), Morton codes at 0 and 16 bits per axis.
#[test]
fn z_order_layout_fits_32_bits_at_every_sample_count() {
    for (spp, lg, bits) in [
        (1u32, 0u32, 16u32),
        (2, 1, 15),
        (3, 2, 15),
        (64, 6, 13),
        (65, 7, 12),
        (1 << 31, 31, 0),
        ((1 << 31) + 1, 32, 0),
        (u32::MAX, 32, 0),
    ] {
        assert_eq!(zsobol_layout(spp), (lg, bits), "spp {spp}");
        assert!(lg + 2 * bits <= 32, "spp {spp}");
    }
    assert_eq!(morton2(u32::MAX, u32::MAX, 0), 0);
    assert_eq!(morton2(0xffff, 0, 16), 0x5555_5555);
    assert_eq!(morton2(0, 0xffff, 16), 0xaaaa_aaaa);
    assert_eq!(morton2(0b101, 0b011, 3), 0b01_10_11);
    // Coordinates beyond the tile's bits wrap into the tile.
    assert_eq!(morton2(5 + (1 << 16), 3, 16), morton2(5, 3, 16));
}

/// In Z order, samples past `spp` but inside the block B (spp 12, B 16) stay in round 0 with the
/// tile's keys, the next round's take other keys, and a pixel's first sample after them is its
/// first sample again; a pixel beyond 2¹⁶ (one sample per pixel: 16 tile bits) is in another
/// tile.
#[test]
fn z_order_rounds_and_tiles_take_the_keys_they_should() {
    let mut s = Sampler::new(Pattern::Sobol, 12, 4).z_ordered(true);
    let draw = |s: &mut Sampler, pixel: UVec2, index: u32| -> (u32, Vec2) {
        s.start_pixel_sample(pixel, index);
        (s.sobol_index, s.next_2d())
    };
    let p = UVec2::new(6, 1);
    let (first_index, first) = draw(&mut s, p, 0);
    let round0_key = s.scramble_key;
    let (i13, _) = draw(&mut s, p, 13);
    assert_eq!(s.scramble_key, round0_key, "index 13 < B = 16 is round 0");
    assert_eq!(i13, (first_index & !15) | 13);
    let _ = draw(&mut s, p, 16);
    assert_ne!(s.scramble_key, round0_key, "index 16 starts round 1");
    assert_eq!(draw(&mut s, p, 0), (first_index, first));
    let mut one = Sampler::new(Pattern::Sobol, 1, 4).z_ordered(true);
    one.start_pixel_sample(UVec2::new(3, 3), 0);
    let near = one.scramble_key;
    one.start_pixel_sample(UVec2::new(3 + (1 << 16), 3), 0);
    assert_ne!(one.scramble_key, near);
    assert_eq!(one.sobol_index, morton2(3, 3, 16));
}
