//! `<volume>` plugins (Mitsuba 3 `src/volumes/`): data over space, read by the `volume` texture,
//! as a medium's albedo or extinction and as a `blendphase` weight. The runtime grid is
//! [`crate::texture::volume`]; a built volume is a [`crate::texture::volume::Volume`].

pub mod constvolume;
pub mod gridvolume;
