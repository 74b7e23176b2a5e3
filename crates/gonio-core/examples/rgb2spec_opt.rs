//! Generates the sRGB → spectrum coefficient table (Jakob & Hanika 2019) that gonio-core embeds.
//!
//! ```text
//! cargo run -p gonio-core --release --example rgb2spec_opt -- [RES] [OUT] [THREADS]
//! ```
//!
//! Defaults: RES = 64 (`gonio_core::rgb2spec::TABLE_RES`), OUT =
//! `crates/gonio-core/data/rgb2spec_srgb.bin` (relative to the workspace root), THREADS = the
//! available parallelism. The fit itself is `gonio_core::rgb2spec::optimize_row` (Gauss–Newton in
//! CIELAB with continuation along z, 1 nm CIE 1931 and D65 quadrature; see that module's docs);
//! rows are independent and are shared between plain `std` threads. After regenerating, run
//! `cargo test -p gonio-core --release rgb2spec` (a test re-fits some rows and compares them with
//! the embedded table). A full run at res 64 takes about a minute on two cores.

use gonio_core::rgb2spec::{RgbToSpectrumTable, TABLE_RES, optimize_row, store_row};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

fn main() {
    if let Err(e) = run() {
        eprintln!("rgb2spec_opt: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let res: usize = match args.first() {
        Some(s) => s
            .parse()
            .map_err(|_| format!("RES \"{s}\" is not a positive integer"))?,
        None => TABLE_RES,
    };
    if !(2..=256).contains(&res) {
        return Err(format!("RES {res} out of range 2..=256"));
    }
    let out = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/data/rgb2spec_srgb.bin").to_string());
    let threads: usize = match args.get(2) {
        Some(s) => s
            .parse()
            .map_err(|_| format!("THREADS \"{s}\" is not a positive integer"))?,
        None => std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1),
    }
    .max(1);

    let start = Instant::now();
    let n_rows = 3 * res * res;
    let next = AtomicUsize::new(0);
    // Each worker fits rows (l, j, i) taken from a shared counter and returns them.
    let rows: Vec<(usize, Vec<[f32; 3]>)> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let r = next.fetch_add(1, Ordering::Relaxed);
                        if r >= n_rows {
                            break done;
                        }
                        let (l, j, i) = (r / (res * res), (r / res) % res, r % res);
                        done.push((r, optimize_row(res, l, j, i)));
                        if r % (res * res) == res * res - 1 {
                            eprintln!(
                                "rgb2spec_opt: component {l} done, {:.1} s",
                                start.elapsed().as_secs_f64()
                            );
                        }
                    }
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("worker thread panicked"))
            .collect()
    });

    let mut coeffs = vec![0.0f32; 3 * res * res * res * 3];
    for (r, row) in &rows {
        let (l, j, i) = (r / (res * res), (r / res) % res, r % res);
        store_row(&mut coeffs, res, l, j, i, row);
    }
    let table = RgbToSpectrumTable::from_parts(res, coeffs)?;
    std::fs::write(&out, table.to_bytes()).map_err(|e| format!("writing {out}: {e}"))?;
    eprintln!(
        "rgb2spec_opt: wrote {out} (res {res}) in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
