//! `twosided`: a one-sided BSDF on both faces, or one BSDF per face (core adapter
//! [`gonio_core::bsdfs::TwoSided`]; Mitsuba 3 `src/bsdfs/twosided.cpp`).

use super::{BsdfPlugin, DefaultValue, Material, ParamSpec, ParamType, ShadingPoint, SurfaceMaterial};
use crate::xml::{Builder, ErrorKind, Params, SceneError, Tag};
use glam::Vec2;
use gonio_core::bsdfs::surface::TooManyNodes;
use gonio_core::bsdfs::{SurfaceBsdf, TwoSided};
use gonio_core::{Bsdf, BsdfFlags, SampledWavelengths};

const ALLOW_TRANSMISSION: ParamSpec = ParamSpec::new(
    "allow_transmission",
    ParamType::Boolean,
    DefaultValue::Bool(false),
    "accept nested BSDFs that transmit (a transmission of the front leaves through the back face)",
);
const NESTED: ParamSpec = ParamSpec::new(
    "(nested bsdf)",
    ParamType::Bsdf,
    DefaultValue::None,
    "one (both faces) or two (front, back) nested BSDFs",
);

/// The `twosided` plugin.
pub static PLUGIN: BsdfPlugin = BsdfPlugin {
    name: "twosided",
    summary: "Two-sided wrapper: the front BSDF where the normal points to the viewer, the back one (mirrored) on the other face.",
    params: &[ALLOW_TRANSMISSION, NESTED],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Material, SceneError> {
    let allow = p.bool(ALLOW_TRANSMISSION.name, ALLOW_TRANSMISSION.default.bool())?;
    let kids = p.objects(Tag::Bsdf)?;
    let obj = b.object(p);
    if kids.is_empty() || kids.len() > 2 {
        return Err(SceneError::new(
            obj.loc.clone(),
            ErrorKind::Grammar,
            format!("twosided needs one or two nested BSDFs, found {}", kids.len()),
        ));
    }
    let mut built = Vec::new();
    for (k, prop) in &kids {
        let m = b.bsdf(*k, &prop.value_loc)?;
        if !allow && m.has_transmission() {
            return Err(SceneError::new(
                prop.loc.clone(),
                ErrorKind::BadValue,
                format!(
                    "twosided cannot wrap the transmitting <bsdf type=\"{}\"> (set allow_transmission)",
                    b.doc.objs[*k].ty
                ),
            ));
        }
        built.push(m);
    }
    let back = if built.len() == 2 { built.pop() } else { None };
    let front = built.pop().expect("one child at least");
    Ok(Material::new(TwoSidedMaterial { front, back }))
}

/// `twosided` in a scene.
#[derive(Clone, Debug)]
pub struct TwoSidedMaterial {
    /// Front (and back if `back` is none).
    pub front: Material,
    /// Back side, if different.
    pub back: Option<Material>,
}

impl SurfaceMaterial for TwoSidedMaterial {
    fn flags(&self) -> BsdfFlags {
        self.front.flags() | self.back.as_ref().map_or(BsdfFlags::NONE, Material::flags)
    }
    fn is_textured(&self) -> bool {
        self.front.is_textured() || self.back.as_ref().is_some_and(Material::is_textured)
    }
    fn node_count(&self) -> usize {
        1 + self.front.as_surface().node_count()
            + self.back.as_ref().map_or(0, |b| b.as_surface().node_count())
    }
    fn asks_for_polarization(&self) -> bool {
        self.front.as_surface().asks_for_polarization()
            || self
                .back
                .as_ref()
                .is_some_and(|b| b.as_surface().asks_for_polarization())
    }
    fn push<'a>(
        &'a self,
        uv: Vec2,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let front = self.front.as_surface().push(uv, wl, tree)?;
        let back = match &self.back {
            Some(b) => b.as_surface().push(uv, wl, tree)?,
            None => front,
        };
        tree.push_two_sided(front, back)
    }
    fn push_at<'a>(
        &'a self,
        at: &ShadingPoint,
        wl: &SampledWavelengths,
        tree: &mut SurfaceBsdf<'a>,
    ) -> Result<u8, TooManyNodes> {
        let front = self.front.as_surface().push_at(at, wl, tree)?;
        let back = match &self.back {
            Some(b) => b.as_surface().push_at(at, wl, tree)?,
            None => front,
        };
        tree.push_two_sided(front, back)
    }
    fn visit(&self, uv: Vec2, f: &mut dyn FnMut(&dyn Bsdf)) {
        self.front
            .as_surface()
            .visit(uv, &mut |fb: &dyn Bsdf| match &self.back {
                Some(back) => back
                    .as_surface()
                    .visit(uv, &mut |bb: &dyn Bsdf| f(&TwoSided { front: fb, back: bb })),
                None => f(&TwoSided { front: fb, back: fb }),
            })
    }
}
