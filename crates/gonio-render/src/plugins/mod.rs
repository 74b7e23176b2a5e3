//! Every plugin the scene reader knows, one file per plugin, grouped by kind (the XML tag).
//!
//! A plugin file holds the plugin's **parameter table** ([`ParamSpec`] rows: Mitsuba 3's names,
//! types, defaults and meaning, "(ours)" where gonio adds one), from which the reader takes every
//! default, the "unused parameter" error its list of accepted names and `docs/plugins.md` its
//! text, and its **builder** from parsed parameters to the scene description. Each kind has a
//! registry below; the reader's "unknown plugin (supported: ...)" error lists it. Parts that
//! several plugins of a kind share (a shape's `to_world`, `flip_normals`, nested BSDF and area
//! emitter, mesh loading and its cache; a sampler's `sample_count` and `seed`) live in the kind's
//! `mod.rs`. The BSDF plugins live with their materials in [`crate::material`].

pub mod emitter;
pub mod film;
pub mod integrator;
pub mod medium;
pub mod phase;
pub mod rfilter;
pub mod sampler;
pub mod sensor;
pub mod shape;
pub mod spectrum;
pub mod texture;
pub mod volume;

pub use crate::material::BSDF_PLUGINS;
pub use crate::xml::{DefaultValue, ParamSpec, ParamType, Plugin};

use crate::scene::{
    AreaEmitterDesc, EmitterDesc, FilmDesc, FilterDesc, IntegratorDesc, SamplerDesc, SensorDesc, ShapeDesc,
};
use crate::texture::Texture;

/// `<integrator>` plugins.
pub static INTEGRATOR_PLUGINS: &[&Plugin<IntegratorDesc>] = &[
    &integrator::path::PLUGIN,
    &integrator::direct::PLUGIN,
    &integrator::depth::PLUGIN,
    &integrator::prb::PRB,
    &integrator::prb::PRB_BASIC,
    &integrator::prb::PRB_PROJECTIVE,
    &integrator::prb::DIRECT_PROJECTIVE,
    &integrator::volpath::VOLPATH,
    &integrator::volpath::VOLPATHMIS,
    &integrator::volpath::PRBVOLPATH,
    &integrator::stokes::PLUGIN,
    &integrator::aov::PLUGIN,
    &integrator::moment::PLUGIN,
    &integrator::ptracer::PLUGIN,
];

/// `<sensor>` plugins.
pub static SENSOR_PLUGINS: &[&Plugin<SensorDesc>] = &[
    &sensor::perspective::PLUGIN,
    &sensor::orthographic::PLUGIN,
    &sensor::thinlens::PLUGIN,
    &sensor::radiancemeter::PLUGIN,
    &sensor::irradiancemeter::PLUGIN,
    &sensor::batch::PLUGIN,
    &sensor::distant::PLUGIN,
];

/// `<film>` plugins (nested in a sensor).
pub static FILM_PLUGINS: &[&Plugin<FilmDesc>] = &[&film::hdrfilm::PLUGIN, &film::specfilm::PLUGIN];

/// `<rfilter>` plugins (nested in a film).
pub static RFILTER_PLUGINS: &[&Plugin<FilterDesc>] = &[
    &rfilter::r#box::PLUGIN,
    &rfilter::tent::PLUGIN,
    &rfilter::gaussian::PLUGIN,
    &rfilter::mitchell::PLUGIN,
    &rfilter::mitchell::CATMULLROM,
    &rfilter::lanczos::PLUGIN,
];

/// `<sampler>` plugins (nested in a sensor).
pub static SAMPLER_PLUGINS: &[&Plugin<SamplerDesc>] = &[
    &sampler::independent::PLUGIN,
    &sampler::stratified::PLUGIN,
    &sampler::multijitter::PLUGIN,
    &sampler::ldsampler::PLUGIN,
    &sampler::orthogonal::PLUGIN,
];

/// `<shape>` plugins.
pub static SHAPE_PLUGINS: &[&Plugin<ShapeDesc>] = &[
    &shape::sphere::PLUGIN,
    &shape::rectangle::PLUGIN,
    &shape::disk::PLUGIN,
    &shape::cube::PLUGIN,
    &shape::obj::PLUGIN,
    &shape::ply::PLUGIN,
    &shape::serialized::PLUGIN,
    &shape::cylinder::PLUGIN,
    &shape::shapegroup::PLUGIN,
    &shape::instance::PLUGIN,
    &shape::merge::PLUGIN,
    &shape::sdfgrid::PLUGIN,
    &shape::linearcurve::PLUGIN,
    &shape::bsplinecurve::PLUGIN,
];

/// `<emitter>` plugins attached to a shape (nested in a `<shape>`).
pub static AREA_EMITTER_PLUGINS: &[&Plugin<AreaEmitterDesc>] =
    &[&emitter::area::PLUGIN, &emitter::directionalarea::PLUGIN];

/// `<emitter>` plugins standing on their own in the scene.
pub static EMITTER_PLUGINS: &[&Plugin<EmitterDesc>] = &[
    &emitter::point::PLUGIN,
    &emitter::spot::PLUGIN,
    &emitter::projector::PLUGIN,
    &emitter::directional::PLUGIN,
    &emitter::constant::PLUGIN,
    &emitter::envmap::PLUGIN,
    &emitter::sunsky::PLUGIN,
];

/// `<texture>` plugins.
pub static TEXTURE_PLUGINS: &[&Plugin<Texture>] = &[
    &texture::checkerboard::PLUGIN,
    &texture::bitmap::PLUGIN,
    &texture::mesh_attribute::PLUGIN,
    &texture::rawconstant::PLUGIN,
    &texture::volume::PLUGIN,
];

/// `<volume>` plugins.
pub static VOLUME_PLUGINS: &[&Plugin<crate::texture::volume::Volume>] =
    &[&volume::gridvolume::PLUGIN, &volume::constvolume::PLUGIN];

/// `<medium>` plugins.
pub static MEDIUM_PLUGINS: &[&Plugin<crate::medium::Medium>] =
    &[&medium::homogeneous::PLUGIN, &medium::heterogeneous::PLUGIN];

/// `<phase>` plugins (nested in a medium).
pub static PHASE_PLUGINS: &[&Plugin<crate::medium::Phase>] = &[
    &phase::isotropic::PLUGIN,
    &phase::hg::PLUGIN,
    &phase::rayleigh::PLUGIN,
    &phase::tabphase::PLUGIN,
    &phase::blendphase::PLUGIN,
    &phase::sggx::PLUGIN,
];

/// `<spectrum type="...">` plugins.
pub static SPECTRUM_PLUGINS: &[&Plugin<Texture>] = &[
    &spectrum::d65::PLUGIN,
    &spectrum::blackbody::PLUGIN,
    &spectrum::uniform::PLUGIN,
    &spectrum::regular::PLUGIN,
    &spectrum::irregular::PLUGIN,
    &spectrum::srgb::PLUGIN,
];

/// The table of one kind of plugin: its tag and the name, summary and parameters of each plugin.
#[derive(Clone, Debug)]
pub struct KindTable {
    /// The XML tag (`bsdf`, `shape`, ...).
    pub tag: &'static str,
    /// The section title in `docs/plugins.md`.
    pub title: &'static str,
    /// `(name, summary, parameters)` of each plugin, in registry order.
    pub plugins: Vec<(&'static str, &'static str, &'static [ParamSpec])>,
    /// Each plugin's section of `docs/plugins.md`.
    sections: Vec<String>,
}

fn table<T>(tag: &'static str, title: &'static str, registries: &[&[&'static Plugin<T>]]) -> KindTable {
    let all = registries.iter().flat_map(|r| r.iter());
    KindTable {
        tag,
        title,
        plugins: all.clone().map(|p| (p.name, p.summary, p.params)).collect(),
        sections: all.map(|p| p.markdown()).collect(),
    }
}

/// Every registry, kind by kind, in the order `docs/plugins.md` lists them.
pub fn all_kinds() -> Vec<KindTable> {
    vec![
        table("bsdf", "BSDFs (`<bsdf>`)", &[BSDF_PLUGINS]),
        table("shape", "Shapes (`<shape>`)", &[SHAPE_PLUGINS]),
        table("emitter", "Emitters (`<emitter>`)", &[AREA_EMITTER_PLUGINS]),
        table("emitter", "Emitters (`<emitter>`)", &[EMITTER_PLUGINS]),
        table("texture", "Textures (`<texture>`)", &[TEXTURE_PLUGINS]),
        table("volume", "Volumes (`<volume>`)", &[VOLUME_PLUGINS]),
        table("medium", "Participating media (`<medium>`)", &[MEDIUM_PLUGINS]),
        table("phase", "Phase functions (`<phase>`)", &[PHASE_PLUGINS]),
        table(
            "spectrum",
            "Spectra (`<spectrum type=\"...\">`)",
            &[SPECTRUM_PLUGINS],
        ),
        table("sensor", "Sensors (`<sensor>`)", &[SENSOR_PLUGINS]),
        table("film", "Films (`<film>`)", &[FILM_PLUGINS]),
        table(
            "rfilter",
            "Reconstruction filters (`<rfilter>`)",
            &[RFILTER_PLUGINS],
        ),
        table("sampler", "Samplers (`<sampler>`)", &[SAMPLER_PLUGINS]),
        table(
            "integrator",
            "Integrators (`<integrator>`)",
            &[INTEGRATOR_PLUGINS],
        ),
    ]
}

/// The parameter tables of every plugin as Markdown (`docs/plugins.md`).
pub fn plugins_markdown() -> String {
    let mut s = String::from(
        "# Plugins\n\nGenerated from the plugins' parameter tables (`crates/gonio-render/src/plugins/` and,\n\
         for BSDFs, `crates/gonio-render/src/material/`); a test keeps this file in step with them.\n\
         Names, types and defaults are Mitsuba 3's unless marked (ours). Where a default of ours\n\
         departs from Mitsuba's estimator, \"Mitsuba:\" gives the value that restores it, the default\n\
         under `gonio render --mitsuba-estimators`.\n\n\
         A spectrum written as wavelength:value pairs is 0 outside its range for reflectances and\n\
         emission, as Mitsuba's `irregular` spectrum; for `eta`, `k` and indices of refraction\n\
         gonio continues the end values there instead (Mitsuba's 0 would make the Fresnel terms\n\
         NaN or absorb everything). Its `mean()`, which sets the lobe sampling weights of the\n\
         plastics, is Mitsuba's: the average over its own range.\n",
    );
    let mut last = "";
    for kind in all_kinds() {
        if kind.title != last {
            s.push_str(&format!("\n## {}\n", kind.title));
            last = kind.title;
        }
        for section in &kind.sections {
            s.push_str(section);
        }
    }
    s
}
