//! `<medium>` plugins (Mitsuba 3 `src/media/`): participating media, referenced by shapes
//! (`interior`, `exterior`) and sensors. The runtime media are in [`crate::medium`].

pub mod heterogeneous;
pub mod homogeneous;
