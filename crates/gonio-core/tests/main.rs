//! The integration tests of `gonio-core`, one module per file beside this one, linked into one test
//! binary: a binary per file cost a link of the whole renderer each, the larger part of a
//! clean `cargo test --release` on two cores. Add a test file by adding its `mod` line here
//! (`autotests = false` in Cargo.toml: a file not listed is not compiled).
//! Run one file's tests with `cargo test --release -p gonio-core --test integration <file>::`.

mod battery;
mod battery_broken;
mod battery_hair;
mod battery_support;
mod hair_mitsuba;
mod instruments_gonio;
mod lambertsphere;
mod lanes;
mod marginal2d_mitsuba;
mod proptest_health;
mod spectral;
