//! `<volume>` plugins (Mitsuba 3 `src/volumes/`): data over space, read by the `volume` texture
//! (participating media remain unsupported). The runtime grid is [`crate::texture::volume`].

pub mod gridvolume;
