//! `mesh_attribute`: a vertex or face attribute of the mesh hit as a texture (Mitsuba 3
//! `src/textures/mesh_attribute.cpp`; runtime and formula in [`crate::texture::hit`]).

use crate::material::Material;
use crate::plugins::{DefaultValue, ParamSpec, ParamType, Plugin};
use crate::scene::Geometry;
use crate::texture::Texture;
use crate::texture::hit::{AttributeTexture, HitBinding, HitBound};
use crate::xml::{Builder, ErrorKind, Location, Params, SceneError, err};
use std::sync::Arc;

const NAME: ParamSpec = ParamSpec::new(
    "name",
    ParamType::String,
    DefaultValue::None,
    "the attribute, `vertex_…` (interpolated over the triangle) or `face_…` (required)",
);
const SCALE: ParamSpec = ParamSpec::new(
    "scale",
    ParamType::Float,
    DefaultValue::Float(1.0),
    "factor applied to the attribute's value",
);

/// The `mesh_attribute` plugin.
pub static PLUGIN: Plugin<Texture> = Plugin {
    name: "mesh_attribute",
    summary: "A mesh's vertex or face attribute (PLY properties, e.g. `vertex_color`) at the hit; only on meshes.",
    params: &[NAME, SCALE],
    build,
};

fn build<'d>(b: &mut Builder<'d>, p: &mut Params<'d>) -> Result<Texture, SceneError> {
    let obj = p.obj;
    let Some((name, loc)) = p.string_opt(NAME.name)? else {
        return Err(err(
            &obj.loc,
            ErrorKind::Grammar,
            "<texture type=\"mesh_attribute\"> needs a name",
        ));
    };
    if !(name.starts_with("vertex_") || name.starts_with("face_")) {
        return Err(err(
            loc,
            ErrorKind::BadValue,
            format!("invalid mesh attribute name \"{name}\": it must start with \"vertex_\" or \"face_\""),
        ));
    }
    let scale = p.float_checked(SCALE.name, SCALE.default.float(), |_| true, "finite")? as f32;
    b.note_hit_texture(Some(name), loc);
    Ok(Texture::MeshAttribute(Arc::new(AttributeTexture {
        name: name.to_owned(),
        scale,
    })))
}

/// The material of a shape (`material`, built from the BSDF object `bsdf`): itself, or, when its
/// textures read the hit (`mesh_attribute`, `volume`), a new material bound to this shape's
/// geometry ([`HitBound`]). A `mesh_attribute` on a shape that is not a mesh, an attribute the
/// mesh lacks, or one of 4 values is an error naming the texture's `name`.
pub(crate) fn bind(
    b: &mut Builder<'_>,
    material: usize,
    bsdf: Option<usize>,
    geometry: &Geometry,
    shape_type: &str,
) -> Result<usize, SceneError> {
    let Some(reqs) = bsdf.and_then(|i| b.hit_bsdfs.get(&i)).cloned() else {
        return Ok(material);
    };
    let binding = binding(b, &reqs, geometry, shape_type)?;
    let inner = b.material(material);
    Ok(b.add_material(Material::new(HitBound::new(inner, binding))))
}

/// What the textures that read the hit, logged as `reqs` (each `mesh_attribute`'s name and
/// location; `None` for a `volume`), need of the shape `geometry`: its mesh with the attributes
/// they name. Errors as [`bind`]'s, located at the texture's `name`.
pub(crate) fn binding(
    b: &Builder<'_>,
    reqs: &[(Option<String>, Location)],
    geometry: &Geometry,
    shape_type: &str,
) -> Result<HitBinding, SceneError> {
    let names: Vec<_> = reqs
        .iter()
        .filter_map(|(n, loc)| n.as_deref().map(|n| (n, loc)))
        .collect();
    let mesh = match (names.first(), geometry) {
        (None, _) => None,
        (Some(_), Geometry::Mesh(m)) => {
            let attrs = b.mesh_attributes.get(&(Arc::as_ptr(m) as usize));
            for &(n, loc) in &names {
                match attrs.and_then(|a| a.get(n)) {
                    None => {
                        let have = attrs.map(|a| a.names().join(", ")).unwrap_or_default();
                        return Err(err(
                            loc,
                            ErrorKind::BadValue,
                            format!(
                                "mesh attribute \"{n}\" not found on the <shape type=\"{shape_type}\"> it textures (its attributes: {})",
                                if have.is_empty() { "none" } else { &have }
                            ),
                        ));
                    }
                    Some(a) if a.dim != 1 && a.dim != 3 => {
                        return Err(err(
                            loc,
                            ErrorKind::BadValue,
                            format!(
                                "mesh attribute \"{n}\" has {} values per element; mesh_attribute reads 1 or 3",
                                a.dim
                            ),
                        ));
                    }
                    Some(_) => {}
                }
            }
            let wanted: Vec<&str> = names.iter().map(|(n, _)| *n).collect();
            Some((m.clone(), attrs.map(|a| a.pick(&wanted)).unwrap_or_default()))
        }
        (Some(&(name, loc)), _) => {
            return Err(err(
                loc,
                ErrorKind::BadValue,
                format!(
                    "mesh_attribute texture \"{name}\" on a <shape type=\"{shape_type}\">, which is not a mesh (attributes come with ply meshes)"
                ),
            ));
        }
    };
    Ok(HitBinding { mesh })
}
