//! The lights of a scene: area and directional-area lights on emitting shapes (in shape order),
//! then the scene's other emitters (in file order), checked and converted once when a scene is
//! prepared.

use super::directional_area::Footprint;
use super::{
    AreaLight, BoundingSphere, ConstantLight, DirectionalAreaLight, DirectionalLight, EnvMapLight, Light,
    Lights, PointLight, SpotLight,
};
use crate::geometry::WorldShape;
use crate::scene::{EmitterDesc, Scene, SurfaceEmission};
use glam::Vec3;

/// An emitter whose parameters cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("emitter {index}: {message}")]
pub struct EmitterError {
    /// Index of the emitter among the scene's emitters.
    pub index: usize,
    /// What went wrong.
    pub message: String,
}

impl BoundingSphere {
    /// The bounding sphere of an axis-aligned box (a unit sphere at the origin when the box is
    /// empty or not finite).
    pub fn from_box(min: Vec3, max: Vec3) -> Self {
        if !(min.is_finite() && max.is_finite()) || min.cmpgt(max).any() {
            return Self {
                center: Vec3::ZERO,
                radius: 1.0,
            };
        }
        let center = 0.5 * (min + max);
        Self {
            center,
            radius: (0.5 * (max - min).length()).max(1e-3),
        }
    }

    /// The bounding sphere of the bounding box of shapes' primitives.
    pub fn of_shapes<'a>(shapes: impl IntoIterator<Item = &'a WorldShape>) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for s in shapes {
            for prim in 0..s.prim_count() {
                let (a, b) = s.prim_bounds(prim);
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
        Self::from_box(lo, hi)
    }
}

impl Light {
    /// The light of one of the scene's emitters (not area lights, which live on shapes).
    pub fn from_emitter(e: &EmitterDesc) -> Result<Self, String> {
        Ok(match e {
            EmitterDesc::Point { position, intensity } => Light::Point(PointLight {
                position: *position,
                intensity: intensity.clone(),
            }),
            EmitterDesc::Spot {
                to_world,
                intensity,
                cutoff_angle_deg,
                beam_width_deg,
                texture,
            } => {
                if to_world.matrix3.determinant() == 0.0 {
                    return Err("singular to_world".into());
                }
                Light::Spot(
                    SpotLight::new(*to_world, intensity.clone(), *cutoff_angle_deg, *beam_width_deg)
                        .with_texture(texture.clone()),
                )
            }
            EmitterDesc::Projector {
                to_world,
                irradiance,
                scale,
                fov_x_deg,
                aspect,
                whitepoint,
            } => {
                if to_world.matrix3.determinant() == 0.0 {
                    return Err("singular to_world".into());
                }
                let light =
                    super::ProjectorLight::new(*to_world, irradiance.clone(), *scale, *fov_x_deg, *aspect);
                Light::Projector(if *whitepoint {
                    light
                } else {
                    light.without_whitepoint()
                })
            }
            EmitterDesc::Directional {
                direction,
                irradiance,
            } => {
                let d = direction.normalize_or_zero();
                if d == Vec3::ZERO {
                    return Err("zero direction".into());
                }
                Light::Directional(DirectionalLight {
                    direction: d,
                    irradiance: irradiance.clone(),
                })
            }
            EmitterDesc::Constant { radiance } => Light::Constant(ConstantLight {
                radiance: radiance.clone(),
            }),
            EmitterDesc::SunSky { params, to_world } => {
                let model = super::sunsky::model(params)?;
                Light::SunSky(
                    super::SunSkyLight::new(model, *to_world)
                        .ok_or_else(|| "singular to_world".to_string())?,
                )
            }
            EmitterDesc::EnvMap {
                image,
                scale,
                to_world,
                mitsuba_lookup,
                mis_compensation,
                product_sampling,
            } => {
                let env = EnvMapLight::new(
                    image.width,
                    image.height,
                    image.data.clone(),
                    *scale,
                    *to_world,
                    crate::texture::uplift_emission_texel,
                )
                .ok_or_else(|| "empty environment image or singular to_world".to_string())?;
                let env = if *mitsuba_lookup {
                    env.with_mitsuba_lookup()
                } else {
                    env
                };
                let env = if *mis_compensation {
                    env.with_mis_compensation()
                } else {
                    env
                };
                Light::EnvMap(if *product_sampling {
                    env.with_product_sampling()
                } else {
                    env
                })
            }
        })
    }
}

impl Lights {
    /// The lights of `scene`, whose shapes placed in the world are `world` (same order).
    pub fn from_scene(scene: &Scene, world: &[WorldShape]) -> Result<Self, EmitterError> {
        let scene_area: f32 = world.iter().map(|s| s.area()).filter(|a| a.is_finite()).sum();
        let bounds = BoundingSphere::of_shapes(world);
        let mut lights = Vec::new();
        for (index, (shape, w)) in scene.shapes.iter().zip(world).enumerate() {
            if let Some(em) = &shape.emitter {
                let sphere = BoundingSphere::of_shapes([w]);
                let surface = AreaLight {
                    shape: index,
                    radiance: em.radiance.clone(),
                    area: w.area(),
                    mean_radiance: em
                        .hit
                        .as_ref()
                        .and_then(|hit| super::area::surface_mean(&em.radiance, hit, w))
                        .unwrap_or_else(|| em.radiance.mean()),
                    center: sphere.center,
                    radius: sphere.radius,
                    hit: em.hit.clone(),
                };
                lights.push(match em.emission {
                    SurfaceEmission::Diffuse => Light::Area(surface),
                    SurfaceEmission::Directional { next_event } => {
                        Light::DirectionalArea(DirectionalAreaLight {
                            surface,
                            footprint: next_event.then(|| Footprint::of(w)).flatten(),
                        })
                    }
                });
            }
        }
        for (index, e) in scene.emitters.iter().enumerate() {
            lights.push(Light::from_emitter(e).map_err(|message| EmitterError { index, message })?);
        }
        Ok(Lights::new(lights, world.len(), scene_area, bounds).with_split(scene.integrator.split_lights))
    }
}
