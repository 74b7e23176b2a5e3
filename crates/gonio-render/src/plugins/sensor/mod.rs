//! `<sensor>` plugins.

pub mod batch;
pub mod distant;
pub mod irradiancemeter;
pub mod orthographic;
pub mod perspective;
pub mod radiancemeter;
pub mod thinlens;

/// A sensor that records one value needs a film of 1 × 1 pixels, as Mitsuba requires; `what`
/// names it in the error ("a radiancemeter records one ray").
pub(crate) fn one_pixel(
    film: &crate::scene::FilmDesc,
    p: &crate::xml::Params<'_>,
    what: &str,
) -> Result<(), crate::xml::SceneError> {
    if (film.width, film.height) == (1, 1) {
        return Ok(());
    }
    Err(crate::xml::err(
        &p.obj.loc,
        crate::xml::ErrorKind::BadValue,
        format!(
            "{what}: its film must be 1 × 1 pixels, not {} × {} (as Mitsuba requires)",
            film.width, film.height
        ),
    ))
}
