//! Per-pixel sample generators.
//!
//! Every value is a pure function of `(seed, pixel, sample index, dimension)`: a sampler is reset
//! with [`Sampler::start_pixel_sample`] and then hands out dimensions in order, so an image does
//! not depend on how pixels are spread over threads.
//!
//! | pattern | per dimension (1D) | per dimension pair (2D) |
//! |---|---|---|
//! | [`Pattern::Independent`] | PCG32 (Mitsuba's `independent`) | PCG32 |
//! | [`Pattern::Stratified`] | one sample per stratum of `[0,1)/spp`, strata shuffled | jittered grid, cells shuffled |
//! | [`Pattern::MultiJitter`] | as stratified | correlated multi-jittered (Kensler 2013): stratified in 2D *and* in each 1D projection |
//! | [`Pattern::Sobol`] | Owen-scrambled Sobol | Owen-scrambled Sobol (0,2)-sequence, index shuffled per pair (Burley 2020) |
//!
//! `Sobol` scrambles each pixel's sequence with keys of its own; [`Sampler::z_ordered`] instead
//! gives each pixel its own block of one sequence, in Morton (Z) order of the pixels (Ahmed and
//! Wonka 2020, pbrt-v4's `ZSobolSampler`): pixel `p` of a tile takes indices
//! `morton(p)·B … morton(p)·B + B − 1`, B the sample count rounded up to a power of two. With
//! spp = B = 2ᵐ a pixel's samples are still a (0, m, 2)-net in every pair `next_2d` draws, and
//! the pixels of every aligned 2ᵏ × 2ᵏ square of a tile are one (0, m + 2k, 2)-net together
//! (other sample counts fill part of each block, and the square part of such a net): under a reconstruction filter wider than
//! a pixel (Mitsuba's default gaussian reaches 4 × 4 pixels) the samples a pixel averages are
//! stratified jointly, not pixel by pixel (the renderer turns it on for such filters). Tiles of
//! 2ᵇ × 2ᵇ pixels (b = min(16, ⌊(32 − log₂B)/2⌋), so that indices fit 32 bits) and each further
//! round of B samples of a pixel scramble with keys of their own. Each dimension also shifts the
//! samples' places within a pixel's block (XOR with a key of the pixel's, which leaves the
//! block's points as they are): without it, two dimensions that are not a pair shared the tile's
//! pairing of their points, and the materials scene, z-ordered under a box filter, came out 3.7 %
//! noisier than with per-pixel keys (with it, within 0.3 %; a nested scramble instead of the
//! shift did no better, within the seeds' spread, at 2 % more instructions than the shift). Two
//! such dimensions are decorrelated over the scrambles, but within one image still less
//! thoroughly than by per-pixel keys (the χ² of their joint histogram over a whole image spreads
//! wider; see `tests/sampler.rs`).
//!
//! The shuffles (Kensler's hashed permutation, Burley's nested uniform scramble) use a different
//! key for every dimension, so dimensions are decorrelated ("padding"). `Sobol` is our own
//! low-discrepancy choice: it is stratified at every power of two up to the sample count, in
//! every 2D pair, which gives the lowest error at equal spp of the four (see `tests/sampler.rs`).
//!
//! PCG32 (the same XSH-RR generator as Mitsuba) and the 64-bit key mixer come from
//! `gonio_core::rng` and `gonio_core::hash`.

use glam::{UVec2, Vec2};
use gonio_core::hash::{GOLDEN_GAMMA, mix64};

/// The sample pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// Independent uniform samples.
    Independent,
    /// Stratified (jittered) samples; `jitter = false` puts them at stratum centres.
    Stratified {
        /// Jitter inside strata.
        jitter: bool,
    },
    /// Correlated multi-jittered samples.
    MultiJitter {
        /// Jitter inside strata.
        jitter: bool,
    },
    /// Owen-scrambled Sobol samples (our low-discrepancy sampler).
    Sobol,
}

impl From<crate::scene::SamplerKind> for Pattern {
    fn from(k: crate::scene::SamplerKind) -> Self {
        use crate::scene::SamplerKind as K;
        match k {
            K::Independent => Pattern::Independent,
            K::Stratified { jitter } => Pattern::Stratified { jitter },
            K::MultiJitter { jitter } => Pattern::MultiJitter { jitter },
            // Aliases: see `plugins::sampler::ldsampler` and `plugins::sampler::orthogonal`.
            K::LowDiscrepancy => Pattern::Sobol,
            K::Orthogonal { jitter } => Pattern::MultiJitter { jitter },
        }
    }
}

/// PCG32 (O'Neill 2014, XSH-RR), as in Mitsuba's `independent` sampler: the core's generator.
pub use gonio_core::rng::Pcg32;

/// A sampler: pattern, samples per pixel and seed, plus the state of the current pixel sample.
#[derive(Clone, Debug)]
pub struct Sampler {
    pattern: Pattern,
    spp: u32,
    seed: u64,
    pixel_key: u64,
    pixel: UVec2,
    index: u32,
    /// The Sobol pattern's index of the current sample in the tile's sequence: the pixel's
    /// block and the sample's place in it (module docs).
    sobol_index: u32,
    /// What the dimension keys are made from: the pixel's key, or in Z order the key of the
    /// pixel's tile and of the sample's round of B.
    scramble_key: u64,
    /// The Sobol pattern's pixels in Z order ([`Sampler::z_ordered`]), or `None`.
    z: Option<ZOrder>,
    dim: u32,
    rng: Pcg32,
    /// [`Sampler::key`] of the first [`CACHED_KEYS`] dimensions of the current pixel (in Z order:
    /// tile and round), made once per pixel rather than once per sample and dimension (a
    /// pixel's samples run one after another).
    dim_keys: [u32; CACHED_KEYS],
}

/// The Z order's layout and the current pixel's place in it (module docs).
#[derive(Clone, Copy, Debug)]
struct ZOrder {
    /// log₂B (the bits of a sample's place in its pixel's block), their mask, and the bits per
    /// axis of a tile's pixel coordinates ([`zsobol_layout`]).
    block_bits: u32,
    block_mask: u32,
    tile_bits: u32,
    /// The key of the pixel's tile (round 0) and the pixel's block, made once per pixel.
    tile_key: u64,
    block: u32,
    /// The keys shifting the places in the pixel's block per dimension (its first
    /// [`CACHED_KEYS`] dimensions, made once per pixel).
    pixel_dim_keys: [u32; CACHED_KEYS],
}

impl ZOrder {
    /// The layout for `spp` samples per pixel, before any pixel.
    fn new(spp: u32) -> Self {
        let (block_bits, tile_bits) = zsobol_layout(spp);
        Self {
            block_bits,
            block_mask: ((1u64 << block_bits) - 1) as u32,
            tile_bits,
            tile_key: 0,
            block: 0,
            pixel_dim_keys: [0; CACHED_KEYS],
        }
    }

    /// The scramble key of round `round` of the pixel's samples (the tile's for the first B).
    #[inline]
    fn round_key(&self, round: u32) -> u64 {
        if round == 0 {
            self.tile_key
        } else {
            mix64(self.tile_key ^ ROUND_SALT ^ (round as u64).wrapping_mul(GOLDEN_GAMMA))
        }
    }
}

/// Dimensions whose keys a sampler keeps per pixel: the structured ones a path draws.
const CACHED_KEYS: usize = STRUCTURED_DIMS as usize + 1;

/// `keys[dim]` = [`Sampler::dim_key`]`(key, dim)` for the cached dimensions.
#[inline]
fn fill_dim_keys(keys: &mut [u32; CACHED_KEYS], key: u64) {
    for (dim, k) in keys.iter_mut().enumerate() {
        *k = Sampler::dim_key(key, dim as u32);
    }
}

/// [`Sampler::dim_key`]`(key, dim)`, from `keys` ([`fill_dim_keys`] of `key`) where cached.
#[inline]
fn cached_dim_key(keys: &[u32; CACHED_KEYS], key: u64, dim: u32) -> u32 {
    match keys.get(dim as usize) {
        Some(&k) => k,
        None => Sampler::dim_key(key, dim),
    }
}

#[inline]
fn u32_to_f32(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Kensler's hashed permutation of `0..l` ("Correlated Multi-Jittered Sampling", 2013).
#[inline]
fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    if l <= 1 {
        return 0;
    }
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | (p >> 27));
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    ((i as u64 + p as u64) % l as u64) as u32
}

/// Kensler's hashed float in [0, 1).
#[inline]
fn randfloat(mut i: u32, p: u32) -> f32 {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb365_34e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc_4795);
    i ^= 0xdf6e_307f;
    i ^= i >> 17;
    i = i.wrapping_mul(1 | (p >> 18));
    u32_to_f32(i)
}

/// The Laine–Karras-style hash of Burley 2020 ("Practical Hash-based Owen Scrambling", JCGT
/// 9(4): its `laine_karras_permutation`, seed added first, then four xor-multiplies with Burley's
/// constants): an Owen scramble in reversed-bit order.
#[inline]
fn lk_permute(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Nested uniform (Owen) scramble of the bits of `x`.
#[inline]
fn owen_scramble(x: u32, seed: u32) -> u32 {
    lk_permute(x.reverse_bits(), seed).reverse_bits()
}

/// Bit-reversed Sobol dimension 1 (direction numbers `v₀ = 2³¹`, `v_{k+1} = v_k ^ (v_k >> 1)`),
/// as four byte-indexed tables: the index of an Owen-shuffled sample is a full 32-bit number, and
/// four lookups replace a 32-step loop over its bits.
const SOBOL_Y_REV: [[u32; 256]; 4] = {
    let mut v = [0u32; 32];
    v[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        k += 1;
    }
    let mut t = [[0u32; 256]; 4];
    let mut byte = 0;
    while byte < 4 {
        let mut b = 0;
        while b < 256 {
            let mut acc = 0u32;
            let mut j = 0;
            while j < 8 {
                if b & (1 << j) != 0 {
                    acc ^= v[8 * byte + j];
                }
                j += 1;
            }
            t[byte][b] = acc.reverse_bits();
            b += 1;
        }
        byte += 1;
    }
    t
};

/// Sobol dimension 1 of index `i`, bit-reversed.
#[inline]
fn sobol_y_rev(i: u32) -> u32 {
    SOBOL_Y_REV[0][(i & 255) as usize]
        ^ SOBOL_Y_REV[1][((i >> 8) & 255) as usize]
        ^ SOBOL_Y_REV[2][((i >> 16) & 255) as usize]
        ^ SOBOL_Y_REV[3][(i >> 24) as usize]
}

/// Owen-scrambled Sobol dimensions 0 and 1 of the Owen-shuffled index `owen_scramble(i, k)`
/// (Burley 2020), with the bit reversals folded: dimension 0 is `reverse(i)`, so its scramble is
/// `reverse(lk(idx))`; dimension 1 comes bit-reversed from the tables.
#[inline]
fn owen_sobol(i: u32, k: u32) -> (u32, u32) {
    let idx = owen_scramble(i, k);
    let x = lk_permute(idx, k.wrapping_mul(0x2545_f491) ^ 0x68bc_21eb).reverse_bits();
    let y = lk_permute(sobol_y_rev(idx), k.wrapping_mul(0x9e37_79b9) ^ 0x02e5_be93).reverse_bits();
    (x, y)
}

/// Salt of the rounds' keys ([`Sampler::z_ordered`]), apart from the dimensions' keys made
/// from the same tile key.
const ROUND_SALT: u64 = 0x9fb2_1c65_1e98_df25;

/// Salt of the per-pixel block shifts' keys ([`Sampler::z_ordered`]), apart from the pixel's
/// other keys.
const PIXEL_SHUFFLE_SALT: u64 = 0x5bd1_e995_2f4a_7c15;

/// The Sobol pattern's layout for `spp` samples per pixel: log₂ of the block a pixel takes (the
/// sample count rounded up to a power of two) and the bits per axis of a tile's pixel
/// coordinates, so that block and sample index fit 32 bits (module docs).
#[inline]
fn zsobol_layout(spp: u32) -> (u32, u32) {
    let lg = 32 - spp.max(1).wrapping_sub(1).leading_zeros();
    (lg, ((32 - lg) / 2).min(16))
}

/// The Morton (Z-order) code of the low `bits` bits of `x` and `y`: x in the even bits, y in the
/// odd ones.
#[inline]
fn morton2(x: u32, y: u32, bits: u32) -> u32 {
    /// Spreads the low 16 bits of `v` to the even bits.
    fn spread(v: u32) -> u32 {
        let mut v = v & 0xffff;
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    }
    let mask = ((1u64 << bits) - 1) as u32;
    spread(x & mask) | (spread(y & mask) << 1)
}

impl Sampler {
    /// A sampler with `spp` samples per pixel (at least 1) and a seed.
    pub fn new(pattern: Pattern, spp: u32, seed: u64) -> Self {
        let mut s = Self {
            pattern,
            spp: spp.max(1),
            seed,
            pixel_key: 0,
            pixel: UVec2::ZERO,
            index: 0,
            sobol_index: 0,
            scramble_key: 0,
            z: None,
            dim: 0,
            rng: Pcg32::new(0, 0),
            dim_keys: [0; CACHED_KEYS],
        };
        s.set_scramble_key(0);
        s.set_pixel(UVec2::ZERO);
        s.start_pixel_sample(UVec2::ZERO, 0);
        s
    }

    /// The same sampler with the [`Pattern::Sobol`] pixels taking blocks of one sequence in Z
    /// order when `on` (module docs): for reconstruction filters that reach neighbouring
    /// pixels. Other patterns are unchanged.
    pub fn z_ordered(mut self, on: bool) -> Self {
        self.z = (on && self.pattern == Pattern::Sobol).then(|| ZOrder::new(self.spp));
        self.set_pixel(self.pixel);
        self.start_pixel_sample(self.pixel, self.index);
        self
    }

    /// The sampler a scene asks for (Mitsuba's plugins map one to one).
    pub fn from_scene(s: &crate::scene::SamplerDesc) -> Self {
        Self::new(s.kind.into(), s.sample_count, s.seed)
    }

    /// Samples per pixel.
    pub fn spp(&self) -> u32 {
        self.spp
    }

    /// The pattern.
    pub fn pattern(&self) -> Pattern {
        self.pattern
    }

    /// Starts sample `index` (in `0..spp`; larger values continue the pixel's sequence, or in Z
    /// order start rounds of B with keys of their own) of `pixel`.
    pub fn start_pixel_sample(&mut self, pixel: UVec2, index: u32) {
        if pixel != self.pixel {
            self.set_pixel(pixel);
        }
        self.index = index;
        self.dim = 0;
        self.sobol_index = index;
        if let Some(z) = self.z {
            let key = z.round_key(((index as u64) >> z.block_bits) as u32);
            if key != self.scramble_key {
                self.set_scramble_key(key);
            }
            self.sobol_index = (((z.block as u64) << z.block_bits) as u32) | (index & z.block_mask);
        }
        if self.pattern == Pattern::Independent
            || matches!(self.pattern, Pattern::Stratified { jitter: true })
        {
            self.rng = Pcg32::new(self.pixel_key, index as u64);
        }
    }

    /// Moves to `pixel`: its key and its dimensions' keys.
    fn set_pixel(&mut self, pixel: UVec2) {
        self.pixel_key = Self::pixel_key(self.seed, pixel);
        self.pixel = pixel;
        let key = match &mut self.z {
            Some(z) => {
                let bits = z.tile_bits;
                let tile = UVec2::new(
                    ((pixel.x as u64) >> bits) as u32,
                    ((pixel.y as u64) >> bits) as u32,
                );
                z.tile_key = mix64(Self::pixel_key(self.seed, tile));
                z.block = morton2(pixel.x, pixel.y, bits);
                fill_dim_keys(&mut z.pixel_dim_keys, self.pixel_key ^ PIXEL_SHUFFLE_SALT);
                z.tile_key
            }
            None => self.pixel_key,
        };
        // Z-ordered pixels of one tile share their keys: made once per tile.
        if key != self.scramble_key {
            self.set_scramble_key(key);
        }
    }

    /// Keys every dimension from `key` (the cached ones made now).
    fn set_scramble_key(&mut self, key: u64) {
        self.scramble_key = key;
        fill_dim_keys(&mut self.dim_keys, key);
    }

    /// The key of `pixel` under `seed`.
    #[inline]
    fn pixel_key(seed: u64, pixel: UVec2) -> u64 {
        mix64(seed ^ mix64(((pixel.y as u64) << 32) | pixel.x as u64))
    }

    /// The key of dimension `dim` under scramble key `key`.
    #[inline]
    fn dim_key(key: u64, dim: u32) -> u32 {
        mix64(key ^ (dim as u64).wrapping_mul(GOLDEN_GAMMA)) as u32
    }

    /// The key of dimension `dim` of the current pixel sample.
    #[inline]
    fn key(&self, dim: u32) -> u32 {
        cached_dim_key(&self.dim_keys, self.scramble_key, dim)
    }

    /// The Sobol index dimension `dim` takes: in Z order, the pixel's block with the sample's
    /// place in it shifted per pixel and dimension (XOR with a key's log₂B low bits, a
    /// permutation of the block), so that two dimensions pair a pixel's points by one of B
    /// shifts chosen per pixel rather than the same way in the whole tile; the block's points,
    /// and so the nets, are the same.
    #[inline]
    fn z_index(&self, dim: u32) -> u32 {
        let Some(z) = &self.z else {
            return self.sobol_index;
        };
        let k = cached_dim_key(&z.pixel_dim_keys, self.pixel_key ^ PIXEL_SHUFFLE_SALT, dim);
        self.sobol_index ^ (k & z.block_mask)
    }

    /// The next sample dimension.
    pub fn next_1d(&mut self) -> f32 {
        let dim = self.dim;
        self.dim += 1;
        let (i, n) = (self.index, self.spp);
        match self.pattern {
            Pattern::Independent => self.rng.next_f32(),
            Pattern::Stratified { jitter } | Pattern::MultiJitter { jitter } => {
                let k = self.key(dim);
                let stratum = permute(i % n, n, k) as f32;
                let j = if !jitter {
                    0.5
                } else if let Pattern::Stratified { .. } = self.pattern {
                    self.rng.next_f32()
                } else {
                    randfloat(i, k.wrapping_mul(0x967a_889b))
                };
                ((stratum + j) / n as f32).min(ONE_MINUS_EPS)
            }
            Pattern::Sobol => {
                let k = self.key(dim);
                let idx = owen_scramble(self.z_index(dim), k);
                u32_to_f32(lk_permute(idx, k.wrapping_mul(0x2545_f491) ^ 0x68bc_21eb).reverse_bits())
            }
        }
    }

    /// The next pair of sample dimensions.
    pub fn next_2d(&mut self) -> Vec2 {
        let dim = self.dim;
        self.dim += 2;
        let (i, n) = (self.index, self.spp);
        match self.pattern {
            Pattern::Independent => {
                let x = self.rng.next_f32();
                Vec2::new(x, self.rng.next_f32())
            }
            Pattern::Stratified { jitter } => {
                let k = self.key(dim);
                let nx = (n as f32).sqrt().floor().max(1.0) as u32;
                let ny = n.div_ceil(nx);
                let cell = permute(i % (nx * ny), nx * ny, k);
                let (jx, jy) = if jitter {
                    (self.rng.next_f32(), self.rng.next_f32())
                } else {
                    (0.5, 0.5)
                };
                Vec2::new(
                    (((cell % nx) as f32 + jx) / nx as f32).min(ONE_MINUS_EPS),
                    (((cell / nx) as f32 + jy) / ny as f32).min(ONE_MINUS_EPS),
                )
            }
            Pattern::MultiJitter { jitter } => {
                // Kensler 2013, arbitrary N: m columns, n rows.
                let p = self.key(dim);
                let m = (n as f32).sqrt().floor().max(1.0) as u32;
                let rows = n.div_ceil(m);
                let s = permute(i % n, n, p.wrapping_mul(0x5163_3e2d));
                let sx = permute(s % m, m, p.wrapping_mul(0x68bc_21eb));
                let sy = permute(s / m, rows, p.wrapping_mul(0x02e5_be93));
                let (jx, jy) = if jitter {
                    (
                        randfloat(s, p.wrapping_mul(0x967a_889b)),
                        randfloat(s, p.wrapping_mul(0x368c_c8b7)),
                    )
                } else {
                    (0.5, 0.5)
                };
                Vec2::new(
                    ((sx as f32 + (sy as f32 + jx) / rows as f32) / m as f32).min(ONE_MINUS_EPS),
                    ((s as f32 + jy) / n as f32).min(ONE_MINUS_EPS),
                )
            }
            Pattern::Sobol => {
                let (x, y) = owen_sobol(self.z_index(dim), self.key(dim));
                Vec2::new(u32_to_f32(x), u32_to_f32(y))
            }
        }
    }

    /// A film position in pixel `pixel`: `pixel + next_2d()`.
    pub fn next_pixel_position(&mut self, pixel: UVec2) -> Vec2 {
        pixel.as_vec2() + self.next_2d()
    }
}

const ONE_MINUS_EPS: f32 = 1.0 - f32::EPSILON / 2.0;

/// The random numbers a path consumes, in a fixed order (so stratified and low-discrepancy
/// samplers keep their dimensions aligned).
pub trait PathSampler {
    /// One number in [0, 1).
    fn next_1d(&mut self) -> f32;
    /// Two numbers in [0, 1)².
    fn next_2d(&mut self) -> Vec2;
    /// Where the sequence stands, for [`PathSampler::rewind`].
    type Mark: Copy;
    /// The current position.
    fn mark(&self) -> Self::Mark;
    /// Back to a position [`PathSampler::mark`] gave: the numbers from there on come again.
    fn rewind(&mut self, mark: Self::Mark);
}

/// Independent numbers from a PCG32 stream (light paths, tests).
impl PathSampler for Pcg32 {
    #[inline]
    fn next_1d(&mut self) -> f32 {
        self.next_f32()
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        self.next_vec2()
    }
    type Mark = Pcg32;
    fn mark(&self) -> Pcg32 {
        *self
    }
    fn rewind(&mut self, mark: Pcg32) {
        *self = mark;
    }
}

/// Dimensions drawn from the structured pattern before switching to independent numbers: the
/// camera (3) and two vertices with a smooth lobe (6 each: light choice, light point, lobe,
/// direction; a purely delta vertex takes one, its lobe choice, and roulette numbers start at
/// `rr_depth`). Stratification matters most for the first bounces; beyond them a scrambled Sobol
/// point costs more than it gains, so deeper dimensions come from a PCG32 stream keyed by
/// [`Sampler::sample_key`] — still a pure function of the sample, as determinism requires.
pub const STRUCTURED_DIMS: u32 = 3 + 2 * 6;

impl Sampler {
    /// A 64-bit key of the current sample: (seed, pixel, sample index), well mixed. It seeds the
    /// independent streams of the sample ([`PaddedSampler`], light subpaths).
    #[inline]
    pub fn sample_key(&self) -> u64 {
        let (px, py, s) = (self.pixel.x as u64, self.pixel.y as u64, self.index as u64);
        mix64(self.seed ^ (px << 40) ^ (py << 20) ^ s.wrapping_mul(GOLDEN_GAMMA))
    }

    /// The rest of the current sample's dimensions for a path: the pattern's up to
    /// [`STRUCTURED_DIMS`] (all of them for [`Pattern::Independent`]), then a PCG32 stream keyed
    /// by [`Self::sample_key`].
    pub fn padded(&mut self) -> PaddedSampler<'_> {
        let limit = if self.pattern == Pattern::Independent {
            u32::MAX
        } else {
            STRUCTURED_DIMS
        };
        PaddedSampler {
            used: self.dim,
            key: self.sample_key(),
            sampler: self,
            limit,
            rng: None,
        }
    }
}

/// A [`Sampler`]'s current sample seen as a [`PathSampler`], padded with independent numbers
/// beyond [`STRUCTURED_DIMS`] (see [`Sampler::padded`]).
#[derive(Debug)]
pub struct PaddedSampler<'s> {
    sampler: &'s mut Sampler,
    used: u32,
    limit: u32,
    key: u64,
    rng: Option<Pcg32>,
}

impl PaddedSampler<'_> {
    /// The key of the sample ([`Sampler::sample_key`]).
    pub fn key(&self) -> u64 {
        self.key
    }

    #[inline]
    fn rng(&mut self) -> &mut Pcg32 {
        let key = self.key;
        self.rng
            .get_or_insert_with(|| Pcg32::new(key, key.rotate_left(17) ^ GOLDEN_GAMMA))
    }
}

/// A [`PaddedSampler`]'s position: the pattern's dimension and stream (the independent and
/// jittered patterns draw from the sampler's own PCG32), the numbers taken, its own stream.
#[derive(Clone, Copy, Debug)]
pub struct PaddedMark {
    dim: u32,
    pattern_rng: Pcg32,
    used: u32,
    rng: Option<Pcg32>,
}

impl PathSampler for PaddedSampler<'_> {
    type Mark = PaddedMark;
    fn mark(&self) -> PaddedMark {
        PaddedMark {
            dim: self.sampler.dim,
            pattern_rng: self.sampler.rng,
            used: self.used,
            rng: self.rng,
        }
    }
    fn rewind(&mut self, mark: PaddedMark) {
        self.sampler.dim = mark.dim;
        self.sampler.rng = mark.pattern_rng;
        self.used = mark.used;
        self.rng = mark.rng;
    }
    #[inline]
    fn next_1d(&mut self) -> f32 {
        if self.used < self.limit {
            self.used += 1;
            self.sampler.next_1d()
        } else {
            self.rng().next_f32()
        }
    }
    #[inline]
    fn next_2d(&mut self) -> Vec2 {
        if self.used + 1 < self.limit {
            self.used += 2;
            self.sampler.next_2d()
        } else {
            let r = self.rng();
            let x = r.next_f32();
            Vec2::new(x, r.next_f32())
        }
    }
}

#[cfg(test)]
mod tests;
