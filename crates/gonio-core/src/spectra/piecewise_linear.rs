//! Piecewise-linear spectra: (λ, value) samples joined by straight lines (Mitsuba's `irregular`
//! spectrum, `<spectrum value="400:0.1, 500:0.3"/>` and `.spd` files; pbrt's `PiecewiseLinear`
//! and named tables; measured η and k). The value at λ is the lerp on the interval holding it,
//! found from a per-nanometre index; outside the table 0 or the end values ([`Extrapolation`]).

use crate::math::{find_interval, floor};
use crate::spectrum::{LAMBDA_MAX, LAMBDA_MIN};

/// What a piecewise-linear table returns outside its wavelength range.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extrapolation {
    /// 0 outside the table (Mitsuba `irregular`, pbrt `PiecewiseLinear`).
    Zero,
    /// The end values continue (measured η/k data: zero η and k would give NaN Fresnel).
    Clamp,
}

/// A spectrum given as (λ, value) samples with linear interpolation.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear {
    lambda: Vec<f32>,
    value: Vec<f32>,
    extrapolation: Extrapolation,
    /// For each whole nanometre from ⌊λ₀⌋ on, the interval [`find_interval`] gives there: where
    /// [`PiecewiseLinear::eval`]'s forward scan starts (empty for tables wider than
    /// [`BUCKET_SPAN_MAX`] nm, which search).
    bucket_start: Vec<u32>,
}

/// Widest table (nm) that gets a per-nanometre index.
const BUCKET_SPAN_MAX: f32 = 8192.0;

/// The per-nanometre starts of `lambda`'s intervals (see [`PiecewiseLinear::bucket_start`]).
fn bucket_starts(lambda: &[f32]) -> Vec<u32> {
    let (lo, hi) = (lambda[0].floor(), lambda[lambda.len() - 1]);
    if lambda.len() < 3 || !(hi - lo <= BUCKET_SPAN_MAX) {
        return Vec::new();
    }
    (0..=(hi - lo) as u32)
        .map(|b| find_interval(lambda, lo + b as f32) as u32)
        .collect()
}

/// Appends the sample written as `(l, v)` to a table being parsed: both numbers, finite, λ above
/// the last one; `bad` words the error about the entry.
fn push_parsed(
    lambda: &mut Vec<f32>,
    value: &mut Vec<f32>,
    (l, v): (&str, &str),
    bad: impl Fn(&str) -> String,
) -> Result<(), String> {
    let l: f32 = l.trim().parse().map_err(|_| bad("wavelength is not a number"))?;
    let v: f32 = v.trim().parse().map_err(|_| bad("value is not a number"))?;
    if !l.is_finite() || !v.is_finite() {
        return Err(bad("non-finite number"));
    }
    if let Some(&prev) = lambda.last()
        && l <= prev
    {
        return Err(bad(&format!(
            "wavelength {l} does not increase (previous {prev})"
        )));
    }
    lambda.push(l);
    value.push(v);
    Ok(())
}

impl PiecewiseLinear {
    /// From samples; `lambda` must be strictly increasing, both the same length ≥ 1.
    /// Returns `None` otherwise (the scene reader turns that into an error naming the value).
    pub fn new(lambda: Vec<f32>, value: Vec<f32>, extrapolation: Extrapolation) -> Option<Self> {
        let ok = !lambda.is_empty()
            && lambda.len() == value.len()
            && lambda.windows(2).all(|w| w[0] < w[1])
            && lambda.iter().chain(&value).all(|x| x.is_finite());
        ok.then(|| Self::from_checked(lambda, value, extrapolation))
    }

    /// The table of samples its constructor has checked (at least one, λ strictly increasing,
    /// all finite), with its per-nanometre index.
    fn from_checked(lambda: Vec<f32>, value: Vec<f32>, extrapolation: Extrapolation) -> Self {
        Self {
            bucket_start: bucket_starts(&lambda),
            lambda,
            value,
            extrapolation,
        }
    }

    /// From interleaved `[λ₀, v₀, λ₁, v₁, ...]` static data.
    pub fn from_interleaved(data: &[f32], extrapolation: Extrapolation) -> Option<Self> {
        if !data.len().is_multiple_of(2) {
            return None;
        }
        let lambda = data.iter().step_by(2).copied().collect();
        let value = data.iter().skip(1).step_by(2).copied().collect();
        Self::new(lambda, value, extrapolation)
    }

    /// Parses a Mitsuba `.spd` file: one "λ value" pair per line (whitespace or a comma between
    /// them), `#` starts a comment, blank lines are skipped; λ must increase strictly. The error
    /// names the offending line (1-based) and its text.
    pub fn parse_spd(text: &str, extrapolation: Extrapolation) -> Result<PiecewiseLinear, String> {
        let (mut lambda, mut value) = (Vec::new(), Vec::new());
        for (n, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|f| !f.is_empty())
                .collect();
            let bad = |why: &str| format!("spectrum file line {}: {why}: \"{}\"", n + 1, raw.trim());
            if fields.len() != 2 {
                return Err(bad("expected two numbers \"wavelength value\""));
            }
            push_parsed(&mut lambda, &mut value, (fields[0], fields[1]), bad)?;
        }
        if lambda.is_empty() {
            return Err("spectrum file holds no \"wavelength value\" lines".into());
        }
        Ok(Self::from_checked(lambda, value, extrapolation))
    }

    /// Parses Mitsuba's inline form `"400:0.1, 500:0.3"` (λ in nm; pairs separated by commas;
    /// 0 outside the range, as Mitsuba's `irregular` spectrum). The error names the bad token.
    pub fn parse_pairs(text: &str) -> Result<PiecewiseLinear, String> {
        let (mut lambda, mut value) = (Vec::new(), Vec::new());
        for token in text.split(',').map(str::trim) {
            if token.is_empty() {
                return Err(format!(
                    "spectrum \"{text}\": empty entry (expected \"wavelength:value\")"
                ));
            }
            let bad = |why: &str| format!("spectrum entry \"{token}\": {why}");
            let pair = token
                .split_once(':')
                .ok_or_else(|| bad("expected \"wavelength:value\""))?;
            push_parsed(&mut lambda, &mut value, pair, bad)?;
        }
        Ok(Self::from_checked(lambda, value, Extrapolation::Zero))
    }

    /// The same table with another extrapolation rule.
    pub fn with_extrapolation(mut self, extrapolation: Extrapolation) -> Self {
        self.extrapolation = extrapolation;
        self
    }

    /// The same table with every value times `k` (the products must stay finite).
    pub fn scaled(&self, k: f32) -> Option<Self> {
        Self::new(
            self.lambda.clone(),
            self.value.iter().map(|v| v * k).collect(),
            self.extrapolation,
        )
    }

    /// The extrapolation rule.
    pub fn extrapolation(&self) -> Extrapolation {
        self.extrapolation
    }

    /// Value at `lambda` (nm).
    pub fn eval(&self, lambda: f32) -> f32 {
        let (l, v) = (&self.lambda, &self.value);
        let n = l.len();
        if lambda < l[0] || lambda > l[n - 1] {
            return match self.extrapolation {
                Extrapolation::Zero => 0.0,
                Extrapolation::Clamp => {
                    if lambda < l[0] {
                        v[0]
                    } else {
                        v[n - 1]
                    }
                }
            };
        }
        if n == 1 {
            return v[0];
        }
        // Index of the last sample ≤ lambda, kept inside [0, n − 2]: `find_interval`'s, from
        // the bucket of ⌊λ⌋ on (whose start is at most the answer) when the table has buckets.
        let i = match self.bucket_start.get((lambda - floor(l[0])) as usize) {
            Some(&start) => {
                let mut i = start as usize;
                while i + 2 < n && l[i + 1] <= lambda {
                    i += 1;
                }
                i
            }
            None => find_interval(l, lambda),
        };
        let t = (lambda - l[i]) / (l[i + 1] - l[i]);
        v[i] + t * (v[i + 1] - v[i])
    }

    /// Largest sample value.
    pub fn max_value(&self) -> f32 {
        self.value.iter().copied().fold(f32::MIN, f32::max)
    }

    /// Mean over the sampled range: the trapezoid integral between the first and last
    /// wavelength divided by that range (Mitsuba's `mean()` of its `regular` and `irregular`
    /// spectra); the one value of a single sample.
    pub fn mean(&self) -> f32 {
        let (l, v) = (&self.lambda, &self.value);
        let n = l.len();
        if n == 1 {
            return v[0];
        }
        let mut integral = 0.0f64;
        for i in 0..n - 1 {
            integral += 0.5 * (v[i] + v[i + 1]) as f64 * (l[i + 1] - l[i]) as f64;
        }
        (integral / (l[n - 1] - l[0]) as f64) as f32
    }

    /// The sample wavelengths, nm.
    pub fn lambdas(&self) -> &[f32] {
        &self.lambda
    }
    /// The sample values.
    pub fn values(&self) -> &[f32] {
        &self.value
    }

    /// The common value if the table is the same at every λ of the visible range.
    pub(super) fn constant_value(&self) -> Option<f32> {
        let v0 = self.value[0];
        if !self.value.iter().all(|&v| v == v0) {
            return None;
        }
        let covers = self.lambda[0] <= LAMBDA_MIN && *self.lambda.last()? >= LAMBDA_MAX;
        (self.extrapolation == Extrapolation::Clamp || covers).then_some(v0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn piecewise_linear_interpolates_and_extrapolates() {
        let p = PiecewiseLinear::new(
            vec![400.0, 500.0, 600.0],
            vec![0.1, 0.3, 0.2],
            Extrapolation::Zero,
        )
        .unwrap();
        assert_eq!(p.eval(400.0), 0.1);
        assert!((p.eval(450.0) - 0.2).abs() < 1e-6);
        assert!((p.eval(550.0) - 0.25).abs() < 1e-6);
        assert_eq!(p.eval(600.0), 0.2);
        assert_eq!(p.eval(399.0), 0.0);
        assert_eq!(p.eval(601.0), 0.0);
        let c = PiecewiseLinear {
            extrapolation: Extrapolation::Clamp,
            ..p
        };
        assert_eq!(c.eval(300.0), 0.1);
        assert_eq!(c.eval(700.0), 0.2);
    }

    #[test]
    fn piecewise_linear_buckets_find_the_searched_interval() {
        // Irregular knots, some closer than a nanometre, some wider apart; every 1/64 nm and
        // the knots themselves: the value of the bucketed scan is the binary search's, bit for bit.
        let lambda: Vec<f32> = vec![
            300.0, 300.3, 300.31, 301.0, 355.5, 410.0, 410.25, 410.5, 411.75, 500.0, 650.0, 829.9, 830.0,
            1200.5,
        ];
        let value: Vec<f32> = (0..lambda.len()).map(|i| (i as f32 * 0.37).sin() + 1.5).collect();
        let p = PiecewiseLinear::new(lambda.clone(), value.clone(), Extrapolation::Clamp).unwrap();
        assert!(!p.bucket_start.is_empty());
        let searched = |x: f32| {
            let i = find_interval(&lambda, x);
            let t = (x - lambda[i]) / (lambda[i + 1] - lambda[i]);
            value[i] + t * (value[i + 1] - value[i])
        };
        let xs = (0..=64 * 900 + 32)
            .map(|k| 300.0 + k as f32 / 64.0)
            .chain(lambda.iter().copied());
        for x in xs {
            assert_eq!(p.eval(x).to_bits(), searched(x).to_bits(), "λ = {x}");
        }
    }

    #[test]
    fn piecewise_linear_rejects_bad_tables() {
        assert!(PiecewiseLinear::new(vec![500.0, 400.0], vec![1.0, 2.0], Extrapolation::Zero).is_none());
        assert!(PiecewiseLinear::new(vec![], vec![], Extrapolation::Zero).is_none());
        assert!(PiecewiseLinear::new(vec![400.0], vec![f32::NAN], Extrapolation::Zero).is_none());
        assert!(PiecewiseLinear::from_interleaved(&[400.0, 1.0, 500.0], Extrapolation::Zero).is_none());
    }

    #[test]
    fn parse_spd_reads_mitsuba_files_and_names_bad_lines() {
        let text = "# data from www.luxpop.com database\n# ;    Lambda (A)   n   k\n\n\
                    300.194000 0.980000\n307.643005\t1.020000   # trailing comment\n316.276001, 1.06\n";
        let p = PiecewiseLinear::parse_spd(text, Extrapolation::Clamp).unwrap();
        assert_eq!(p.lambdas(), &[300.194, 307.643, 316.276]);
        assert_eq!(p.values(), &[0.98, 1.02, 1.06]);
        assert_eq!(p.eval(100.0), 0.98);
        let e = PiecewiseLinear::parse_spd("400 1\n500 x\n", Extrapolation::Zero).unwrap_err();
        assert!(e.contains("line 2") && e.contains("500 x"), "{e}");
        let e = PiecewiseLinear::parse_spd("400 1\n\n390 2\n", Extrapolation::Zero).unwrap_err();
        assert!(e.contains("line 3") && e.contains("does not increase"), "{e}");
        let e = PiecewiseLinear::parse_spd("400 1 2\n", Extrapolation::Zero).unwrap_err();
        assert!(e.contains("line 1"), "{e}");
        assert!(PiecewiseLinear::parse_spd("# nothing\n", Extrapolation::Zero).is_err());
        assert!(PiecewiseLinear::parse_spd("400 inf\n", Extrapolation::Zero).is_err());
    }

    #[test]
    fn parse_pairs_reads_the_inline_form_and_names_bad_tokens() {
        let p = PiecewiseLinear::parse_pairs("400:0.1, 500:0.3,600 : 0.2").unwrap();
        assert_eq!(p.lambdas(), &[400.0, 500.0, 600.0]);
        assert_eq!(p.values(), &[0.1, 0.3, 0.2]);
        assert_eq!(p.eval(700.0), 0.0);
        let e = PiecewiseLinear::parse_pairs("400:0.1, 500-0.3").unwrap_err();
        assert!(e.contains("\"500-0.3\""), "{e}");
        let e = PiecewiseLinear::parse_pairs("400:0.1, 5x0:0.3").unwrap_err();
        assert!(e.contains("\"5x0:0.3\""), "{e}");
        let e = PiecewiseLinear::parse_pairs("500:0.1, 400:0.3").unwrap_err();
        assert!(
            e.contains("\"400:0.3\"") && e.contains("does not increase"),
            "{e}"
        );
        assert!(PiecewiseLinear::parse_pairs("400:0.1,,500:1").is_err());
        assert!(PiecewiseLinear::parse_pairs("").is_err());
    }
}
