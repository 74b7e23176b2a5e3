//! `volume`: a `<volume>` (e.g. `gridvolume`) evaluated at the surface point (Mitsuba 3
//! `src/textures/volume.cpp`; runtime in [`crate::texture::volume`] and [`crate::texture::hit`]).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::Texture;
use crate::texture::volume::Volume;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

const VOLUME: ParamSpec = ParamSpec::new(
    "volume",
    ParamType::Volume,
    DefaultValue::None,
    "the nested or referenced `<volume>` evaluated at the hit's world position (required)",
);

/// The `volume` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "volume",
    summary: "A `<volume>` (`gridvolume`, `constvolume`) evaluated at the surface point, in world space.",
    params: &[VOLUME],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let volumes = p.objects(Tag::Volume)?;
    let (idx, prop) = match volumes.as_slice() {
        [] => {
            return Err(err(
                &p.obj.loc,
                ErrorKind::Grammar,
                "<texture type=\"volume\"> needs a nested <volume>",
            ));
        }
        [(i, prop)] => (*i, *prop),
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "more than one <volume> in a <texture type=\"volume\">",
            ));
        }
    };
    match b.build_plugin(crate::plugins::VOLUME_PLUGINS, idx)? {
        Volume::Grid(grid) if grid.channels == 6 => Err(err(
            &prop.loc,
            ErrorKind::BadValue,
            "the volume of a <texture type=\"volume\"> has 6 channels (the matrix of an sggx phase function; a texture reads 1 or 3)",
        )),
        Volume::Grid(grid) => {
            b.note_hit_texture(None, &prop.value_loc);
            Ok(Texture::Volume(grid))
        }
        // The same value at every point.
        Volume::Constant(s, _) => Ok(Texture::Spectrum(s)),
    }
}
