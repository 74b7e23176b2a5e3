//! `aov`: arbitrary output variables (Mitsuba 3 `src/integrators/aov.cpp`): nested integrators'
//! images and values read at the first surface a camera ray hits, written as film layers. The
//! channels, their order and their values are in `crate::integrator::layers`.
//!
//! | parameter | meaning |
//! |---|---|
//! | `aovs` | `name:type` pairs separated by commas or spaces; types `depth`, `position`, `uv`, `geo_normal`, `sh_normal`, `dp_du`, `dp_dv`, `duv_dx`, `duv_dy`, `prim_index`, `shape_index` |
//! | (nested `<integrator>`s) | integrators whose images become the layers `name.R, .G, .B, .A` (named by their `name` attribute, `_arg_N` when unnamed); the first one's image is the film's `R, G, B` |

use crate::plugins::{DefaultValue, INTEGRATOR_PLUGINS, ParamSpec, ParamType, Plugin};
use crate::scene::{AovType, IntegratorDesc, LayersDesc, NestedIntegrator};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag, err};

const AOVS: ParamSpec = ParamSpec::new(
    "aovs",
    ParamType::String,
    DefaultValue::None,
    "`name:type` pairs, comma or space separated (`dd.y:depth, nn:sh_normal`); types: depth, position, uv, geo_normal, sh_normal, dp_du, dp_dv, duv_dx, duv_dy, prim_index, shape_index",
);

/// The `aov` plugin.
pub static PLUGIN: Plugin<IntegratorDesc> = Plugin {
    name: "aov",
    summary: "Arbitrary output variables: nested integrators' images and the first hit's depth, position, uv, normals, derivatives and indices, as extra film layers.",
    params: &[AOVS],
    build,
};

/// Parses Mitsuba's `aovs` string: tokens separated by commas and white space, each exactly
/// `name:type` with both parts non-empty. `Err` carries the message (the caller adds where).
pub fn parse_aovs(value: &str) -> Result<Vec<(String, AovType)>, String> {
    let mut out: Vec<(String, AovType)> = Vec::new();
    for token in value
        .split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
    {
        let mut parts = token.split(':');
        let (Some(name), Some(ty), None) = (parts.next(), parts.next(), parts.next()) else {
            return Err(format!(
                "aovs \"{value}\": \"{token}\" is not a <name>:<type> pair"
            ));
        };
        if name.is_empty() || ty.is_empty() {
            return Err(format!(
                "aovs \"{value}\": \"{token}\" is not a <name>:<type> pair (empty name or type)"
            ));
        }
        let Some(&(_, t)) = AovType::ALL.iter().find(|(n, _)| *n == ty) else {
            let known: Vec<&str> = AovType::ALL.iter().map(|(n, _)| *n).collect();
            let mitsuba_only = ["albedo", "boundary_test"].contains(&ty);
            return Err(format!(
                "aovs \"{value}\": {} AOV type \"{ty}\" (gonio knows: {})",
                if mitsuba_only { "unsupported" } else { "unknown" },
                known.join(", ")
            ));
        };
        if out.iter().any(|(n, _)| n == name) {
            return Err(format!("aovs \"{value}\": the name \"{name}\" is used twice"));
        }
        out.push((name.to_string(), t));
    }
    Ok(out)
}

/// The integrators nested in `p` with their layer names (the `name` attribute, `_arg_N` when
/// unnamed), in document order: Mitsuba 3.9.1's `aov` and `moment` take their children in the
/// order written (a `direct` named `b` before a `path` named `a` gives `b.R` … before `a.R` …).
pub(super) fn nested_integrators<'d>(
    b: &mut Builder<'d>,
    p: &mut Params<'d>,
) -> Result<Vec<NestedIntegrator>, SceneError> {
    let mut out = Vec::new();
    let mut children = p.objects(Tag::Integrator)?;
    let props = &p.obj.props;
    children.sort_by_key(|(_, prop)| props.iter().position(|q| std::ptr::eq(q, *prop)));
    for (i, prop) in children {
        let desc = b.build_plugin(INTEGRATOR_PLUGINS, i)?;
        out.push(NestedIntegrator {
            name: prop.name.clone(),
            desc,
        });
    }
    Ok(out)
}

/// The settings of a wrapper: the first nested integrator's (whose image is the film's), with
/// the layers.
pub(super) fn wrapper(nested: &[NestedIntegrator], layers: LayersDesc) -> IntegratorDesc {
    let first = nested.first().map(|n| n.desc.clone()).unwrap_or_default();
    IntegratorDesc {
        layers: Some(Box::new(layers)),
        ..first
    }
}

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<IntegratorDesc, SceneError> {
    let Some((value, loc)) = p.string_opt(AOVS.name)? else {
        return Err(err(
            &p.obj.loc,
            ErrorKind::BadValue,
            "<integrator type=\"aov\"> needs the string \"aovs\" (e.g. \"dd:depth, nn:sh_normal\")",
        ));
    };
    let aovs = parse_aovs(value).map_err(|m| err(loc, ErrorKind::BadValue, m))?;
    let nested = nested_integrators(b, p)?;
    if aovs.is_empty() && nested.is_empty() {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!(
                "<integrator type=\"aov\"> with no AOV in \"{value}\" and no nested integrator writes nothing"
            ),
        ));
    }
    let layers = LayersDesc::Aov {
        nested: nested.clone(),
        aovs,
    };
    Ok(wrapper(&nested, layers))
}
