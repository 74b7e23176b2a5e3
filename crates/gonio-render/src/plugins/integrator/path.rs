//! `path`: the unidirectional path tracer with next-event estimation and MIS (Mitsuba 3
//! `src/integrators/path.cpp`); ours adds shadow rays through thin sheets and through glass, and
//! light subpaths for caustics (`crate::integrator`).

use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::{IntegratorDesc, IntegratorKind};
use crate::xml::{Builder, Params, SceneError};

pub(super) const MAX_DEPTH: ParamSpec = ParamSpec::new(
    "max_depth",
    ParamType::Integer,
    DefaultValue::Int(-1),
    "longest path, in segments; −1 is unbounded",
);
pub(super) const RR_DEPTH: ParamSpec = ParamSpec::new(
    "rr_depth",
    ParamType::Integer,
    DefaultValue::Int(5),
    "path depth at which Russian roulette starts (≥ 1)",
);
const RR_SURVIVAL: ParamSpec = ParamSpec::new(
    "rr_survival",
    ParamType::Float,
    DefaultValue::Float(0.99),
    "(ours) highest probability with which Russian roulette continues a path, in (0, 1): light trapped in glass by total internal reflection is not boosted into fireflies",
)
.mitsuba(DefaultValue::Float(0.95));
const RR_SCALE: ParamSpec = ParamSpec::new(
    "rr_scale",
    ParamType::Float,
    DefaultValue::Float(4.0),
    "(ours) Russian roulette continues a path with probability min(`rr_scale`·max(β)·η², `rr_survival`): paths whose throughput β is above 1/`rr_scale` go on. Mitsuba's and pbrt-v4's 1 makes a path as likely to go on as its throughput, but a pixel's value is its first surface's albedo times the light arriving there, so at albedos of ¼ to ½ the light a path still gathers is several times the pixel's value and the variance of early kills outweighs the time they save; a positive number",
)
.mitsuba(DefaultValue::Float(1.0));
pub(super) const HIDE_EMITTERS: ParamSpec = ParamSpec::new(
    "hide_emitters",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "hide directly visible emitters",
);
const THIN_SHADOWS: ParamSpec = ParamSpec::new(
    "thin_shadows",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) shadow rays cross null surfaces and `thindielectric` sheets, attenuated by their transmittance, and a path's straight pass through one counts no segment (at most 64 per segment)",
)
.mitsuba(DefaultValue::Bool(false));
const CAUSTIC_PATHS: ParamSpec = ParamSpec::new(
    "caustic_paths",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) light subpaths for caustics, weighted by MIS against the path tracer",
)
.mitsuba(DefaultValue::Bool(false));
const REFRACTED_NEE: ParamSpec = ParamSpec::new(
    "refracted_nee",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) next-event estimation follows shadow rays through smooth glass, refracting, weighted by MIS",
)
.mitsuba(DefaultValue::Bool(false));
const MANIFOLD_NEE: ParamSpec = ParamSpec::new(
    "manifold_nee",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) caustics seen through delta surfaces: a light sample reflected by a mirror sphere (manifold next-event estimation), weighted by MIS",
)
.mitsuba(DefaultValue::Bool(false));
const SPLIT_ESCAPES: ParamSpec = ParamSpec::new(
    "split_escapes",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) at glass, instead of choosing reflection or refraction by Fresnel alone: a reflection or refraction of rough glass that leaves the scene is added whole and the path follows the other lobe; an area light met by the outward lobe of smooth or rough glass, or by a `plastic` coat's mirror reflection (a glint), adds its emission whole",
)
.mitsuba(DefaultValue::Bool(false));
const SPLIT_VISIBLE_GLASS: ParamSpec = ParamSpec::new(
    "split_visible_glass",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) where the camera sees smooth glass (`dielectric`, `thindielectric`) directly, both its reflection and its refraction are followed, each weighted by its Fresnel factor, instead of one chosen by Fresnel (spectral renders; not dispersive glass while the secondary wavelengths live)",
)
.mitsuba(DefaultValue::Bool(false));
const SPLIT_LIGHTS: ParamSpec = ParamSpec::new(
    "split_lights",
    ParamType::Integer,
    DefaultValue::Int(2),
    "(ours) next-event estimation samples every light at each vertex when the scene has at most this many; 0 chooses one per vertex",
)
.mitsuba(DefaultValue::Int(0));
const NARROW_LOBES: ParamSpec = ParamSpec::new(
    "narrow_lobes",
    ParamType::Boolean,
    DefaultValue::Bool(true),
    "(ours) a light at infinity whose radiance has no feature as narrow as the lobe of a single-scattering `roughconductor` or `roughdielectric` (or the side of a `twosided` a ray meets, when a `roughconductor`) is not sampled at that surface: BSDF sampling alone finds it, weighted 1 (the light's largest density max L/∫L dω at most 0.05 (Beckmann) or 0.005 (GGX) times the lobe's peak 1/(4π α_u α_v): under Mitsuba's `museum.exr` Beckmann α ≤ 0.028, GGX α ≤ 0.0087)",
)
.mitsuba(DefaultValue::Bool(false));
const RIS_CANDIDATES: ParamSpec = ParamSpec::new(
    "ris_candidates",
    ParamType::Integer,
    DefaultValue::Int(8),
    "(ours) where the scene has one `envmap` and the surface is a single-scattering `roughconductor` of narrow lobe (α_u, α_v ≤ 0.15; either side of a `twosided`), next-event estimation of the map resamples this many directions drawn from the lobe's normals by a coarse estimate of f·cos θ·L and traces one shadow ray (resampled importance sampling, Talbot et al. 2005), which alone then adds the map's direct light there (spectral renders, not where `narrow_lobes` leaves the map to BSDF sampling); 0 takes one light sample and one BSDF sample weighed by MIS; from 0 to 64",
)
.mitsuba(DefaultValue::Int(0));
const MIS_EXPONENT: ParamSpec = ParamSpec::new(
    "mis_exponent",
    ParamType::Float,
    DefaultValue::Float(1.25),
    "(ours) exponent β of the power heuristic that weighs next-event estimation against BSDF sampling (Veach 1997 §9.2: 2 is Mitsuba's, 1 the balance heuristic); from 1 to 16",
)
.mitsuba(DefaultValue::Float(2.0));
pub(super) const SAMPLES_PER_PASS: ParamSpec = ParamSpec::new(
    "samples_per_pass",
    ParamType::Integer,
    DefaultValue::Int(-1),
    "accepted and ignored (gonio renders in passes of its own)",
);
pub(super) const TIMEOUT: ParamSpec = ParamSpec::new(
    "timeout",
    ParamType::Float,
    DefaultValue::Float(-1.0),
    "accepted and ignored",
);

/// The `path` plugin.
pub static PLUGIN: Plugin<IntegratorDesc> = Plugin {
    name: "path",
    summary: "Path tracer: emission and next-event estimation combined by MIS (power heuristic), BSDF sampling, Russian roulette.",
    params: &[
        MAX_DEPTH,
        RR_DEPTH,
        RR_SURVIVAL,
        RR_SCALE,
        HIDE_EMITTERS,
        THIN_SHADOWS,
        CAUSTIC_PATHS,
        REFRACTED_NEE,
        MANIFOLD_NEE,
        SPLIT_ESCAPES,
        SPLIT_VISIBLE_GLASS,
        SPLIT_LIGHTS,
        NARROW_LOBES,
        RIS_CANDIDATES,
        MIS_EXPONENT,
        SAMPLES_PER_PASS,
        TIMEOUT,
    ],
    build,
};

/// Reads the rows a path-like integrator shares with `path`: `max_depth` (its own row, whose
/// text differs per plugin), `rr_depth`, `hide_emitters` and the ignored `samples_per_pass`.
pub(super) fn read_path_rows(
    p: &mut Params<'_>,
    max_depth: &ParamSpec,
) -> Result<(i32, u32, bool), SceneError> {
    let depth = p.int_in(max_depth.name, max_depth.default.int(), -1, i32::MAX as i64)? as i32;
    let rr_depth = p.int_in(RR_DEPTH.name, RR_DEPTH.default.int(), 1, u32::MAX as i64)? as u32;
    let hide_emitters = p.bool(HIDE_EMITTERS.name, HIDE_EMITTERS.default.bool())?;
    p.int_in(
        SAMPLES_PER_PASS.name,
        SAMPLES_PER_PASS.default.int(),
        -1,
        i64::MAX,
    )?;
    Ok((depth, rr_depth, hide_emitters))
}

/// `desc` with the defaults of our estimator rows (`thin_shadows` … `narrow_lobes`) for this
/// document: ours, or Mitsuba's under `--mitsuba-estimators`. For integrators that render as
/// the path tracer without these rows (Mitsuba's `prb` family).
pub(super) fn with_estimator_defaults(p: &Params<'_>, desc: IntegratorDesc) -> IntegratorDesc {
    IntegratorDesc {
        rr_survival: p.default_of(&RR_SURVIVAL).float() as f32,
        rr_scale: p.default_of(&RR_SCALE).float() as f32,
        thin_shadows: p.default_of(&THIN_SHADOWS).bool(),
        caustic_paths: p.default_of(&CAUSTIC_PATHS).bool(),
        refracted_nee: p.default_of(&REFRACTED_NEE).bool(),
        manifold_nee: p.default_of(&MANIFOLD_NEE).bool(),
        split_escapes: p.default_of(&SPLIT_ESCAPES).bool(),
        split_visible_glass: p.default_of(&SPLIT_VISIBLE_GLASS).bool(),
        split_lights: p.default_of(&SPLIT_LIGHTS).int() as u32,
        narrow_lobes: p.default_of(&NARROW_LOBES).bool(),
        ris_candidates: p.default_of(&RIS_CANDIDATES).int() as u32,
        mis_exponent: p.default_of(&MIS_EXPONENT).float() as f32,
        ..desc
    }
}

fn build<'d>(_: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let (max_depth, rr_depth, hide_emitters) = read_path_rows(p, &MAX_DEPTH)?;
    let rr_survival = p.float_checked(
        RR_SURVIVAL.name,
        p.default_of(&RR_SURVIVAL).float(),
        |v| v > 0.0 && v < 1.0,
        "a probability above 0 and below 1",
    )? as f32;
    let rr_scale = p.float_checked(
        RR_SCALE.name,
        p.default_of(&RR_SCALE).float(),
        |v| v > 0.0 && v.is_finite(),
        "a positive number",
    )? as f32;
    let thin_shadows = p.bool(THIN_SHADOWS.name, p.default_of(&THIN_SHADOWS).bool())?;
    let caustic_paths = p.bool(CAUSTIC_PATHS.name, p.default_of(&CAUSTIC_PATHS).bool())?;
    let refracted_nee = p.bool(REFRACTED_NEE.name, p.default_of(&REFRACTED_NEE).bool())?;
    let manifold_nee = p.bool(MANIFOLD_NEE.name, p.default_of(&MANIFOLD_NEE).bool())?;
    let split_escapes = p.bool(SPLIT_ESCAPES.name, p.default_of(&SPLIT_ESCAPES).bool())?;
    let split_visible_glass = p.bool(
        SPLIT_VISIBLE_GLASS.name,
        p.default_of(&SPLIT_VISIBLE_GLASS).bool(),
    )?;
    let split_lights = p.int_in(SPLIT_LIGHTS.name, p.default_of(&SPLIT_LIGHTS).int(), 0, 1024)? as u32;
    let narrow_lobes = p.bool(NARROW_LOBES.name, p.default_of(&NARROW_LOBES).bool())?;
    let ris_candidates = p.int_in(
        RIS_CANDIDATES.name,
        p.default_of(&RIS_CANDIDATES).int(),
        0,
        crate::integrator::MAX_RIS_CANDIDATES as i64,
    )? as u32;
    let mis_exponent = p.float_checked(
        MIS_EXPONENT.name,
        p.default_of(&MIS_EXPONENT).float(),
        |v| (1.0..=16.0).contains(&v),
        "a number from 1 to 16",
    )? as f32;
    p.float(TIMEOUT.name, TIMEOUT.default.float())?;
    Ok(IntegratorDesc {
        max_depth,
        rr_depth,
        rr_survival,
        rr_scale,
        hide_emitters,
        volumetric: false,
        thin_shadows,
        caustic_paths,
        refracted_nee,
        manifold_nee,
        split_escapes,
        split_visible_glass,
        split_lights,
        narrow_lobes,
        ris_candidates,
        mis_exponent,
        kind: IntegratorKind::Path,
        stokes: false,
        polarized: false,
        layers: None,
    })
}
