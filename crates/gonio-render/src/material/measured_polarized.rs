//! `measured_polarized`: a measured polarimetric BRDF (Baek et al. 2020's KAIST pBRDF dataset)
//! read from Mitsuba's `.pbsdf` tensor files (core model
//! [`gonio_core::bsdfs::MeasuredPolarized`]; Mitsuba 3 `src/bsdfs/measured_polarized.cpp`).
//!
//! The file holds the fields Mitsuba reads: `phi_d`, `theta_d`, `theta_h` (radians, increasing;
//! Mitsuba's files store them as 1 × n arrays), `wvls` (nm) and `M`, the Mueller matrices of shape
//! n_φd × n_θd × n_θh × n_λ × 4 × 4. Mitsuba insists on float32 axes and matrices and uint16
//! wavelengths, and reads five of them whatever the axis holds; gonio reads any numeric element
//! type and uses every wavelength of the axis.
//! A scene with this material renders polarized, as one with `pplastic` does.

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, TableMaterial, TableModel};
use crate::tensor_file::TensorFile;
use crate::xml::{Builder, Params, SceneError};
use gonio_core::bsdfs::measured_polarized::PbrdfTable;
use gonio_core::bsdfs::{LeafBsdf, MeasuredPolarized};
use std::path::Path;
use std::sync::Arc;

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the `.pbsdf` file (required), relative to the scene file or a `<path>` folder",
);
const ALPHA_SAMPLE: ParamSpec = ParamSpec::new(
    "alpha_sample",
    ParamType::Float,
    DefaultValue::Float(0.1),
    "GGX roughness of the sampling lobe (> 0): shapes the noise, not the image",
);
const WAVELENGTH: ParamSpec = ParamSpec::new(
    "wavelength",
    ParamType::Float,
    DefaultValue::Float(-1.0),
    "−1: the spectral table; else every wavelength looks up the table at this one (nm, > 0; the dataset spans 450–650)",
);

/// The `measured_polarized` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "measured_polarized",
    summary: "A measured polarimetric BRDF (Baek et al. 2020, KAIST pBRDF dataset, Mitsuba's `.pbsdf` files): Mueller matrices over the Rusinkiewicz angles and wavelength, interpolated.",
    params: &[FILENAME, ALPHA_SAMPLE, WAVELENGTH],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let alpha = p.float_checked(ALPHA_SAMPLE.name, 0.1, |a| a > 0.0, "must be a finite number > 0")? as f32;
    let wavelength = p.float_checked(
        WAVELENGTH.name,
        -1.0,
        |l| l == -1.0 || l > 0.0,
        "must be −1 (spectral) or a wavelength > 0 nm",
    )?;
    let table = super::read_filename(b, p, PLUGIN.name, read_pbsdf)?;
    let wavelength = (wavelength != -1.0).then_some(wavelength as f32);
    Ok(Material::new(TableMaterial {
        model: Arc::new(MeasuredPolarized::new(table, alpha, wavelength)),
    }))
}

/// Reads a `.pbsdf` file into a checked table.
pub fn read_pbsdf(path: &Path) -> Result<PbrdfTable, String> {
    read_pbsdf_fields(path).map_err(|e| format!("{}: {e}", path.display()))
}

fn read_pbsdf_fields(path: &Path) -> Result<PbrdfTable, String> {
    let file = TensorFile::read(path).map_err(|e| e.to_string())?;
    let field = |name: &str| {
        file.require(name)
            .map_err(|e| format!("{e}; a .pbsdf file has phi_d, theta_d, theta_h, wvls and M"))
    };
    let (phi_d, theta_d, theta_h, wvls, m) = (
        field("phi_d")?,
        field("theta_d")?,
        field("theta_h")?,
        field("wvls")?,
        field("M")?,
    );
    let want = [phi_d.len(), theta_d.len(), theta_h.len(), wvls.len(), 4, 4];
    if m.shape != want {
        return Err(format!(
            "field \"M\" has shape {:?}; the axes call for {want:?} (phi_d × theta_d × theta_h × wvls × 4 × 4)",
            m.shape
        ));
    }
    PbrdfTable::new(
        phi_d.to_f32(),
        theta_d.to_f32(),
        theta_h.to_f32(),
        wvls.to_f32(),
        m.to_f32(),
    )
    .map_err(|e| e.to_string())
}

/// `measured_polarized` in a scene.
pub type MeasuredPolarizedMaterial = TableMaterial<MeasuredPolarized>;

impl TableModel for MeasuredPolarized {
    const POLARIZED: bool = true;
    fn leaf(&self) -> LeafBsdf<'_> {
        LeafBsdf::MeasuredPolarized(self)
    }
}
