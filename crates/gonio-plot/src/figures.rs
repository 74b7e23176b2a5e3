//! Ready-made figures for the instruments: each takes the numbers computed by
//! `gonio_core::instruments` and lays them out with titles, units, legends and markers.

use super::{
    DiskImage, DiskMarker, Figure, HemispherePlot, LegendPosition, LinePlot, MarkerKind, Panel, Pixels,
    PolarArrow, PolarCurve, PolarPlot, Series, VLine,
};
use gonio_core::Spectrum;
use gonio_core::bsdf::BsdfFlags;
use gonio_core::instruments::DeltaLobe;
use gonio_core::instruments::albedo::AlbedoPoint;
use gonio_core::instruments::fresnel::{
    PolarizationCurves, brewster_angle_deg, conductor_polarization_vs_angle, conductor_vs_angle,
    conductor_vs_wavelength, critical_angle_deg, dielectric_polarization_vs_angle, dielectric_vs_angle,
    dielectric_vs_wavelength, thin_slab_vs_angle,
};
use gonio_core::instruments::microfacet_albedo::RoughnessCurve;
use gonio_core::instruments::polar::PolarLobe;
use gonio_core::instruments::slice::{Fixed, Slice};

fn pts(x: &[f32], y: &[f32]) -> Vec<(f64, f64)> {
    x.iter().zip(y).map(|(&a, &b)| (a as f64, b as f64)).collect()
}

const ANGLE: &str = "angle of incidence θ  [deg]";

/// R_s, R_p, R and T = 1 − R against angle, seen from the side of relative index `eta`.
pub fn fresnel_angle_panel(eta: f32, title: &str) -> LinePlot {
    let c = dielectric_vs_angle(eta, 361);
    let mut p = LinePlot::new(title, ANGLE, "reflectance  [–]");
    p.x_range = Some((0.0, 90.0));
    p.y_range = Some((0.0, 1.02));
    let t: Vec<f32> = c.r.iter().map(|r| 1.0 - r).collect();
    p.series
        .push(Series::new("R_s (⊥)", pts(&c.angles_deg, &c.rs)).color(0));
    p.series
        .push(Series::new("R_p (∥)", pts(&c.angles_deg, &c.rp)).color(1));
    p.series
        .push(Series::new("R = (R_s + R_p)/2", pts(&c.angles_deg, &c.r)).color(6));
    p.series
        .push(Series::new("T = 1 − R", pts(&c.angles_deg, &t)).color(2).dashed());
    let b = brewster_angle_deg(eta);
    p.vlines.push(VLine {
        x: b as f64,
        label: format!("Brewster {b:.1}°"),
    });
    if let Some(c) = critical_angle_deg(eta) {
        p.vlines.push(VLine {
            x: c as f64,
            label: format!("critical {c:.1}°"),
        });
    }
    p
}

/// Single interface against the Stokes thin slab, for relative index `eta`.
pub fn thin_slab_panel(eta: f32) -> LinePlot {
    let c = thin_slab_vs_angle(eta, 361);
    let mut p = LinePlot::new(
        format!("Thin vs thick glass, η = {eta}"),
        ANGLE,
        "reflectance / transmittance  [–]",
    );
    p.x_range = Some((0.0, 90.0));
    p.y_range = Some((0.0, 1.02));
    p.note = "thin slab: Stokes sum R' = R + T²R/(1 − R²), T' = 1 − R'".into();
    p.series
        .push(Series::new("one interface R (thick glass)", pts(&c.angles_deg, &c.single)).color(0));
    p.series
        .push(Series::new("thin slab R'", pts(&c.angles_deg, &c.slab_r)).color(1));
    p.series.push(
        Series::new("thin slab T'", pts(&c.angles_deg, &c.slab_t))
            .color(2)
            .dashed(),
    );
    p
}

/// The finite points of a curve (NaN marks "no light": total internal reflection).
fn finite_pts(x: &[f32], y: &[f32]) -> Vec<(f64, f64)> {
    x.iter()
        .zip(y)
        .filter(|(_, b)| b.is_finite())
        .map(|(&a, &b)| (a as f64, b as f64))
        .collect()
}

const DOP: &str = "degree of polarization  [–]";
const RETARDANCE: &str = "retardance δ = arg r_p − arg r_s  [deg]";

/// Degree of polarization of reflected and transmitted light for unpolarized incident light,
/// from both sides of a dielectric of relative index `eta` (> 1).
pub fn dielectric_dop_panel(eta: f32) -> LinePlot {
    let mut p = LinePlot::new(
        format!("Polarization of unpolarized light, η = {eta}"),
        ANGLE,
        DOP,
    );
    p.x_range = Some((0.0, 90.0));
    p.y_range = Some((0.0, 1.02));
    p.note = "reflected: |R_s − R_p|/(R_s + R_p), transmitted: |T_s − T_p|/(T_s + T_p)".into();
    let out = dielectric_polarization_vs_angle(eta, 361);
    let inside = dielectric_polarization_vs_angle(1.0 / eta, 361);
    let add =
        |p: &mut LinePlot, label: &str, c: &PolarizationCurves, y: &[f32], color: usize, dashed: bool| {
            let s = Series::new(label, finite_pts(&c.angles_deg, y)).color(color);
            p.series.push(if dashed { s.dashed() } else { s });
        };
    add(&mut p, "reflected, outside", &out, &out.dop_reflected, 0, false);
    add(
        &mut p,
        "transmitted, outside",
        &out,
        &out.dop_transmitted,
        2,
        false,
    );
    add(
        &mut p,
        "reflected, inside",
        &inside,
        &inside.dop_reflected,
        1,
        true,
    );
    add(
        &mut p,
        "transmitted, inside",
        &inside,
        &inside.dop_transmitted,
        6,
        true,
    );
    let b = brewster_angle_deg(eta);
    p.vlines.push(VLine {
        x: b as f64,
        label: format!("Brewster {b:.1}°"),
    });
    p
}

/// Retardance of the reflection from both sides of a dielectric: 180° or 0° (a sign flip of r_p
/// at Brewster's angle) outside total internal reflection, the continuous TIR phase past the
/// critical angle.
pub fn dielectric_retardance_panel(eta: f32) -> LinePlot {
    let mut p = LinePlot::new(format!("Phase of reflection, η = {eta}"), ANGLE, RETARDANCE);
    p.x_range = Some((0.0, 90.0));
    p.y_range = Some((-5.0, 185.0));
    p.note = "TIR: tan(δ/2) = cos θ √(sin²θ − η²)/sin²θ".into();
    let out = dielectric_polarization_vs_angle(eta, 361);
    let inside = dielectric_polarization_vs_angle(1.0 / eta, 361);
    let abs = |v: &[f32]| v.iter().map(|x| x.abs()).collect::<Vec<f32>>();
    p.series
        .push(Series::new("|δ|, outside", pts(&out.angles_deg, &abs(&out.retardance_deg))).color(0));
    p.series.push(
        Series::new(
            "|δ|, inside (TIR)",
            pts(&inside.angles_deg, &abs(&inside.retardance_deg)),
        )
        .color(1)
        .dashed(),
    );
    if let Some(c) = critical_angle_deg(1.0 / eta) {
        p.vlines.push(VLine {
            x: c as f64,
            label: format!("critical {c:.1}°"),
        });
    }
    p
}

/// Degree of polarization of the light a conductor reflects (unpolarized incident light) at
/// three wavelengths.
pub fn conductor_dop_panel(eta: &Spectrum, k: &Spectrum, name: &str) -> LinePlot {
    let mut p = LinePlot::new(format!("{name}: polarization of reflected light"), ANGLE, DOP);
    p.x_range = Some((0.0, 90.0));
    p.y_range = Some((0.0, 1.02));
    p.legend = LegendPosition::UpperLeft;
    for (c, l) in [(0usize, 450.0f32), (2, 550.0), (1, 650.0)] {
        let cv = conductor_polarization_vs_angle(eta.eval(l), k.eval(l), 361);
        p.series
            .push(Series::new(format!("{l} nm"), finite_pts(&cv.angles_deg, &cv.dop_reflected)).color(c));
    }
    p
}

/// Retardance of a conductor's reflection at three wavelengths: from 180° at normal incidence
/// to 0° at grazing, through 90° near the principal angle.
pub fn conductor_retardance_panel(eta: &Spectrum, k: &Spectrum, name: &str) -> LinePlot {
    let mut p = LinePlot::new(format!("{name}: phase of reflection"), ANGLE, RETARDANCE);
    p.x_range = Some((0.0, 90.0));
    p.y_range = Some((-5.0, 185.0));
    p.legend = LegendPosition::LowerLeft;
    for (c, l) in [(0usize, 450.0f32), (2, 550.0), (1, 650.0)] {
        let cv = conductor_polarization_vs_angle(eta.eval(l), k.eval(l), 361);
        let d: Vec<f32> = cv.retardance_deg.iter().map(|x| x.abs()).collect();
        p.series
            .push(Series::new(format!("|δ|, {l} nm"), pts(&cv.angles_deg, &d)).color(c));
    }
    p
}

/// The three Fresnel panels of a dielectric of relative index `eta` (> 1): from outside, from
/// inside, thin slab.
pub fn fresnel_dielectric_figure(eta: f32, name: &str) -> Figure {
    let eta = (eta * 1e4).round() / 1e4;
    Figure {
        title: format!("Fresnel reflectance of a dielectric: {name}, η = {eta}"),
        panels: vec![
            Panel::Line(fresnel_angle_panel(eta, &format!("From outside (η = {eta})"))),
            Panel::Line(fresnel_angle_panel(
                1.0 / eta,
                &format!("From inside (η = 1/{eta})"),
            )),
            Panel::Line(thin_slab_panel(eta)),
            Panel::Line(dielectric_dop_panel(eta)),
            Panel::Line(dielectric_retardance_panel(eta)),
        ],
        columns: 3,
        panel_size: (560, 440),
    }
}

/// A dispersive glass: the three Fresnel panels at its index at 589.3 nm, then n(λ) and the
/// normal-incidence reflectance against wavelength.
pub fn fresnel_dispersive_figure(ior: &Spectrum, name: &str) -> Figure {
    let n_d = ior.eval(589.3);
    let mut f = fresnel_dielectric_figure(n_d, &format!("{name} (n_d at 589.3 nm)"));
    let d = dielectric_vs_wavelength(ior, 1.0, 360.0, 830.0, 236, 0.0);
    let mut pn = LinePlot::new(
        format!("Dispersion of {name}"),
        "wavelength λ  [nm]",
        "index of refraction n(λ)  [–]",
    );
    pn.series
        .push(Series::new("n(λ)", d.iter().map(|x| (x.0 as f64, x.1 as f64)).collect()).color(0));
    let lo = d.iter().map(|x| x.1).fold(f32::MAX, f32::min) as f64;
    let hi = d.iter().map(|x| x.1).fold(f32::MIN, f32::max) as f64;
    pn.y_range = Some((lo - 0.1 * (hi - lo).max(1e-3), hi + 0.1 * (hi - lo).max(1e-3)));
    let mut pr = LinePlot::new(
        format!("Reflectance of {name} against λ"),
        "wavelength λ  [nm]",
        "reflectance  [–]",
    );
    pr.series
        .push(Series::new("R at 0°", d.iter().map(|x| (x.0 as f64, x.2 as f64)).collect()).color(1));
    let r60 = dielectric_vs_wavelength(ior, 1.0, 360.0, 830.0, 236, 60.0);
    pr.series
        .push(Series::new("R at 60°", r60.iter().map(|x| (x.0 as f64, x.2 as f64)).collect()).color(2));
    f.panels.push(Panel::Line(pn));
    f.panels.push(Panel::Line(pr));
    f
}

/// A conductor: R_s, R_p, R against angle at three wavelengths; R against wavelength at 0° and
/// 60°; and its η(λ), k(λ).
pub fn fresnel_conductor_figure(eta: &Spectrum, k: &Spectrum, name: &str) -> Figure {
    let mut pa = LinePlot::new(
        format!("{name}: reflectance against angle"),
        ANGLE,
        "reflectance  [–]",
    );
    pa.legend = LegendPosition::LowerLeft;
    pa.x_range = Some((0.0, 90.0));
    pa.y_range = Some((0.0, 1.02));
    for (c, l) in [(0usize, 450.0f32), (2, 550.0), (1, 650.0)] {
        let cv = conductor_vs_angle(eta.eval(l), k.eval(l), 361);
        pa.series
            .push(Series::new(format!("R, {l} nm"), pts(&cv.angles_deg, &cv.r)).color(c));
        if l == 550.0 {
            pa.series.push(
                Series::new("R_s, 550 nm", pts(&cv.angles_deg, &cv.rs))
                    .color(6)
                    .dashed(),
            );
            pa.series.push(
                Series::new("R_p, 550 nm", pts(&cv.angles_deg, &cv.rp))
                    .color(3)
                    .dashed(),
            );
        }
    }
    let mut pl = LinePlot::new(
        format!("{name}: reflectance against wavelength"),
        "wavelength λ  [nm]",
        "reflectance  [–]",
    );
    pl.legend = LegendPosition::LowerRight;
    pl.y_range = Some((0.0, 1.02));
    for (c, a) in [(1usize, 0.0f32), (0, 60.0), (2, 80.0)] {
        let v = conductor_vs_wavelength(eta, k, 360.0, 830.0, 236, a);
        pl.series.push(
            Series::new(
                format!("R at {a}°"),
                v.iter().map(|x| (x.0 as f64, x.1 as f64)).collect(),
            )
            .color(c),
        );
    }
    let mut pk = LinePlot::new(
        format!("{name}: complex index n + ik"),
        "wavelength λ  [nm]",
        "n, k  [–]",
    );
    let ls: Vec<f32> = (0..236).map(|i| 360.0 + 2.0 * i as f32).collect();
    pk.series.push(
        Series::new(
            "n (η)",
            ls.iter().map(|&l| (l as f64, eta.eval(l) as f64)).collect(),
        )
        .color(0),
    );
    pk.series
        .push(Series::new("k", ls.iter().map(|&l| (l as f64, k.eval(l) as f64)).collect()).color(1));
    Figure {
        title: format!("Fresnel reflectance of a conductor: {name}"),
        panels: vec![
            Panel::Line(pa),
            Panel::Line(pl),
            Panel::Line(pk),
            Panel::Line(conductor_dop_panel(eta, k, name)),
            Panel::Line(conductor_retardance_panel(eta, k, name)),
        ],
        columns: 3,
        panel_size: (560, 440),
    }
}

fn delta_label(d: &DeltaLobe) -> String {
    let kind = if d.flags.contains(BsdfFlags::TRANSMISSION) {
        "δ transmission"
    } else {
        "δ reflection"
    };
    format!("{kind}, {:.3}", d.throughput[0])
}

/// A slice as a hemisphere panel (channel 0 of the values, i.e. one wavelength).
pub fn slice_panel(slice: &Slice, name: &str, log: bool, wavelength_note: &str) -> HemispherePlot {
    let s = &slice.settings;
    let tf = |v: f32| if log { (1.0 + v.max(0.0)).log10() } else { v };
    let mut disks = vec![];
    let mut vmax = 0.0f32;
    for d in &slice.disks {
        let values: Vec<Option<f32>> = d.pixels.iter().map(|p| p.map(|v| tf(v[0]))).collect();
        vmax = values.iter().flatten().copied().fold(vmax, f32::max);
        let varying = if s.fixed == Fixed::Light { "view" } else { "light" };
        let label = if d.side * slice.fixed_direction.z.signum() > 0.0 {
            format!("{varying} on the same side (reflection)")
        } else {
            format!("{varying} on the other side (transmission)")
        };
        disks.push(DiskImage {
            label,
            pixels: Pixels::Scalar {
                resolution: s.resolution,
                values,
            },
            markers: vec![],
        });
    }
    let proj = s.projection;
    let fixed_name = if s.fixed == Fixed::Light { "light" } else { "view" };
    if let Some(first) = disks.first_mut() {
        let p = proj.to_disk(slice.fixed_direction);
        first.markers.push(DiskMarker {
            pos: (p.x, p.y),
            label: format!("{fixed_name} θ={}°", s.theta_deg),
            kind: MarkerKind::Fixed,
        });
    }
    for d in &slice.deltas {
        let same = d.direction.z * slice.fixed_direction.z > 0.0;
        let k = if same { 0 } else { 1 };
        if let Some(disk) = disks.get_mut(k) {
            let p = proj.to_disk(d.direction);
            disk.markers.push(DiskMarker {
                pos: (p.x, p.y),
                label: delta_label(d),
                kind: MarkerKind::Delta,
            });
        }
    }
    let quantity = if s.cosine { "f·|cos θ|" } else { "f" };
    let colorbar_label = if log {
        format!("log10(1 + {quantity})")
    } else {
        format!("{quantity}  [1/sr]")
    };
    let empty = vmax <= 0.0;
    let mut note = format!(
        "{}: centre = normal, rim = horizon, rings every 30°, azimuth φ anticlockwise from the right; {wavelength_note}",
        proj.description()
    );
    if empty {
        note.push_str("; f = 0 off the delta lobes");
    }
    let rings = [30.0f32, 60.0]
        .iter()
        .map(|&t| (proj.ring_radius(t.to_radians()), format!("{t}°")))
        .collect();
    let title = format!(
        "{name}: fix the {fixed_name} at θ = {}°, φ = {}°, vary the {}",
        s.theta_deg,
        s.phi_deg,
        if s.fixed == Fixed::Light { "view" } else { "light" }
    );
    HemispherePlot {
        title,
        disks,
        value_range: (0.0, if empty { 1.0 } else { vmax }),
        colorbar_label,
        note,
        rings,
    }
}

/// A slice of RGB display colours (sRGB-encoded, 0–1) as a hemisphere panel.
pub fn slice_panel_rgb(
    slice: &Slice,
    rgb: Vec<Vec<Option<[f32; 3]>>>,
    name: &str,
    note: &str,
) -> HemispherePlot {
    let mut p = slice_panel(slice, name, false, note);
    for (d, values) in p.disks.iter_mut().zip(rgb) {
        d.pixels = Pixels::Rgb {
            resolution: slice.settings.resolution,
            values,
        };
    }
    p
}

/// In-plane lobes of several BSDFs overlaid; `log` shows log10(1 + v).
pub fn polar_figure(lobes: &[(String, PolarLobe)], log: bool, wavelength_note: &str) -> Figure {
    let tf = |v: f32| if log { (1.0 + v.max(0.0)).log10() } else { v };
    let mut curves = vec![];
    let mut arrows = vec![];
    let mut full = false;
    let mut theta_i = 0.0;
    let mut cosine = false;
    for (k, (name, lobe)) in lobes.iter().enumerate() {
        theta_i = lobe.theta_i_deg;
        cosine = lobe.cosine;
        let points: Vec<(f32, f32)> = lobe
            .angles_deg
            .iter()
            .zip(&lobe.values)
            .map(|(&a, v)| (a, tf(v[0])))
            .collect();
        full |= points.iter().any(|p| p.0.abs() > 90.5 && p.1 > 0.0);
        curves.push(PolarCurve {
            label: name.clone(),
            points,
            color: k,
        });
        for d in &lobe.deltas {
            full |= d.direction.z < 0.0;
            arrows.push(PolarArrow {
                angle_deg: d.direction.x.atan2(d.direction.z).to_degrees(),
                label: delta_label(d),
                color: k,
            });
        }
    }
    let q = if cosine { "f·|cos θo|" } else { "f" };
    let r_label = if log {
        format!("log10(1 + {q})")
    } else {
        format!("{q} [1/sr]")
    };
    let plot = PolarPlot {
        title: format!("Lobes in the plane of incidence, θi = {theta_i}°  ({wavelength_note})"),
        curves,
        arrows,
        light_deg: -theta_i,
        r_label,
        full_circle: full,
    };
    Figure::single(Panel::Polar(plot), (760, if full { 760 } else { 480 }))
}

/// R(θ) and T(θ) with ±1 standard-error bars, several BSDFs.
pub fn albedo_figure(curves: &[(String, Vec<AlbedoPoint>)], note: &str) -> Figure {
    let mut p = LinePlot::new("Directional albedo", "angle of incidence θ  [deg]", "albedo  [–]");
    p.x_range = Some((0.0, 90.0));
    p.note = note.to_string();
    for (k, (name, pts)) in curves.iter().enumerate() {
        let x: Vec<f64> = pts.iter().map(|a| a.theta_deg as f64).collect();
        p.series.push(
            Series::new(
                format!("R(θ), {name}"),
                x.iter().zip(pts).map(|(&x, a)| (x, a.r)).collect(),
            )
            .color(k)
            .with_error(pts.iter().map(|a| a.r_stderr).collect()),
        );
        if pts.iter().any(|a| a.t > 0.0) {
            p.series.push(
                Series::new(
                    format!("T(θ), {name}"),
                    x.iter().zip(pts).map(|(&x, a)| (x, a.t)).collect(),
                )
                .color(k)
                .dashed()
                .with_error(pts.iter().map(|a| a.t_stderr).collect()),
            );
        }
    }
    let top = curves
        .iter()
        .flat_map(|c| c.1.iter())
        .map(|a| (a.r + a.t).max(a.r + a.r_stderr))
        .fold(1.0, f64::max);
    p.y_range = Some((0.0, top * 1.05));
    Figure::single(Panel::Line(p), (760, 520))
}

/// The lecture's point about single scattering: the directional albedo of a white (F = 1)
/// rough conductor against its roughness α, one colour per incident angle, GGX dashed.
pub fn microfacet_energy_figure(curves: &[RoughnessCurve]) -> Figure {
    let mut p = LinePlot::new(
        "Energy lost by single scattering: white rough conductor (F = 1)",
        "roughness α  [–]",
        "directional albedo E(θ)  [–]",
    );
    p.note = "Smith model, single scattering; 1 − E is the light that real mirror facets would still reflect after more bounces".into();
    p.legend = LegendPosition::LowerLeft;
    let mut thetas: Vec<f32> = vec![];
    for c in curves {
        if !thetas.contains(&c.theta_deg) {
            thetas.push(c.theta_deg);
        }
        let k = thetas.iter().position(|&t| t == c.theta_deg).unwrap_or(0);
        let s = Series::new(
            format!("{}, θ = {}°", c.kind.name(), c.theta_deg),
            c.points.iter().map(|&(a, e)| (a as f64, e)).collect(),
        )
        .color(k);
        p.series
            .push(if c.kind == gonio_core::microfacet::MicrofacetKind::Ggx {
                s.dashed()
            } else {
                s
            });
    }
    p.y_range = Some((0.0, 1.02));
    Figure::single(Panel::Line(p), (760, 520))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::MarkerKind;
    use gonio_core::SampledWavelengths;
    use gonio_core::bsdfs::{Conductor, Diffuse};
    use gonio_core::instruments::slice::{SliceSettings, compute_slice};

    #[test]
    fn microfacet_energy_figure_draws_a_curve_per_distribution_and_angle() {
        use gonio_core::instruments::microfacet_albedo::{albedo_vs_roughness, alpha_grid};
        use gonio_core::microfacet::MicrofacetKind;
        let curves = albedo_vs_roughness(
            &[MicrofacetKind::Beckmann, MicrofacetKind::Ggx],
            &[0.0, 80.0],
            &alpha_grid(0.1, 1.0, 4),
        );
        let f = microfacet_energy_figure(&curves);
        let svg = f.to_svg().unwrap();
        for label in ["beckmann, θ = 0°", "ggx, θ = 80°", "roughness α  [–]"] {
            assert!(svg.contains(label), "{label}");
        }
        let Panel::Line(p) = &f.panels[0] else {
            panic!("a line plot")
        };
        assert_eq!(p.series.len(), 4);
        assert!(p.series.iter().filter(|s| s.dashed).count() == 2, "GGX dashed");
    }

    #[test]
    fn fresnel_figure_marks_brewster_and_critical_angles_and_renders() {
        let f = fresnel_dielectric_figure(1.5, "glass");
        let svg = f.to_svg().unwrap();
        assert!(svg.contains("Brewster 56.3°"), "Brewster's angle from outside");
        assert!(
            svg.contains("Brewster 33.7°") && svg.contains("critical 41.8°"),
            "inside view"
        );
        assert!(
            svg.contains("angle of incidence θ  [deg]"),
            "axis label with units"
        );
        assert!(svg.contains("R_p (∥)"), "legend");
        let png = f.to_png().unwrap();
        let (w, h, rgb) = crate::decode_rgb_png(&png);
        assert_eq!((w, h), f.size());
        let dark = rgb.chunks_exact(3).filter(|p| p.iter().all(|&c| c < 100)).count();
        assert!(dark > 2000, "text and curves were drawn ({dark} dark pixels)");
    }

    #[test]
    fn mirror_slice_is_empty_but_for_its_marked_delta() {
        let wl = SampledWavelengths::fixed(550.0);
        let s = compute_slice(
            &Conductor::mirror(),
            &SliceSettings {
                theta_deg: 35.0,
                resolution: 32,
                ..Default::default()
            },
            &wl,
        );
        let p = slice_panel(&s, "mirror", false, "λ = 550 nm");
        match &p.disks[0].pixels {
            Pixels::Scalar { values, .. } => assert!(values.iter().flatten().all(|&v| v == 0.0)),
            Pixels::Rgb { .. } => panic!("scalar slice expected"),
        }
        let deltas: Vec<_> = p.disks[0]
            .markers
            .iter()
            .filter(|m| m.kind == MarkerKind::Delta)
            .collect();
        assert_eq!(deltas.len(), 1);
        // The mirror direction of a light at φ = 0 lies at φ = 180°: the left half of the disk.
        assert!(
            deltas[0].pos.0 < -0.3 && deltas[0].pos.1.abs() < 1e-4,
            "{:?}",
            deltas[0].pos
        );
        assert!(deltas[0].label.contains("δ reflection, 1.000"));
        assert!(p.note.contains("f = 0 off the delta lobes") && p.note.contains("equal-area"));
        let lam = compute_slice(
            &Diffuse::default(),
            &SliceSettings {
                resolution: 16,
                ..Default::default()
            },
            &wl,
        );
        let p = slice_panel(&lam, "diffuse", false, "");
        assert!(
            (p.value_range.1 - 0.5 / std::f32::consts::PI).abs() < 1e-6,
            "colour bar up to ρ/π"
        );
        let svg = Figure::single(Panel::Hemisphere(p), (700, 500)).to_svg().unwrap();
        assert!(
            svg.contains("data:image/png;base64,"),
            "the disk is embedded as an image"
        );
    }
}

#[cfg(test)]
mod text_fits {
    //! Every figure's text stays inside it: no ink in the outermost pixels of any figure kind at
    //! the size `gonio plot` draws it, with the longest captions each kind writes.
    use super::*;
    use gonio_core::bsdfs::{Conductor, Diffuse, Plastic};
    use gonio_core::instruments::albedo::{Wavelengths, directional_albedo};
    use gonio_core::instruments::microfacet_albedo::{albedo_vs_roughness, alpha_grid};
    use gonio_core::instruments::polar::compute_polar;
    use gonio_core::instruments::slice::{SliceSettings, compute_slice};
    use gonio_core::microfacet::MicrofacetKind;
    use gonio_core::{SampledWavelengths, TransportMode};

    /// Pixels of the figure's 2-pixel border that are not white.
    fn ink_on_border(f: &Figure) -> usize {
        let (w, h, rgb) = crate::decode_rgb_png(&f.to_png().unwrap());
        rgb.chunks_exact(3)
            .enumerate()
            .filter(|(i, p)| {
                let (x, y) = (*i as u32 % w, *i as u32 / w);
                (x < 2 || y < 2 || x + 2 >= w || y + 2 >= h) && p.iter().any(|&c| c < 245)
            })
            .count()
    }

    #[test]
    fn captions_fit_inside_every_figure() {
        let wl = SampledWavelengths::fixed(550.0);
        let mut figures: Vec<(&str, Figure)> = vec![];
        for (fixed, theta, width) in [(Fixed::Light, 30.0, 760), (Fixed::View, 60.0, 760)] {
            let s = compute_slice(
                &Conductor::mirror(),
                &SliceSettings {
                    fixed,
                    theta_deg: theta,
                    resolution: 24,
                    ..Default::default()
                },
                &wl,
            );
            let p = slice_panel(&s, "<bsdf type=\"conductor\"/>", true, "λ = 550 nm");
            let width = if p.disks.len() > 1 { 1100 } else { width };
            figures.push(("slice", Figure::single(Panel::Hemisphere(p), (width, 580))));
        }
        let s = compute_slice(
            &Plastic::default(),
            &SliceSettings {
                resolution: 24,
                ..Default::default()
            },
            &wl,
        );
        figures.push((
            "slice rgb",
            Figure::single(
                Panel::Hemisphere(slice_panel_rgb(
                    &s,
                    vec![vec![Some([0.5; 3]); 24 * 24]],
                    "<bsdf type=\"plastic\"/>",
                    "colour of π·f under D65, sRGB, scaled by 0.123",
                )),
                (760, 580),
            ),
        ));
        let lobes: Vec<(String, _)> = [
            (
                "<bsdf type=\"diffuse\"/>",
                compute_polar(&Diffuse::default(), 45.0, 181, true, &wl),
            ),
            (
                "<bsdf type=\"plastic\"/>",
                compute_polar(&Plastic::default(), 45.0, 181, true, &wl),
            ),
        ]
        .into_iter()
        .map(|(n, l)| (n.to_string(), l))
        .collect();
        figures.push(("polar", polar_figure(&lobes, true, "λ = 550 nm")));
        let pts = directional_albedo(
            &Diffuse::default(),
            &[0.0, 45.0, 89.5],
            64,
            TransportMode::Importance,
            Wavelengths::Visible,
            false,
            0,
        );
        figures.push((
            "albedo",
            albedo_figure(
                &[("<bsdf type=\"diffuse\"/>".into(), pts)],
                "20000 samples per angle, importance mode, mean over 360–830 nm, light from below; bars: ±1 standard error",
            ),
        ));
        let curves = albedo_vs_roughness(
            &[MicrofacetKind::Beckmann, MicrofacetKind::Ggx],
            &[0.0, 45.0, 80.0],
            &alpha_grid(0.1, 1.0, 3),
        );
        figures.push(("microfacet-albedo", microfacet_energy_figure(&curves)));
        figures.push(("fresnel", fresnel_dielectric_figure(1.5, "glass")));
        for (name, f) in &figures {
            assert_eq!(ink_on_border(f), 0, "{name}: text reaches the figure's edge");
        }
    }

    #[test]
    fn long_captions_wrap_and_short_ones_do_not() {
        let long = "Lambert equal-area projection: centre = normal, rim = horizon, rings every 30°, azimuth φ anticlockwise from the right; λ = 550 nm; f = 0 off the delta lobes";
        let lines = crate::wrap_text(long, 12, 700);
        assert!(lines.len() >= 2, "{lines:?}");
        assert!(lines.iter().all(|l| crate::text_width(l, 12) <= 700));
        assert_eq!(lines.join(" "), long, "no word lost");
        assert!(
            lines.iter().any(|l| l.contains("Lambert equal-area projection"))
                && lines.iter().any(|l| l.contains("f = 0 off the delta lobes")),
            "clauses stay whole: {lines:?}"
        );
        assert_eq!(crate::wrap_text("λ = 550 nm", 12, 700), vec!["λ = 550 nm"]);
        assert!(crate::fitting_size(long, 18, 300) < 18);
    }
}
