//! `tabulated`: an isotropic BRDF given by a measured table (gonio's own plugin; Mitsuba's
//! closest relative is `measured`, which reads RGL's adaptive format instead).
//!
//! The table samples f(θi, θo, φd, λ) on a grid: source polar angle θi, detector polar angle
//! θo, azimuth difference φd = φo − φi ∈ [0°, 180°] (isotropy and mirror symmetry fold the rest
//! of the sphere onto it), wavelength λ. It is what `gonio measure` writes (the text format is
//! in `gonio-render::tabulated_io` and `docs/instruments.md`).
//!
//! * **Interpolation**: trilinear in (θi, θo, φd), linear in λ, clamped at the ends of each
//!   axis; negative entries are clamped to 0.
//! * **Reciprocity** is enforced: f(wi, wo) = ½[T(θi, θo, φd) + T(θo, θi, φd)], with T the
//!   interpolated table, so f(wi, wo) = f(wo, wi) exactly whatever noise the measurement had.
//! * **Importance sampling**: for each θi node a piecewise-constant distribution over cells of
//!   (θo, φd) ∈ [0, 90°] × [0, 180°] proportional to f·cos θo (mean over λ) times the cell's
//!   solid angle; the sign of φd is chosen with probability ½; between θi nodes the two
//!   neighbouring distributions are mixed with the interpolation weights, and a fraction
//!   [`Tabulated::DEFENSIVE`] of cosine-weighted sampling keeps the pdf positive wherever f may
//!   be. `pdf` evaluates exactly this mixture, so sample and pdf agree.
//!
//! One-sided like every Mitsuba BRDF: zero unless both directions are above the surface.
//!
//! | parameter  | type   | default | meaning                                  |
//! |------------|--------|---------|------------------------------------------|
//! | `filename` | string | —       | the table (read by the scene loader)     |

use crate::bsdf::{Bsdf, BsdfContext, BsdfFlags, BsdfSample};
use crate::math::find_interval;
use crate::sampling::Distribution2D;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::warp::{square_to_cosine_hemisphere, square_to_cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, PI};

/// The raw table: axes and values, `values[((i·n_o + o)·n_φ + p)·n_λ + l]`.
#[derive(Clone, Debug, PartialEq)]
pub struct TabulatedData {
    /// Source polar angles θi, degrees, strictly increasing, in [0, 90].
    pub theta_i_deg: Vec<f32>,
    /// Detector polar angles θo, degrees, strictly increasing, in [0, 90].
    pub theta_o_deg: Vec<f32>,
    /// Azimuth differences φd, degrees, strictly increasing, in [0, 180].
    pub phi_d_deg: Vec<f32>,
    /// Wavelengths, nm, strictly increasing.
    pub wavelengths_nm: Vec<f32>,
    /// f, 1/sr.
    pub values: Vec<f32>,
    /// Standard error of each value, when the table was measured.
    pub stderr: Option<Vec<f32>>,
    /// Free text: what was measured and how.
    pub description: String,
}

fn check_axis(name: &str, v: &[f32], lo: f32, hi: f32) -> Result<(), String> {
    if v.is_empty() {
        return Err(format!("axis {name} is empty"));
    }
    if let Some(x) = v.iter().find(|x| !(x.is_finite() && **x >= lo && **x <= hi)) {
        return Err(format!("axis {name}: value {x} outside [{lo}, {hi}]"));
    }
    if let Some(w) = v.windows(2).find(|w| w[0] >= w[1]) {
        return Err(format!(
            "axis {name} is not strictly increasing at {} → {}",
            w[0], w[1]
        ));
    }
    Ok(())
}

impl TabulatedData {
    /// Validates and builds a table; the error names the axis or entry at fault.
    pub fn new(
        theta_i_deg: Vec<f32>,
        theta_o_deg: Vec<f32>,
        phi_d_deg: Vec<f32>,
        wavelengths_nm: Vec<f32>,
        values: Vec<f32>,
        stderr: Option<Vec<f32>>,
        description: String,
    ) -> Result<Self, String> {
        check_axis("theta_i", &theta_i_deg, 0.0, 90.0)?;
        check_axis("theta_o", &theta_o_deg, 0.0, 90.0)?;
        check_axis("phi_d", &phi_d_deg, 0.0, 180.0)?;
        check_axis("wavelengths", &wavelengths_nm, 1.0, 1.0e5)?;
        let n = theta_i_deg.len() * theta_o_deg.len() * phi_d_deg.len() * wavelengths_nm.len();
        if values.len() != n {
            return Err(format!(
                "expected {n} values (θi × θo × φd × λ), found {}",
                values.len()
            ));
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(format!("value #{k} is not finite ({})", values[k]));
        }
        if let Some(e) = &stderr
            && e.len() != n
        {
            return Err(format!("expected {n} standard errors, found {}", e.len()));
        }
        Ok(Self {
            theta_i_deg,
            theta_o_deg,
            phi_d_deg,
            wavelengths_nm,
            values,
            stderr,
            description,
        })
    }

    /// Flat index of entry (i, o, p, l).
    #[inline]
    pub fn index(&self, i: usize, o: usize, p: usize, l: usize) -> usize {
        ((i * self.theta_o_deg.len() + o) * self.phi_d_deg.len() + p) * self.wavelengths_nm.len() + l
    }
}

/// Position of `x` on a sorted axis: (lower index, weight of the upper), clamped at the ends.
#[inline]
fn locate(axis: &[f32], x: f32) -> (usize, f32) {
    let n = axis.len();
    if n == 1 || x <= axis[0] {
        return (0, 0.0);
    }
    if x >= axis[n - 1] {
        return (n - 2, 1.0);
    }
    let k = find_interval(axis, x);
    (k, (x - axis[k]) / (axis[k + 1] - axis[k]))
}

/// A point of the table's angular grid: along θa, θb and φd, the lower node and the weight of
/// the upper one ([`locate`]).
#[derive(Clone, Copy, Debug)]
struct GridPoint {
    i: (usize, f32),
    o: (usize, f32),
    p: (usize, f32),
}

/// Sampling grid resolution per θi node.
const SAMPLE_THETA: usize = 32;
const SAMPLE_PHI: usize = 32;

/// The tabulated BRDF: a [`TabulatedData`] ready for rendering (axes in radians, sampling
/// tables built).
#[derive(Clone, Debug, PartialEq)]
pub struct Tabulated {
    data: TabulatedData,
    ti: Vec<f32>,
    to: Vec<f32>,
    pd: Vec<f32>,
    /// Per θi node: the piecewise-constant distribution over (φ column, θ row) cells.
    node_dist: Vec<Distribution2D>,
}

impl Tabulated {
    /// Fraction of cosine-weighted sampling mixed in.
    pub const DEFENSIVE: f32 = 0.1;

    /// Builds the BRDF (negative entries clamped to 0).
    pub fn new(mut data: TabulatedData) -> Self {
        for v in &mut data.values {
            *v = v.max(0.0);
        }
        let ti: Vec<f32> = data.theta_i_deg.iter().map(|d| d.to_radians()).collect();
        let to: Vec<f32> = data.theta_o_deg.iter().map(|d| d.to_radians()).collect();
        let pd: Vec<f32> = data.phi_d_deg.iter().map(|d| d.to_radians()).collect();
        let mut t = Self {
            data,
            ti,
            to,
            pd,
            node_dist: vec![],
        };
        t.build_sampling();
        t
    }

    /// The table it plays back.
    pub fn data(&self) -> &TabulatedData {
        &self.data
    }

    fn build_sampling(&mut self) {
        let (nt, np) = (SAMPLE_THETA, SAMPLE_PHI);
        let nl = self.data.wavelengths_nm.len();
        for node in 0..self.ti.len() {
            let theta_i = self.ti[node];
            let mut cells = vec![0.0f32; nt * np];
            for r in 0..nt {
                let (t0, t1) = (
                    r as f32 * FRAC_PI_2 / nt as f32,
                    (r + 1) as f32 * FRAC_PI_2 / nt as f32,
                );
                let solid = (t0.cos() - t1.cos()) * (PI / np as f32);
                let tc = 0.5 * (t0 + t1);
                for c in 0..np {
                    let pc = (c as f32 + 0.5) * PI / np as f32;
                    let g = self.grid_points(theta_i, tc, pc);
                    let mut f = 0.0;
                    for l in 0..nl {
                        f += self.lookup_sym(&g, l);
                    }
                    cells[r * np + c] = (f / nl as f32 * tc.cos() * solid).max(0.0);
                }
            }
            if cells.iter().all(|&c| c <= 0.0) {
                // Black row: sample uniformly over cells (only the defensive part matters).
                cells.iter_mut().for_each(|c| *c = 1.0);
            }
            // Rows of the grid are θ rows, columns φ cells.
            self.node_dist.push(Distribution2D::new(&cells, np, nt));
        }
    }

    /// The cells and weights of (θ_a, θ_b, φd) on the table's angular axes.
    #[inline]
    fn grid_point(&self, ta: f32, tb: f32, phi: f32) -> GridPoint {
        GridPoint {
            i: locate(&self.ti, ta),
            o: locate(&self.to, tb),
            p: locate(&self.pd, phi),
        }
    }

    /// The grid points of both direction orders, (θa, θb, φd) and (θb, θa, φd): located once,
    /// read at every wavelength.
    #[inline]
    fn grid_points(&self, ta: f32, tb: f32, phi: f32) -> [GridPoint; 2] {
        [self.grid_point(ta, tb, phi), self.grid_point(tb, ta, phi)]
    }

    /// The table interpolated at grid point `g` for wavelength index `l`, one direction order.
    #[inline]
    fn lookup(&self, g: &GridPoint, l: usize) -> f32 {
        let ((i, wi), (o, wo), (p, wp)) = (g.i, g.o, g.p);
        let (ni, no, np) = (self.ti.len(), self.to.len(), self.pd.len());
        let mut acc = 0.0;
        for (di, fi) in [(0, 1.0 - wi), (1, wi)] {
            if fi == 0.0 || i + di >= ni {
                continue;
            }
            for (dob, fo) in [(0, 1.0 - wo), (1, wo)] {
                if fo == 0.0 || o + dob >= no {
                    continue;
                }
                for (dp, fp) in [(0, 1.0 - wp), (1, wp)] {
                    if fp == 0.0 || p + dp >= np {
                        continue;
                    }
                    acc += fi * fo * fp * self.data.values[self.data.index(i + di, o + dob, p + dp, l)];
                }
            }
        }
        acc
    }

    /// Reciprocal lookup: the mean of both direction orders.
    #[inline]
    fn lookup_sym(&self, g: &[GridPoint; 2], l: usize) -> f32 {
        0.5 * (self.lookup(&g[0], l) + self.lookup(&g[1], l))
    }

    #[inline]
    fn angles(wi: Vec3, wo: Vec3) -> (f32, f32, f32) {
        let ta = wi.z.clamp(-1.0, 1.0).acos();
        let tb = wo.z.clamp(-1.0, 1.0).acos();
        let mut phi = (wo.y.atan2(wo.x) - wi.y.atan2(wi.x)).abs();
        if phi > PI {
            phi = 2.0 * PI - phi;
        }
        (ta, tb, phi)
    }

    /// f at one wavelength (nm), linear in λ between the table's wavelengths.
    #[inline]
    fn eval_at(&self, g: &[GridPoint; 2], lambda: f32) -> f32 {
        let (l, wl) = locate(&self.data.wavelengths_nm, lambda);
        let a = self.lookup_sym(g, l);
        if wl == 0.0 || l + 1 >= self.data.wavelengths_nm.len() {
            return a;
        }
        (1.0 - wl) * a + wl * self.lookup_sym(g, l + 1)
    }

    /// The table part of the pdf for θi node `node`, per solid angle (including the ½ of the
    /// φ sign choice).
    #[inline]
    fn node_pdf(&self, node: usize, tb: f32, phi: f32) -> f32 {
        let r = ((tb / FRAC_PI_2 * SAMPLE_THETA as f32) as usize).min(SAMPLE_THETA - 1);
        let c = ((phi / PI * SAMPLE_PHI as f32) as usize).min(SAMPLE_PHI - 1);
        let p = self.node_dist[node].pmf(c, r);
        let (t0, t1) = (
            r as f32 * FRAC_PI_2 / SAMPLE_THETA as f32,
            (r + 1) as f32 * FRAC_PI_2 / SAMPLE_THETA as f32,
        );
        let solid = (t0.cos() - t1.cos()) * (PI / SAMPLE_PHI as f32);
        0.5 * p / solid
    }
}

impl Bsdf for Tabulated {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::GLOSSY_REFLECTION
    }

    fn eval(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, wl: &SampledWavelengths) -> SampledSpectrum {
        if !ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let (ta, tb, phi) = Self::angles(wi, wo);
        let g = self.grid_points(ta, tb, phi);
        SampledSpectrum::from_fn(|k| self.eval_at(&g, wl.lambda(k)))
    }

    fn pdf(&self, ctx: &BsdfContext, wi: Vec3, wo: Vec3, _wl: &SampledWavelengths) -> f32 {
        if !ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let (ta, tb, phi) = Self::angles(wi, wo);
        let (i, w) = locate(&self.ti, ta);
        let mut table = (1.0 - w) * self.node_pdf(i, tb, phi);
        if w > 0.0 && i + 1 < self.ti.len() {
            table += w * self.node_pdf(i + 1, tb, phi);
        }
        (1.0 - Self::DEFENSIVE) * table + Self::DEFENSIVE * square_to_cosine_hemisphere_pdf(wo)
    }

    fn sample(
        &self,
        ctx: &BsdfContext,
        wi: Vec3,
        u1: f32,
        u2: Vec2,
        wl: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if !ctx.is_enabled(BsdfFlags::GLOSSY_REFLECTION) || wi.z <= 0.0 {
            return None;
        }
        let wo = if u1 < Self::DEFENSIVE {
            square_to_cosine_hemisphere(u2)
        } else {
            let mut u = (u1 - Self::DEFENSIVE) / (1.0 - Self::DEFENSIVE);
            let (ta, _, _) = Self::angles(wi, Vec3::Z);
            let (i, w) = locate(&self.ti, ta);
            let node = if u < 1.0 - w || i + 1 >= self.ti.len() {
                u /= (1.0 - w).max(f32::MIN_POSITIVE);
                i
            } else {
                u = (u - (1.0 - w)) / w;
                i + 1
            };
            let sign = if u < 0.5 { 1.0 } else { -1.0 };
            // u2.x picks the θ row (the marginal), u2.y the φ cell within it.
            let ((c, r), _, t) = self.node_dist[node].sample_discrete(Vec2::new(u2.y, u2.x));
            let (tc, tr) = (t.x, t.y);
            // Uniform in solid angle inside the cell: linear in cos θ and in φ.
            let (t0, t1) = (
                r as f32 * FRAC_PI_2 / SAMPLE_THETA as f32,
                (r + 1) as f32 * FRAC_PI_2 / SAMPLE_THETA as f32,
            );
            let cos_t = t0.cos() + tr * (t1.cos() - t0.cos());
            let phi_d = (c as f32 + tc) * PI / SAMPLE_PHI as f32;
            let phi = wi.y.atan2(wi.x) + sign * phi_d;
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
        };
        if wo.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(ctx, wi, wo, wl);
        if pdf <= 0.0 {
            return None;
        }
        let f = self.eval(ctx, wi, wo, wl);
        // Returned even when black (see `Bsdf::sample`: mixtures need the direction).
        let weight = f * (wo.z / pdf);
        Some(BsdfSample {
            wo,
            weight,
            pdf,
            flags: BsdfFlags::GLOSSY_REFLECTION,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instruments::spherical_direction;

    /// A table of f = a + b·cos θi·cos θo·(1 + cos φd)/2 sampled on a grid.
    fn synthetic(a: f32, b: f32) -> TabulatedData {
        let ti: Vec<f32> = (0..10).map(|k| k as f32 * 10.0).collect();
        let to = ti.clone();
        let pd: Vec<f32> = (0..13).map(|k| k as f32 * 15.0).collect();
        let wl = vec![400.0, 700.0];
        let mut values = vec![];
        for &i in &ti {
            for &o in &to {
                for &p in &pd {
                    for &l in &wl {
                        let s = if l < 500.0 { 1.0 } else { 0.5 };
                        values.push(
                            s * (a + b
                                * i.to_radians().cos()
                                * o.to_radians().cos()
                                * (1.0 + p.to_radians().cos())
                                / 2.0),
                        );
                    }
                }
            }
        }
        TabulatedData::new(ti, to, pd, wl, values, None, "synthetic".into()).unwrap()
    }

    #[test]
    fn interpolates_grid_values_and_wavelengths() {
        let t = Tabulated::new(synthetic(0.1, 0.2));
        let ctx = BsdfContext::radiance();
        let wi = spherical_direction(20f32.to_radians(), 0.3);
        let wo = spherical_direction(40f32.to_radians(), 0.3 + 30f32.to_radians());
        let expect = 0.1
            + 0.2 * 20f32.to_radians().cos() * 40f32.to_radians().cos() * (1.0 + 30f32.to_radians().cos())
                / 2.0;
        let f = t.eval(&ctx, wi, wo, &SampledWavelengths::fixed(400.0));
        assert!((f[0] - expect).abs() < 1e-5, "{} vs {expect}", f[0]);
        let f = t.eval(&ctx, wi, wo, &SampledWavelengths::fixed(550.0));
        assert!(
            (f[0] - 0.75 * expect).abs() < 1e-5,
            "λ halfway between 400 (×1) and 700 (×0.5)"
        );
        assert_eq!(
            t.eval(&ctx, -wi, wo, &SampledWavelengths::fixed(400.0))[0],
            0.0,
            "one-sided"
        );
    }

    #[test]
    fn reciprocity_is_enforced_on_a_non_reciprocal_table() {
        let mut d = synthetic(0.1, 0.0);
        // Make the raw table asymmetric: f depends on θi only.
        for i in 0..d.theta_i_deg.len() {
            for o in 0..d.theta_o_deg.len() {
                for p in 0..d.phi_d_deg.len() {
                    for l in 0..2 {
                        let k = d.index(i, o, p, l);
                        d.values[k] = 0.1 + 0.01 * i as f32;
                    }
                }
            }
        }
        let t = Tabulated::new(d);
        let ctx = BsdfContext::radiance();
        let wl = SampledWavelengths::fixed(500.0);
        let a = spherical_direction(0.2, 0.1);
        let b = spherical_direction(1.1, 2.0);
        let fab = t.eval(&ctx, a, b, &wl)[0];
        let fba = t.eval(&ctx, b, a, &wl)[0];
        assert!((fab - fba).abs() < 1e-7, "{fab} vs {fba}");
    }

    #[test]
    fn sample_weight_matches_eval_over_pdf_and_pdf_integrates_to_one() {
        let t = Tabulated::new(synthetic(0.02, 0.5));
        let ctx = BsdfContext::radiance();
        let wi = spherical_direction(35f32.to_radians(), 1.0);
        let wl0 = SampledWavelengths::fixed(450.0);
        let mut rng = crate::rng::Pcg32::new(3, 0);
        for _ in 0..2000 {
            let mut wl = wl0;
            let s = t
                .sample(&ctx, wi, rng.next_f32(), rng.next_vec2(), &mut wl)
                .unwrap();
            let f = t.eval(&ctx, wi, s.wo, &wl0);
            let pdf = t.pdf(&ctx, wi, s.wo, &wl0);
            assert!((s.pdf - pdf).abs() <= 1e-4 * pdf);
            assert!((s.weight[0] - f[0] * s.wo.z / pdf).abs() <= 1e-4 * s.weight[0]);
        }
        // ∫ pdf dω over the hemisphere = 1 (midpoint rule in (cos θ, φ)).
        let n = 400;
        let mut sum = 0.0f64;
        for a in 0..n {
            let ct = (a as f32 + 0.5) / n as f32;
            for b in 0..n {
                let phi = (b as f32 + 0.5) / n as f32 * 2.0 * PI;
                let st = (1.0 - ct * ct).sqrt();
                let wo = Vec3::new(st * phi.cos(), st * phi.sin(), ct);
                sum += t.pdf(&ctx, wi, wo, &wl0) as f64;
            }
        }
        let integral = sum * (2.0 * PI as f64) / (n * n) as f64;
        assert!((integral - 1.0).abs() < 5e-3, "∫pdf = {integral}");
    }

    #[test]
    fn bad_tables_are_rejected_with_the_reason() {
        let e = TabulatedData::new(
            vec![0.0, 95.0],
            vec![0.0],
            vec![0.0],
            vec![550.0],
            vec![0.1; 2],
            None,
            String::new(),
        );
        assert!(e.unwrap_err().contains("theta_i"));
        let e = TabulatedData::new(
            vec![0.0],
            vec![0.0],
            vec![0.0, 0.0],
            vec![550.0],
            vec![0.1; 2],
            None,
            String::new(),
        );
        assert!(e.unwrap_err().contains("strictly increasing"));
        let e = TabulatedData::new(
            vec![0.0],
            vec![0.0],
            vec![0.0],
            vec![550.0],
            vec![0.1; 2],
            None,
            String::new(),
        );
        assert!(e.unwrap_err().contains("expected 1 values"));
    }
}
