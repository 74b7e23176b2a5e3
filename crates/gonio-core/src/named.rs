//! Named optical data: Mitsuba's IOR presets, conductor η/k tables under Mitsuba's `material`
//! names, and dispersive glasses as Sellmeier spectra.
//!
//! * [`ior_preset`]: Mitsuba 3 `include/mitsuba/render/ior.h` (values from Hecht, ≈ 589 nm,
//!   0–20 °C), matched case-insensitively.
//! * [`conductor`]: η and k as piecewise-linear spectra with the end values continued outside
//!   the table (n = k = 0 would make the conductor Fresnel formula NaN). Data and sources in
//!   `data/metals.rs`; `none` is the ideal mirror η = 0, k = 1 (F ≡ 1).
//! * [`glass`]: Schott catalogue Sellmeier coefficients n² = 1 + Σ Bⱼλ²/(λ² − Cⱼ) (λ in µm):
//!   N-BK7, N-BAF10, N-FK51A, N-LASF9, SF5, SF10, SF11 (Schott optical glass data sheets; the same
//!   curves refractiveindex.info tabulates and pbrt-v4 samples as `glass-*`) and fused silica
//!   (Malitson 1965, J. Opt. Soc. Am. 55, 1205).

use crate::data::metals::*;
use crate::data::metals_luxpop::LUXPOP;
use crate::spectra::{Extrapolation, PiecewiseLinear, Spectrum};

/// Mitsuba's IOR presets (name, index).
#[allow(clippy::excessive_precision)]
const IOR_PRESETS: [(&str, f32); 23] = [
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index of refraction of a Mitsuba preset name (case-insensitive, surrounding blanks
/// ignored), e.g. `"bk7"` → 1.5046, `"Air"` → 1.000277.
pub fn ior_preset(name: &str) -> Option<f32> {
    let name = name.trim();
    IOR_PRESETS
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name))
        .map(|&(_, v)| v)
}

/// All IOR preset names, for error messages.
pub fn ior_preset_names() -> Vec<&'static str> {
    IOR_PRESETS.iter().map(|(n, _)| *n).collect()
}

/// Conductor names with their own tables in `data/metals.rs` (Mitsuba's spelling); every other
/// name of Mitsuba's `data/ior` folder is in `data/metals_luxpop.rs`.
const CONDUCTORS: [&str; 8] = ["none", "Ag", "Al", "Au", "Cr", "Cu", "CuZn", "W"];

fn table(lambda: &[f32], values: &[f32]) -> Spectrum {
    // The static tables are strictly increasing and finite (checked by the tests below).
    match PiecewiseLinear::new(lambda.to_vec(), values.to_vec(), Extrapolation::Clamp) {
        Some(p) => Spectrum::piecewise(p),
        None => Spectrum::Constant(0.0),
    }
}

/// Complex index (η, k) of a conductor under its Mitsuba `material` name (case-insensitive):
/// `none` (η = 0, k = 1: a perfect mirror), `CuZn` (brass, pbrt-v4's data), and every preset of
/// Mitsuba 3's `data/ior` folder: `a-C`, `Ag`, `Al`, `AlAs`, `AlSb`, `Au`, `Be`, `Cr`, `CsI`, `Cu`,
/// `Cu2O`, `CuO`, `d-C`, `Hg`, `HgTe`, `Ir`, `K`, `Li`, `MgO`, `Mo`, `Na_palik`, `Nb`,
/// `Ni_palik`, `Rh`, `Se`, `Se-e`, `SiC`, `SnTe`, `Ta`, `Te`, `Te-e`, `ThF4`, `TiC`, `TiN`,
/// `TiO2`, `TiO2-e`, `VC`, `V_palik`, `VN`, `W` and their `_palik` spellings.
///
/// Where a table ends inside the visible range (AlSb and Se at 590–690 nm, Li at 751 nm, MgO at
/// 768 nm, ThF4 at 800 nm, d-C at 346–656 nm) its end values continue; Mitsuba 3.9.1 evaluates
/// those wavelengths to NaN instead. The presets whose k is zero everywhere (CsI, SnTe, ThF4,
/// d-C: dielectrics, listed by Mitsuba as conductors) load here; Mitsuba refuses them ("no
/// probability mass found").
pub fn conductor(name: &str) -> Option<(Spectrum, Spectrum)> {
    let name = name.trim();
    if let Some(canonical) = CONDUCTORS.iter().find(|n| n.eq_ignore_ascii_case(name)) {
        let (l, eta, k): (&[f32], &[f32], &[f32]) = match *canonical {
            "none" => return Some((Spectrum::Constant(0.0), Spectrum::Constant(1.0))),
            "Ag" => (&PALIK_LAMBDA, &AG_ETA, &AG_K),
            "Al" => (&PALIK_LAMBDA, &AL_ETA, &AL_K),
            "Au" => (&PALIK_LAMBDA, &AU_ETA, &AU_K),
            "Cu" => (&PALIK_LAMBDA, &CU_ETA, &CU_K),
            "Cr" => (&CR_LAMBDA, &CR_ETA, &CR_K),
            "CuZn" => (&CUZN_LAMBDA, &CUZN_ETA, &CUZN_K),
            "W" => (&W_LAMBDA, &W_ETA, &W_K),
            _ => return None,
        };
        return Some((table(l, eta), table(l, k)));
    }
    let (_, l, eta, k) = LUXPOP.iter().find(|(n, ..)| n.eq_ignore_ascii_case(name))?;
    Some((table(l, eta), table(l, k)))
}

/// All conductor names, for error messages.
pub fn conductor_names() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = CONDUCTORS.to_vec();
    names.extend(LUXPOP.iter().map(|(n, ..)| *n));
    names
}

/// A Schott-style glass: canonical name, accepted aliases (compared after lower-casing and
/// removing blanks, '-' and '_'), B₁..₃, C₁..₃ (µm²).
struct Glass {
    name: &'static str,
    aliases: &'static [&'static str],
    b: [f32; 3],
    c: [f32; 3],
}

// Catalogue figures are kept verbatim although f32 rounds them.
#[allow(clippy::excessive_precision)]
const GLASSES: [Glass; 8] = [
    Glass {
        name: "N-BK7",
        aliases: &["nbk7", "bk7", "bk7glass", "glassbk7"],
        b: [1.03961212, 0.231792344, 1.01046945],
        c: [0.00600069867, 0.0200179144, 103.560653],
    },
    Glass {
        name: "fused silica",
        aliases: &["fusedsilica", "silica", "sio2", "fusedquartz"],
        // Malitson 1965: C = 0.0684043², 0.1162414², 9.896161² µm².
        b: [0.6961663, 0.4079426, 0.8974794],
        c: [0.00467914826, 0.0135120631, 97.9340025],
    },
    Glass {
        name: "N-BAF10",
        aliases: &["nbaf10", "baf10", "glassbaf10"],
        b: [1.5851495, 0.143559385, 1.08521269],
        c: [0.00926681282, 0.0424489805, 105.613573],
    },
    Glass {
        name: "N-FK51A",
        aliases: &["nfk51a", "fk51a", "glassfk51a"],
        b: [0.971247817, 0.216901417, 0.904651666],
        c: [0.00472301995, 0.0153575612, 168.68133],
    },
    Glass {
        name: "N-LASF9",
        aliases: &["nlasf9", "lasf9", "glasslasf9"],
        b: [2.00029547, 0.298926886, 1.80691843],
        c: [0.0121426017, 0.0538736236, 156.530829],
    },
    Glass {
        name: "SF5",
        aliases: &["sf5", "glassf5", "glasssf5"],
        b: [1.52481889, 0.187085527, 1.42729015],
        c: [0.011254756, 0.0588995392, 129.141675],
    },
    Glass {
        name: "SF10",
        aliases: &["sf10", "glassf10", "glasssf10"],
        b: [1.62153902, 0.256287842, 1.64447552],
        c: [0.0122241457, 0.0595736775, 147.468793],
    },
    Glass {
        name: "SF11",
        aliases: &["sf11", "glassf11", "glasssf11"],
        b: [1.73759695, 0.313747346, 1.89878101],
        c: [0.013188707, 0.0623068142, 155.23629],
    },
];

fn squash(name: &str) -> String {
    name.chars()
        .filter(|c| !c.is_whitespace() && *c != '-' && *c != '_')
        .flat_map(char::to_lowercase)
        .collect()
}

/// The dispersive index n(λ) of a named glass as a Sellmeier spectrum. Names are matched
/// case-insensitively ignoring blanks, '-' and '_': "N-BK7", "nbk7", "sf11", "fused silica",
/// and pbrt-v4's scene names "glass-BK7", "glass-F11" (which hold SF11), ...
pub fn glass(name: &str) -> Option<Spectrum> {
    let key = squash(name);
    GLASSES
        .iter()
        .find(|g| squash(g.name) == key || g.aliases.contains(&key.as_str()))
        .map(|g| Spectrum::sellmeier(g.b, g.c))
}

/// Canonical names of the dispersive glasses.
pub fn glass_names() -> Vec<&'static str> {
    GLASSES.iter().map(|g| g.name).collect()
}

/// pbrt-v4's named spectra that have a counterpart here: `metal-<X>-eta` / `metal-<X>-k` for the
/// conductors above, `glass-BK7`, `glass-BAF10`, `glass-FK51A`, `glass-LASF9`, `glass-F5`,
/// `glass-F10`, `glass-F11` (Sellmeier curves; pbrt's tables sample the same formula) and
/// `stdillum-D65` (unit luminance).
pub fn pbrt_named_spectrum(name: &str) -> Option<Spectrum> {
    let name = name.trim();
    if name == "stdillum-D65" {
        return Some(Spectrum::d65());
    }
    if let Some(rest) = name.strip_prefix("metal-") {
        let (metal, which) = rest.rsplit_once('-')?;
        let metal = CONDUCTORS.iter().find(|n| **n == metal && **n != "none")?;
        let (eta, k) = conductor(metal)?;
        return match which {
            "eta" => Some(eta),
            "k" => Some(k),
            _ => None,
        };
    }
    if name.starts_with("glass-") {
        glass(name)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ior_presets_are_case_insensitive() {
        assert_eq!(ior_preset("bk7"), Some(1.5046));
        assert_eq!(ior_preset("BK7"), Some(1.5046));
        assert_eq!(ior_preset(" Acrylic Glass "), Some(1.49));
        assert_eq!(ior_preset("air"), Some(1.000277));
        assert_eq!(ior_preset("diamond"), Some(2.419));
        assert_eq!(ior_preset("unobtainium"), None);
        assert_eq!(ior_preset_names().len(), 23);
        // Derived defaults of Mitsuba 3 (include/mitsuba/render/ior.h): bk7/air and polypropylene/air.
        assert!((ior_preset("bk7").unwrap() / ior_preset("air").unwrap() - 1.504183).abs() < 1e-6);
        assert!((ior_preset("polypropylene").unwrap() / ior_preset("air").unwrap() - 1.489587).abs() < 1e-6);
    }

    #[test]
    fn metal_tables_are_well_formed() {
        for name in CONDUCTORS {
            let (eta, k) = conductor(name).unwrap();
            for s in [&eta, &k] {
                if let Spectrum::PiecewiseLinear(p) = s {
                    assert!(p.lambdas().len() >= 28, "{name}");
                    assert!(
                        p.lambdas()[0] <= 360.0 && *p.lambdas().last().unwrap() >= 830.0,
                        "{name}"
                    );
                }
            }
            // Clamp extrapolation: never zero η and k together.
            for l in [200.0, 360.0, 555.0, 830.0, 1000.0] {
                assert!(eta.eval(l) > 0.0 || k.eval(l) > 0.0, "{name} at {l}");
            }
        }
        assert!(
            matches!(conductor("none"), Some((Spectrum::Constant(e), Spectrum::Constant(k))) if e == 0.0 && k == 1.0)
        );
        assert!(conductor("au").is_some() && conductor("CUZN").is_some());
        assert!(conductor("Unobtainium").is_none());
    }

    #[test]
    fn every_mitsuba_conductor_preset_resolves() {
        // Mitsuba 3's `data/ior` tables are shorter (TiC: 6 samples) and some end inside the
        // visible range, but each is a strictly increasing, finite table that, continued by its
        // end values, never gives η = k = 0 (which would make the conductor Fresnel formula NaN).
        assert_eq!(conductor_names().len(), 8 + 65); // Mitsuba ships 71 names, 6 of them in metals.rs
        for (name, l, eta, k) in LUXPOP.iter() {
            assert!(
                l.len() >= 6 && l.len() == eta.len() && l.len() == k.len(),
                "{name}"
            );
            assert!(l.windows(2).all(|w| w[0] < w[1]), "{name}");
            assert!(
                eta.iter().chain(k.iter()).all(|v| v.is_finite() && *v >= 0.0),
                "{name}"
            );
            let (eta, k) = conductor(name).unwrap();
            assert!(matches!(eta, Spectrum::PiecewiseLinear(_)), "{name}");
            for l in [200.0, 360.0, 555.0, 700.0, 830.0, 1000.0] {
                assert!(eta.eval(l) > 0.0 || k.eval(l) > 0.0, "{name} at {l}");
            }
        }
        for name in ["a-C", "A-c", "Cu_palik", "TiO2-e", "Na_palik", "VN"] {
            assert!(conductor(name).is_some(), "{name}");
        }
        // Distinct data where Mitsuba's files differ (Cu_palik is not Cu).
        assert_ne!(conductor("Cu_palik"), conductor("Cu"));
        assert_eq!(conductor("AlAs_palik"), conductor("AlAs"));
    }

    #[test]
    fn metals_at_550nm_match_the_notes() {
        // pbrt-v4's metal-*-eta/-k tables (util/spectrum.cpp) interpolated at 550 nm: Ag n 0.125,
        // k 3.340; Al 0.959, 6.687; Cu 0.958, 2.577; CuZn 0.527, 2.765; Au 0.3504, 2.7141.
        for (name, n, k) in [
            ("Ag", 0.125, 3.340),
            ("Al", 0.959, 6.687),
            ("Cu", 0.958, 2.577),
            ("CuZn", 0.527, 2.765),
            ("Au", 0.3504, 2.7141),
        ] {
            let (eta, kk) = conductor(name).unwrap();
            assert!(
                (eta.eval(550.0) - n).abs() < 1.5e-3,
                "{name} n = {}",
                eta.eval(550.0)
            );
            assert!(
                (kk.eval(550.0) - k).abs() < 1.5e-3,
                "{name} k = {}",
                kk.eval(550.0)
            );
        }
    }

    #[test]
    fn pbrt_names_resolve() {
        let au = pbrt_named_spectrum("metal-Au-k").unwrap();
        assert_eq!(au, conductor("Au").unwrap().1);
        assert_eq!(
            pbrt_named_spectrum("metal-CuZn-eta").unwrap(),
            conductor("CuZn").unwrap().0
        );
        assert_eq!(pbrt_named_spectrum("glass-F11").unwrap(), glass("SF11").unwrap());
        assert_eq!(pbrt_named_spectrum("stdillum-D65").unwrap(), Spectrum::d65());
        for bad in [
            "metal-Au",
            "metal-none-eta",
            "metal-Xx-k",
            "glass-XYZ",
            "stdillum-A",
            "Au",
        ] {
            assert!(pbrt_named_spectrum(bad).is_none(), "{bad}");
        }
    }

    #[test]
    fn glass_names_resolve() {
        for name in [
            "N-BK7",
            "nbk7",
            "BK7 glass",
            "glass-BK7",
            "sf11",
            "SF11",
            "glass-F11",
            "fused silica",
            "Fused-Silica",
            "n-lasf9",
        ] {
            assert!(glass(name).is_some(), "{name}");
        }
        assert!(glass("bk8").is_none());
        assert_eq!(glass_names().len(), 8);
        for name in glass_names() {
            assert!(glass(name).is_some(), "{name}");
        }
    }
}
