//! `measured`: a BRDF of RGL's material database (Dupuy and Jakob 2018), read from its spectral
//! `.bsdf` file, Mitsuba's tensor format (core model [`gonio_core::bsdfs::Measured`]; Mitsuba 3
//! `src/bsdfs/measured.cpp`).
//!
//! The file's fields and shapes, as Mitsuba checks them: `description` (text), `jacobian` (one
//! value), `theta_i`, `phi_i`, `wavelengths` (1-D), `ndf`, `sigma` (2-D), `vndf`, `luminance`
//! (φi × θi × 2-D, the latter square) and `spectra` (φi × θi × λ × 2-D, the grid of
//! `luminance`); Mitsuba also insists on float32 (uint8 for the text and the flag), gonio reads
//! any numeric type. An RGB file (an `rgb` field instead of `spectra` and `wavelengths`) is
//! refused, as by Mitsuba's spectral variants: gonio renders spectrally.

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, TableMaterial, TableModel};
use crate::tensor_file::{Field, TensorFile};
use crate::xml::{Builder, Params, SceneError};
use gonio_core::bsdfs::measured::{Grid, MeasuredData};
use gonio_core::bsdfs::{LeafBsdf, Measured};
use std::path::Path;
use std::sync::Arc;

const FILENAME: ParamSpec = ParamSpec::new(
    "filename",
    ParamType::String,
    DefaultValue::None,
    "the spectral `.bsdf` file of RGL's database (required), relative to the scene file or a `<path>` folder",
);

/// The `measured` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "measured",
    summary: "A measured BRDF of RGL's material database (Dupuy and Jakob 2018): spectra indexed by the visible-normal warp of the material's own microfacet model, interpolated and importance-sampled.",
    params: &[FILENAME],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let model = super::read_filename(b, p, PLUGIN.name, read_rgl)?;
    Ok(Material::new(TableMaterial {
        model: Arc::new(model),
    }))
}

/// Reads an RGL `.bsdf` file into a checked model.
pub fn read_rgl(path: &Path) -> Result<Measured, String> {
    let file = TensorFile::read(path).map_err(|e| e.to_string())?;
    let field = |name: &str| {
        file.field(name).ok_or_else(|| {
            if name == "wavelengths" && file.field("rgb").is_some() {
                "an RGB file (its `rgb` field); gonio renders spectrally: use the material's spectral file"
                    .to_string()
            } else {
                format!("no field \"{name}\" (this file has {})", file.names().join(", "))
            }
        })
    };
    let wavelengths = field("wavelengths")?;
    let (theta_i, phi_i) = (field("theta_i")?, field("phi_i")?);
    let (n_phi, n_theta) = (phi_i.len(), theta_i.len());
    let dims = |f: &Field, name: &str, lead: &[usize], n: usize| -> Result<[usize; 2], String> {
        let ok = f.shape.len() == lead.len() + n && f.shape[..lead.len()] == *lead;
        if !ok {
            let want: Vec<String> = lead
                .iter()
                .map(|x| x.to_string())
                .chain(["h", "w"].map(String::from))
                .collect();
            return Err(format!(
                "field \"{name}\" has shape {:?}; expected [{}]",
                f.shape,
                want[..lead.len() + n].join(", ")
            ));
        }
        Ok([f.shape[f.shape.len() - 1], f.shape[f.shape.len() - 2]])
    };
    let grid = |name: &str, lead: &[usize]| -> Result<Grid, String> {
        let f = field(name)?;
        let size = dims(f, name, lead, 2)?;
        Ok(Grid {
            size,
            values: f.to_f32(),
        })
    };
    let luminance = grid("luminance", &[n_phi, n_theta])?;
    let spectra = grid("spectra", &[n_phi, n_theta, wavelengths.len()])?;
    if luminance.size[0] != luminance.size[1] || luminance.size != spectra.size {
        return Err(format!(
            "field \"spectra\" is over a {:?} grid, \"luminance\" over {:?}; they must agree and be square",
            spectra.size, luminance.size
        ));
    }
    let jacobian = field("jacobian")?;
    if jacobian.len() != 1 {
        return Err(format!(
            "field \"jacobian\" has shape {:?}; expected [1]",
            jacobian.shape
        ));
    }
    let data = MeasuredData {
        description: String::from_utf8_lossy(field("description")?.as_bytes()).into_owned(),
        jacobian: jacobian.to_f32()[0] != 0.0,
        theta_i: theta_i.to_f32(),
        phi_i: phi_i.to_f32(),
        wavelengths: wavelengths.to_f32(),
        ndf: grid("ndf", &[])?,
        sigma: grid("sigma", &[])?,
        vndf: grid("vndf", &[n_phi, n_theta])?,
        luminance,
        spectra,
    };
    Measured::new(data).map_err(|e| e.to_string())
}

/// `measured` in a scene.
pub type MeasuredMaterial = TableMaterial<Measured>;

impl TableModel for Measured {
    fn leaf(&self) -> LeafBsdf<'_> {
        LeafBsdf::Measured(self)
    }
}
