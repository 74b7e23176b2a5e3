//! `<film>` plugins (nested in a sensor).

pub mod hdrfilm;
