//! The integration tests of `gonio`, one module per file beside this one, linked into one test
//! binary: a binary per file cost a link of the whole renderer each, the larger part of a
//! clean `cargo test --release` on two cores. Add a test file by adding its `mod` line here
//! (`autotests = false` in Cargo.toml: a file not listed is not compiled).
//! Run one file's tests with `cargo test --release -p gonio --test integration <file>::`.

mod bsdf_cli;
mod compare;
mod fuzz_replay;
mod instruments_cli;
mod instruments_relight;
mod render_cli;
mod tabulated_roundtrip;
