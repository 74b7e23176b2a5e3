//! `<volume>` plugins (Mitsuba 3 `src/volumes/`): data over space, read by the `volume` texture
//! and as a `homogeneous` medium's albedo. The runtime grid is [`crate::texture::volume`].

pub mod gridvolume;
