//! Three coordinates of `N` lanes each: `N` directions at once (structure of arrays).

use super::{F32s, Isa, Mask, Portable};
use glam::Vec3;
use std::ops::{Add, Mul, Neg, Sub};

/// `N` 3D vectors, one per lane, stored as three [`F32s`].
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Vec3s<const N: usize, X: Isa = Portable> {
    /// x of every lane.
    pub x: F32s<N, X>,
    /// y of every lane.
    pub y: F32s<N, X>,
    /// z of every lane.
    pub z: F32s<N, X>,
}

impl<const N: usize, X: Isa> Vec3s<N, X> {
    /// From the three coordinates.
    #[inline(always)]
    pub fn new(x: F32s<N, X>, y: F32s<N, X>, z: F32s<N, X>) -> Self {
        Self { x, y, z }
    }
    /// The same vector in every lane.
    #[inline(always)]
    pub fn splat(v: Vec3) -> Self {
        Self::new(F32s::splat(v.x), F32s::splat(v.y), F32s::splat(v.z))
    }
    /// Lane `k` is `f(k)`.
    #[inline(always)]
    pub fn from_fn(mut f: impl FnMut(usize) -> Vec3) -> Self {
        let mut r = Self::default();
        for k in 0..N {
            let v = f(k);
            (r.x.0[k], r.y.0[k], r.z.0[k]) = (v.x, v.y, v.z);
        }
        r
    }
    /// Lane `k`.
    #[inline(always)]
    pub fn lane(&self, k: usize) -> Vec3 {
        Vec3::new(self.x.0[k], self.y.0[k], self.z.0[k])
    }
    /// Dot product per lane.
    #[inline(always)]
    pub fn dot(self, o: Self) -> F32s<N, X> {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Squared length per lane.
    #[inline(always)]
    pub fn length_squared(self) -> F32s<N, X> {
        self.dot(self)
    }
    /// Unit vectors (NaN or ∞ lanes where the length is 0, as `glam::Vec3::normalize`).
    #[inline(always)]
    pub fn normalize(self) -> Self {
        self * self.length_squared().sqrt().recip()
    }
    /// Unit vectors, `fallback` where the length is 0 or not finite (as
    /// `glam::Vec3::normalize_or`).
    #[inline(always)]
    pub fn normalize_or(self, fallback: Vec3) -> Self {
        let rcp = self.length_squared().sqrt().recip();
        let ok = rcp.is_finite() & rcp.gt(0.0);
        ok.select3(self * rcp, Self::splat(fallback))
    }
    /// The mirror reflection of `self` about the unit normal `m` per lane, 2(v·m)m − v (the
    /// scalar models' `2.0 * wi.dot(m) * m - wi`, bit for bit).
    #[inline(always)]
    pub fn reflect_about(self, m: Self) -> Self {
        m * (2.0 * self.dot(m)) - self
    }
    /// Cross product per lane.
    #[inline(always)]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// Lanes whose coordinates are all finite.
    #[inline(always)]
    pub fn is_finite(self) -> Mask<N, X> {
        self.x.is_finite() & self.y.is_finite() & self.z.is_finite()
    }
}

impl<const N: usize, X: Isa> Add for Vec3s<N, X> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<const N: usize, X: Isa> Sub for Vec3s<N, X> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<const N: usize, X: Isa> Neg for Vec3s<N, X> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<const N: usize, X: Isa> Mul<F32s<N, X>> for Vec3s<N, X> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: F32s<N, X>) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

impl<const N: usize, X: Isa> Mul<Vec3s<N, X>> for F32s<N, X> {
    type Output = Vec3s<N, X>;
    #[inline(always)]
    fn mul(self, v: Vec3s<N, X>) -> Vec3s<N, X> {
        v * self
    }
}
