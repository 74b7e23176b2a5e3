//! `homogeneous`: a participating medium with the same extinction everywhere (Mitsuba 3
//! `src/media/homogeneous.cpp`; runtime [`crate::medium::Medium`]).
//!
//! σt(λ) = `scale`·`sigma_t`(λ), σs = α·σt, σa = (1 − α)·σt; the phase function is the nested
//! `<phase>` (isotropic without one). `sigma_t` is a spectrum: an `<rgb>` with components up to 1
//! is uplifted as Mitsuba does (as a reflectance: the extinction's spectral shape, and so the
//! transmittance through a chromatic medium, then equals Mitsuba's), a brighter one (which
//! Mitsuba refuses) as an unbounded colour. `albedo` is a reflectance-like spectrum or a
//! `<volume>` read where light scatters (a colour grid as Mitsuba reads it, clamped to [0, 1]
//! per wavelength: Mitsuba's saturated colours exceed 1 there, which `--mitsuba-estimators`
//! keeps).
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `sigma_t` | 1 | extinction coefficient (1/length), before `scale` |
//! | `albedo` | 0.75 | single-scattering albedo σs/σt in [0, 1]: a spectrum or a `<volume>` |
//! | `scale` | 1 | multiplier of σt (a change of length unit) |
//! | `sample_emitters` | true | next-event estimation at scattering events in the medium |
//! | `has_spectral_extinction` | true | accepted: gonio samples distances with spectral MIS, exact for any σt |
//! | (nested phase) | isotropic | the phase function |

use crate::medium::{Albedo, Extinction, Medium, Phase};
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::texture::volume::Volume;
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, Value, err};
use gonio_core::phase::PhaseFunction;
use gonio_core::spectra::RgbKind;

pub(crate) const SIGMA_T: ParamSpec = ParamSpec::new(
    "sigma_t",
    ParamType::Spectrum,
    DefaultValue::Float(1.0),
    "extinction coefficient (1/length), before `scale`",
);
pub(crate) const ALBEDO: ParamSpec = ParamSpec::new(
    "albedo",
    ParamType::Texture,
    DefaultValue::Float(0.75),
    "single-scattering albedo σs/σt in [0, 1]: a spectrum, or a nested or referenced `<volume>`",
);
pub(crate) const SCALE: ParamSpec = ParamSpec::new(
    "scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "multiplier of σt",
);
pub(crate) const SAMPLE_EMITTERS: ParamSpec = ParamSpec::new(
    "sample_emitters",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "next-event estimation at scattering events in the medium",
);
pub(crate) const SPECTRAL_EXTINCTION: ParamSpec = ParamSpec::new(
    "has_spectral_extinction",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "accepted: gonio samples distances with spectral MIS over the sample's wavelengths, exact for any σt",
);
pub(crate) const PHASE: ParamSpec = ParamSpec::new(
    "(nested phase)",
    ParamType::Phase,
    DefaultValue::Str("isotropic"),
    "the phase function",
);

/// The `homogeneous` plugin.
pub static PLUGIN: Plugin<Medium> = Plugin {
    name: "homogeneous",
    summary: "A participating medium of constant extinction, with an albedo and a phase function.",
    params: &[
        SIGMA_T,
        ALBEDO,
        SCALE,
        SAMPLE_EMITTERS,
        SPECTRAL_EXTINCTION,
        PHASE,
    ],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Medium, SceneError> {
    build_medium(b, p, false)
}

/// `homogeneous` and `heterogeneous` (which also takes a `<volume>` as `sigma_t`).
pub(crate) fn build_medium<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
    grids: bool,
) -> Result<Medium, SceneError> {
    let (mut sigma_t, mut albedo) = (None, None);
    for (i, prop) in p.objects(Tag::Volume)? {
        let what = p.what();
        let refused = |why: &str| {
            err(
                &prop.loc,
                ErrorKind::UnusedParameter,
                format!("a <volume> named \"{}\" in {what} ({why})", prop.name),
            )
        };
        let grids_here = if grids {
            "\"sigma_t\" and \"albedo\" may be volumes"
        } else {
            "only \"albedo\" may be a grid; a grid of sigma_t is the heterogeneous medium"
        };
        if prop.name != "albedo" && prop.name != SIGMA_T.name {
            return Err(refused(grids_here));
        }
        let volume = b.build_plugin(crate::plugins::VOLUME_PLUGINS, i)?;
        if let Volume::Grid(g) = &volume
            && g.channels == 6
        {
            return Err(err(
                &prop.loc,
                ErrorKind::BadValue,
                format!(
                    "the \"{}\" volume of {what} has 6 channels (the matrix of an sggx phase function; give 1 or 3)",
                    prop.name
                ),
            ));
        }
        match (prop.name.as_str(), volume) {
            ("albedo", Volume::Grid(g)) => {
                albedo = Some(Albedo::Volume {
                    grid: g,
                    unclamped: p.doc.mitsuba_estimators,
                })
            }
            ("albedo", Volume::Constant(a, _)) => {
                if a.max_value() > 1.0 {
                    return Err(err(
                        &prop.loc,
                        ErrorKind::BadValue,
                        format!(
                            "invalid albedo of {what}: a constvolume reaching {} (an albedo lies in [0, 1])",
                            a.max_value()
                        ),
                    ));
                }
                albedo = Some(Albedo::Spectrum(a));
            }
            // A heterogeneous medium exists inside its extinction's box (Mitsuba's
            // `intersect_aabb`), for a constant the bounds of its `to_world`'s unit cube.
            (_, Volume::Constant(s, to_world)) if grids => {
                let Some(to_local) = crate::medium::unit_cube_bounds(&to_world) else {
                    return Err(err(
                        &prop.loc,
                        ErrorKind::BadValue,
                        format!(
                            "the \"sigma_t\" constvolume of {what} has a flat or non-finite box (its to_world)"
                        ),
                    ));
                };
                sigma_t = Some(Extinction::Box(s, to_local));
            }
            (_, Volume::Constant(s, _)) => sigma_t = Some(Extinction::Spectrum(s)),
            (_, Volume::Grid(g)) if grids => sigma_t = Some(Extinction::Volume(g)),
            (_, Volume::Grid(_)) => return Err(refused(grids_here)),
        }
    }
    let sigma_t = match sigma_t {
        Some(s) => s,
        None => {
            // Mitsuba uplifts an `<rgb>` extinction as it does a reflectance (it refuses
            // components above 1): the same spectrum here; larger colours are uplifted as
            // unbounded ones.
            let kind = match p
                .obj
                .props
                .iter()
                .find(|x| x.name == SIGMA_T.name)
                .map(|x| &x.value)
            {
                Some(Value::Rgb(c)) if c.iter().all(|&v| v <= 1.0) => RgbKind::Albedo,
                _ => RgbKind::Unbounded,
            };
            let value = b.spectrum_param(p, SIGMA_T.name, kind, SIGMA_T.default.float() as f32)?;
            if grids {
                // Mitsuba's number is a `constvolume` over the unit cube.
                Extinction::Box(value, glam::Affine3A::IDENTITY)
            } else {
                Extinction::Spectrum(value)
            }
        }
    };
    let albedo = match albedo {
        Some(a) => a,
        None => Albedo::Spectrum(b.spectrum_param(
            p,
            ALBEDO.name,
            RgbKind::Albedo,
            ALBEDO.default.float() as f32,
        )?),
    };
    let scale = p.float_checked(SCALE.name, SCALE.default.float(), |v| v >= 0.0, "non-negative")?;
    let sample_emitters = p.bool(SAMPLE_EMITTERS.name, SAMPLE_EMITTERS.default.bool())?;
    p.bool(SPECTRAL_EXTINCTION.name, SPECTRAL_EXTINCTION.default.bool())?;
    let phase = match p.objects(Tag::Phase)?.as_slice() {
        [] => Phase::Model(PhaseFunction::Isotropic),
        [(i, _)] => b.build_plugin(crate::plugins::PHASE_PLUGINS, *i)?,
        [_, (_, extra), ..] => {
            return Err(err(
                &extra.loc,
                ErrorKind::Grammar,
                "more than one <phase> in a medium",
            ));
        }
    };
    p.finish()?;
    let medium = Medium::new(sigma_t, albedo, scale as f32, phase, sample_emitters);
    // σt × scale must stay finite in single precision (a free flight of length 0 forever, or
    // tracking that never advances, otherwise).
    let bound = medium.majorant();
    if !bound.is_finite() {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            format!(
                "the extinction of {} overflows single precision (sigma_t times scale {scale:e})",
                p.what()
            ),
        ));
    }
    Ok(medium)
}
