//! The text format of a tabulated isotropic BRDF: what `gonio measure` writes and the
//! `tabulated` BSDF reads (`<bsdf type="tabulated"><string name="filename" value="t.txt"/>`).
//!
//! ```text
//! gonio-tabulated 1
//! # Lines starting with '#' and blank lines are ignored.
//! description measured by gonio's virtual gonioreflectometer: bsdf diffuse ...
//! theta_i 5 15 25 35 45 55 65 75 85        # source polar angles, degrees, increasing, in [0, 90]
//! theta_o 5 15 25 35 45 55 65 75 85        # detector polar angles, degrees, in [0, 90]
//! phi_d 0 10 20 ... 180                    # azimuth φo − φi, degrees, in [0, 180]
//! wavelengths 450 550 650                  # nm, increasing
//! errors yes                               # "yes": each row also holds standard errors
//! data
//! 5 5 0  0.19 0.19 0.19  0.002 0.002 0.002
//! 5 5 10 ...
//! ```
//!
//! After `data`, one row per grid point in the order θi (slowest), θo, φd (fastest): the three
//! angles (checked against the axes), then f at each wavelength (1/sr), then, with `errors yes`,
//! the standard error of each. Every value is a decimal number; a row may end in a `#` comment.
//! The header keywords may come in any order before `data`. Errors name the file, the line and
//! the value at fault.

use gonio_core::bsdfs::tabulated::TabulatedData;
use std::fmt::Write as _;
use std::path::Path;

/// A problem reading a table, located in its file.
#[derive(Debug, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct TableError {
    /// The file (or `<string>`).
    pub file: String,
    /// 1-based line number (0: the file as a whole).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// The format version this module writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// Parses a table from text; `file` names it in errors.
pub fn parse_tabulated(text: &str, file: &str) -> Result<TabulatedData, TableError> {
    let err = |line: usize, message: String| TableError {
        file: file.to_string(),
        line,
        message,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.split('#').next().unwrap_or("").trim()));
    let mut lines = lines.by_ref().filter(|(_, l)| !l.is_empty());
    let (n, first) = lines
        .next()
        .ok_or_else(|| err(0, "empty file: expected 'gonio-tabulated 1'".into()))?;
    let mut it = first.split_whitespace();
    if it.next() != Some("gonio-tabulated") {
        return Err(err(
            n,
            format!("expected 'gonio-tabulated {FORMAT_VERSION}', found '{first}'"),
        ));
    }
    match it.next().map(str::parse::<u32>) {
        Some(Ok(FORMAT_VERSION)) => {}
        other => {
            return Err(err(
                n,
                format!("unsupported format version {other:?} (this reader knows {FORMAT_VERSION})"),
            ));
        }
    }
    let num = |line: usize, s: &str, what: &str| -> Result<f32, TableError> {
        s.parse::<f32>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| err(line, format!("{what}: '{s}' is not a finite number")))
    };
    let (mut ti, mut to, mut pd, mut wl) = (None, None, None, None);
    let mut errors = None;
    let mut description = String::new();
    let mut data_line = None;
    for (n, l) in lines.by_ref() {
        let (key, rest) = l.split_once(char::is_whitespace).unwrap_or((l, ""));
        let list = |what: &str| -> Result<Vec<f32>, TableError> {
            let v = rest
                .split_whitespace()
                .map(|s| num(n, s, what))
                .collect::<Result<Vec<_>, _>>()?;
            if v.is_empty() {
                return Err(err(n, format!("{what}: no values")));
            }
            Ok(v)
        };
        match key {
            "description" => description = rest.trim().to_string(),
            "theta_i" => ti = Some(list("theta_i")?),
            "theta_o" => to = Some(list("theta_o")?),
            "phi_d" => pd = Some(list("phi_d")?),
            "wavelengths" => wl = Some(list("wavelengths")?),
            "errors" => {
                errors = Some(match rest.trim() {
                    "yes" => true,
                    "no" => false,
                    v => return Err(err(n, format!("errors: expected 'yes' or 'no', found '{v}'"))),
                })
            }
            "data" => {
                data_line = Some(n);
                break;
            }
            k => {
                return Err(err(
                    n,
                    format!(
                        "unknown keyword '{k}' (expected description, theta_i, theta_o, phi_d, wavelengths, errors, data)"
                    ),
                ));
            }
        }
    }
    let data_at = data_line.ok_or_else(|| err(0, "no 'data' line".into()))?;
    let missing = |k: &str| err(data_at, format!("'{k}' must be given before 'data'"));
    let ti = ti.ok_or_else(|| missing("theta_i"))?;
    let to = to.ok_or_else(|| missing("theta_o"))?;
    let pd = pd.ok_or_else(|| missing("phi_d"))?;
    let wl = wl.ok_or_else(|| missing("wavelengths"))?;
    let errors = errors.unwrap_or(false);
    let nl = wl.len();
    let per_row = 3 + nl * if errors { 2 } else { 1 };
    let rows = ti.len() * to.len() * pd.len();
    let mut values = Vec::with_capacity(rows * nl);
    let mut stderr = Vec::with_capacity(if errors { rows * nl } else { 0 });
    let mut last = data_at;
    for r in 0..rows {
        let (i, o, p) = (r / (to.len() * pd.len()), (r / pd.len()) % to.len(), r % pd.len());
        let (n, l) = lines.next().ok_or_else(|| {
            err(
                last,
                format!(
                    "table ends after {r} rows; {rows} expected (θi × θo × φd = {} × {} × {})",
                    ti.len(),
                    to.len(),
                    pd.len()
                ),
            )
        })?;
        last = n;
        let f: Vec<&str> = l.split_whitespace().collect();
        if f.len() != per_row {
            return Err(err(
                n,
                format!(
                    "expected {per_row} numbers (3 angles, {nl} values{}), found {}",
                    if errors { ", {nl} errors" } else { "" },
                    f.len()
                ),
            ));
        }
        for (k, (want, what)) in [(ti[i], "theta_i"), (to[o], "theta_o"), (pd[p], "phi_d")]
            .into_iter()
            .enumerate()
        {
            let got = num(n, f[k], what)?;
            if (got - want).abs() > 1e-3 * want.abs().max(1.0) {
                return Err(err(
                    n,
                    format!(
                        "{what} = {got}, but row {} of the grid has {what} = {want}",
                        r + 1
                    ),
                ));
            }
        }
        for s in &f[3..3 + nl] {
            values.push(num(n, s, "value")?);
        }
        if errors {
            for s in &f[3 + nl..] {
                stderr.push(num(n, s, "standard error")?);
            }
        }
    }
    if let Some((n, l)) = lines.next() {
        return Err(err(
            n,
            format!("extra row after the {rows} rows of the grid: '{l}'"),
        ));
    }
    TabulatedData::new(ti, to, pd, wl, values, errors.then_some(stderr), description)
        .map_err(|m| err(data_at, m))
}

/// Reads a table file.
pub fn read_tabulated(path: &Path) -> Result<TabulatedData, TableError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| TableError {
        file: file.clone(),
        line: 0,
        message: format!("cannot read: {e}"),
    })?;
    parse_tabulated(&text, &file)
}

/// The text of a table.
pub fn format_tabulated(t: &TabulatedData) -> String {
    let mut s = String::new();
    let axis = |v: &[f32]| v.iter().map(|x| format!("{x}")).collect::<Vec<_>>().join(" ");
    let _ = writeln!(s, "gonio-tabulated {FORMAT_VERSION}");
    let _ = writeln!(
        s,
        "# An isotropic BRDF table; format in docs/instruments.md. Angles in degrees, wavelengths in nm,"
    );
    let _ = writeln!(
        s,
        "# values f in 1/sr (without the cosine). Rows: theta_i theta_o phi_d, f per wavelength{}.",
        if t.stderr.is_some() {
            ", standard error per wavelength"
        } else {
            ""
        }
    );
    let _ = writeln!(
        s,
        "description {}",
        t.description.replace('\n', " ").replace('#', "no.")
    );
    let _ = writeln!(s, "theta_i {}", axis(&t.theta_i_deg));
    let _ = writeln!(s, "theta_o {}", axis(&t.theta_o_deg));
    let _ = writeln!(s, "phi_d {}", axis(&t.phi_d_deg));
    let _ = writeln!(s, "wavelengths {}", axis(&t.wavelengths_nm));
    let _ = writeln!(s, "errors {}", if t.stderr.is_some() { "yes" } else { "no" });
    let _ = writeln!(s, "data");
    let nl = t.wavelengths_nm.len();
    for (i, &a) in t.theta_i_deg.iter().enumerate() {
        for (o, &b) in t.theta_o_deg.iter().enumerate() {
            for (p, &c) in t.phi_d_deg.iter().enumerate() {
                let k = t.index(i, o, p, 0);
                let _ = write!(s, "{a} {b} {c}");
                for v in &t.values[k..k + nl] {
                    let _ = write!(s, " {v:e}");
                }
                if let Some(e) = &t.stderr {
                    for v in &e[k..k + nl] {
                        let _ = write!(s, " {v:e}");
                    }
                }
                s.push('\n');
            }
        }
    }
    s
}

/// Writes a table atomically ([`crate::output::write_atomically`]: a temporary file in the same
/// folder, then a rename).
pub fn write_tabulated(path: &Path, t: &TabulatedData) -> Result<(), TableError> {
    crate::output::write_atomically(path, format_tabulated(t).as_bytes()).map_err(|e| TableError {
        file: path.display().to_string(),
        line: 0,
        message: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> TabulatedData {
        let values: Vec<f32> = (0..2 * 2 * 3 * 2).map(|k| 0.1 + 0.01 * k as f32).collect();
        let stderr = values.iter().map(|v| v * 0.01).collect();
        TabulatedData::new(
            vec![10.0, 50.0],
            vec![20.0, 70.0],
            vec![0.0, 90.0, 180.0],
            vec![450.0, 650.0],
            values,
            Some(stderr),
            "test table".into(),
        )
        .unwrap()
    }

    #[test]
    fn round_trip_is_exact() {
        let t = table();
        let text = format_tabulated(&t);
        let back = parse_tabulated(&text, "t.txt").unwrap();
        assert_eq!(back, t);
    }

    #[test]
    fn errors_name_the_line_and_the_value() {
        let text = format_tabulated(&table());
        let bad = text.replace("10 20 90 ", "10 20 95 ");
        let e = parse_tabulated(&bad, "t.txt").unwrap_err().to_string();
        assert!(e.starts_with("t.txt:12:") && e.contains("phi_d = 95"), "{e}");
        let bad = text.replacen("1.1e-1", "x1", 1);
        let e = parse_tabulated(&bad, "t.txt").unwrap_err().to_string();
        assert!(e.contains("'x1' is not a finite number"), "{e}");
        let short: String = text.lines().take(14).map(|l| format!("{l}\n")).collect();
        let e = parse_tabulated(&short, "t.txt").unwrap_err().to_string();
        assert!(e.contains("table ends after 4 rows; 12 expected"), "{e}");
        let e = parse_tabulated("gonio-tabulated 2\n", "t.txt")
            .unwrap_err()
            .to_string();
        assert!(e.contains("t.txt:1: unsupported format version"), "{e}");
        let e = parse_tabulated(&text.replace("theta_o 20 70", "theta_o 70 20"), "t.txt")
            .unwrap_err()
            .to_string();
        assert!(e.contains("theta_o"), "{e}");
    }
}
