//! Tabulated optical data compiled into the library (each file cites its source).
#![allow(
    clippy::excessive_precision,
    clippy::unreadable_literal,
    clippy::approx_constant
)]

pub mod cie1931;
pub mod d65;
pub mod metals;
pub mod metals_luxpop;
