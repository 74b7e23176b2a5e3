//! `<integrator>` plugins.

pub mod aov;
pub mod depth;
pub mod direct;
pub mod moment;
pub mod path;
pub mod prb;
pub mod ptracer;
pub mod stokes;
pub mod volpath;

/// Warnings for what the scene's integrator leaves out of it (`loc`: the scene's element):
/// participating media in a polarized volumetric render (the volumetric path tracer carries
/// spectra) or under `ptracer` (the light tracer renders no media), and polarization under
/// `ptracer` (its paths carry spectra, where Mitsuba's polarized variants carry Stokes vectors
/// through it). Said rather than dropped silently.
pub(crate) fn what_is_left_out(scene: &crate::scene::Scene, loc: &crate::xml::Location) -> Vec<String> {
    let mut out = Vec::new();
    let has_media = scene.has_media();
    let ptracer = scene.integrator.kind == crate::scene::IntegratorKind::PTracer;
    if scene.integrator.volumetric && has_media && scene.asks_for_polarization() {
        out.push(format!(
            "{loc}: participating media are rendered unpolarized only: this polarized render leaves them out"
        ));
    }
    if ptracer && has_media {
        out.push(format!(
            "{loc}: the ptracer integrator renders no participating media: the scene's media are left out (use volpath)"
        ));
    }
    if ptracer && scene.asks_for_polarization() {
        out.push(format!(
            "{loc}: the ptracer integrator renders without polarization: polarizer, retarder, circular, pplastic and measured_polarized act on the intensity only (use path for a polarized render)"
        ));
    }
    out
}
