//! The canonical scenes of `testdata/mitsuba/scenes/` load with the expected contents.

use glam::{Vec2, Vec3};
use gonio_core::{Ior, Spectrum};
use gonio_render::material::{
    ConductorMaterial, DielectricMaterial, DiffuseMaterial, PlasticMaterial, ThinDielectricMaterial,
};
use gonio_render::scene::{EmitterDesc, FilterDesc, Geometry, SamplerKind, Scene};
use gonio_render::texture::Texture;
use gonio_render::xml::{load_scene_file, load_scene_file_with_warnings};
use std::path::PathBuf;

fn scene_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/mitsuba/scenes")
        .join(name)
}

fn load(name: &str) -> Scene {
    let l = load_scene_file_with_warnings(scene_path(name), &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(
        l.warnings.is_empty(),
        "{name}: unexpected warnings {:?}",
        l.warnings
    );
    l.scene
}

fn constant(t: &Texture) -> f32 {
    t.as_spectrum()
        .and_then(Spectrum::as_constant)
        .expect("a constant texture")
}

#[test]
fn materials_scene() {
    let s = load("materials.xml");
    assert_eq!(s.integrator.max_depth, 16);
    assert_eq!(s.integrator.rr_depth, 5);
    assert!(!s.integrator.hide_emitters);
    assert!(s.integrator.thin_shadows);
    assert_eq!((s.sensor.film.width, s.sensor.film.height), (480, 200));
    assert_eq!(s.sensor.film.filter, FilterDesc::Box { radius: 0.5 });
    assert_eq!(s.sensor.sampler.sample_count, 64);
    assert_eq!(s.sensor.sampler.kind, SamplerKind::Independent);
    assert_eq!(s.sensor.fov_x_deg, 32.0);
    assert!((s.sensor.near_clip - 0.01).abs() < 1e-9 && s.sensor.far_clip == 10000.0);
    // Camera at (0, 3.5, 19) looking at (0, 0.9, 0): +z of camera space is the view direction.
    let origin = s.sensor.to_world.transform_point3(Vec3::ZERO);
    assert!((origin - Vec3::new(0.0, 3.5, 19.0)).length() < 1e-5);
    let dir = s.sensor.to_world.transform_vector3(Vec3::Z);
    let want = (Vec3::new(0.0, 0.9, 0.0) - origin).normalize();
    assert!((dir - want).length() < 1e-5);

    // 5 spheres, floor, light.
    assert_eq!(s.shapes.len(), 7);
    assert_eq!(
        s.shapes
            .iter()
            .filter(|x| matches!(x.geometry, Geometry::Sphere { .. }))
            .count(),
        5
    );
    assert_eq!(s.shapes.iter().filter(|x| x.emitter.is_some()).count(), 1);
    assert_eq!(s.emitters.len(), 1);
    assert!(matches!(s.emitters[0], EmitterDesc::Constant { .. }));

    let mat = |i: usize| &s.materials[s.shapes[i].material];
    let Geometry::Sphere { center, radius } = s.shapes[0].geometry else {
        panic!()
    };
    assert_eq!((center, radius), (Vec3::new(-4.4, 1.0, 0.0), 1.0));
    // matte: rgb (0.7, 0.25, 0.2) uplifted as a reflectance: red > green at the right wavelengths.
    let Some(DiffuseMaterial { reflectance, .. }) = mat(0).get() else {
        panic!("{:?}", mat(0))
    };
    let r = reflectance.as_spectrum().unwrap();
    assert!(r.eval(650.0) > 0.5 && r.eval(530.0) < 0.35, "{r:?}");
    // mirror: η = 0, k = 1.
    let Some(ConductorMaterial { model, .. }) = mat(1).get() else {
        panic!()
    };
    assert_eq!(
        (model.eta.as_constant(), model.k.as_constant()),
        (Some(0.0), Some(1.0))
    );
    // gold: tabulated η, k.
    let Some(ConductorMaterial { model, .. }) = mat(2).get() else {
        panic!()
    };
    assert!(model.eta.as_constant().is_none() && model.k.eval(600.0) > 2.0);
    // glass 1.5 / 1.0.
    let Some(DielectricMaterial { model, .. }) = mat(3).get() else {
        panic!()
    };
    assert_eq!(
        (&model.int_ior, &model.ext_ior),
        (&Ior::Constant(1.5), &Ior::Constant(1.0))
    );
    // coated: plastic, int_ior 1.5, default ext_ior air.
    let Some(PlasticMaterial {
        model,
        diffuse_reflectance,
        ..
    }) = mat(4).get()
    else {
        panic!()
    };
    assert_eq!(model.int_ior(), 1.5);
    assert!((model.ext_ior() - 1.000277).abs() < 1e-7);
    assert!(!model.nonlinear);
    assert!(diffuse_reflectance.as_spectrum().unwrap().eval(460.0) > 0.4);
    // Floor checkerboard 0.2 / 0.6 scaled 12×.
    let Some(DiffuseMaterial {
        reflectance: Texture::Checkerboard { to_uv, .. },
        ..
    }) = mat(5).get()
    else {
        panic!()
    };
    assert_eq!(to_uv.transform_point2(Vec2::new(1.0, 1.0)), Vec2::new(12.0, 12.0));
    // Light: rectangle emitting rgb 6 × D65: its spectrum is not flat (D65 shape).
    let light = s.shapes.iter().find(|x| x.emitter.is_some()).unwrap();
    let l = light.emitter.as_ref().unwrap().radiance.as_spectrum().unwrap();
    assert!(l.as_constant().is_none() && l.eval(560.0) > 4.0);
    // The emitter has no BSDF: default black diffuse.
    let Some(DiffuseMaterial { reflectance, .. }) = s.materials[light.material].get() else {
        panic!()
    };
    assert_eq!(constant(reflectance), 0.0);
}

#[test]
fn furnace_scene() {
    let s = load("furnace.xml");
    assert_eq!(s.integrator.max_depth, -1);
    assert_eq!(s.integrator.rr_depth, 1000);
    assert_eq!((s.sensor.film.width, s.sensor.film.height), (256, 128));
    assert_eq!(s.shapes.len(), 3);
    assert_eq!(s.materials.len(), 3);
    let Some(DiffuseMaterial { reflectance, .. }) = s.materials[s.shapes[0].material].get() else {
        panic!()
    };
    // A white rgb reflectance is exactly 1 at every wavelength.
    for l in [360.0, 450.0, 550.0, 700.0, 830.0] {
        assert!((reflectance.as_spectrum().unwrap().eval(l) - 1.0).abs() < 1e-4);
    }
    assert!(
        s.materials[s.shapes[1].material]
            .get::<DielectricMaterial>()
            .is_some()
    );
    assert!(
        s.materials[s.shapes[2].material]
            .get::<ThinDielectricMaterial>()
            .is_some()
    );
    let EmitterDesc::Constant { radiance } = &s.emitters[0] else {
        panic!()
    };
    assert_eq!(radiance, &Spectrum::d65());
}

#[test]
fn thin_vs_thick_scene() {
    let s = load("thin-vs-thick.xml");
    assert_eq!(s.integrator.max_depth, 32);
    assert_eq!((s.sensor.film.width, s.sensor.film.height), (400, 240));
    assert_eq!(s.sensor.fov_x_deg, 45.0);
    assert_eq!(s.shapes.len(), 4);
    let Geometry::Mesh(cube) = &s.shapes[1].geometry else {
        panic!("the cube is a mesh")
    };
    assert_eq!(cube.indices.len(), 12);
    // Cube: scale (1, 1.1, 0.15), rotate y 55°, translate (−1.3, 1.2, 0). The corner (1, 1, 1)
    // maps to R_y(55°)(1, 1.1, 0.15) + t.
    let p = s.shapes[1].to_world.transform_point3(Vec3::ONE);
    let (sn, cs) = 55f32.to_radians().sin_cos();
    let want = Vec3::new(cs * 1.0 + sn * 0.15 - 1.3, 1.1 + 1.2, -sn * 1.0 + cs * 0.15);
    assert!((p - want).length() < 1e-5, "{p} vs {want}");
    assert!(
        s.materials[s.shapes[1].material]
            .get::<DielectricMaterial>()
            .is_some()
    );
    assert!(
        s.materials[s.shapes[2].material]
            .get::<ThinDielectricMaterial>()
            .is_some()
    );
    // The light rectangle: rotate x 90° maps its +z normal to −y (facing down).
    let light = &s.shapes[3];
    let n = light.to_world.matrix3.inverse().transpose() * Vec3::Z;
    assert!((n.normalize() - Vec3::NEG_Y).length() < 1e-5);
    assert!(light.emitter.is_some());
}

#[test]
fn cornell_scene() {
    let s = load("cornell-spheres.xml");
    assert_eq!((s.sensor.film.width, s.sensor.film.height), (256, 256));
    // fov_axis smaller on a square film is fov_x.
    assert!((s.sensor.fov_x_deg - 39.3077).abs() < 1e-4);
    assert!(s.shapes.iter().any(|x| x.id.as_deref() == Some("floor")));
    assert!(s.shapes.iter().any(|x| x.emitter.is_some()));
    // Walls share materials by reference: fewer materials than shapes.
    assert!(s.materials.len() < s.shapes.len());
    // Every material index is valid and every material builds a BSDF.
    for sh in &s.shapes {
        let m = &s.materials[sh.material];
        let flags = m.with_bsdf(Vec2::new(0.5, 0.5), |b| b.flags());
        assert!(flags.0 != 0);
    }
}

#[test]
fn defines_override_defaults() {
    let d = vec![
        ("spp".to_string(), "3".to_string()),
        ("width".to_string(), "32".to_string()),
    ];
    let s = load_scene_file(scene_path("materials.xml"), &d).unwrap();
    assert_eq!(s.sensor.sampler.sample_count, 3);
    assert_eq!(s.sensor.film.width, 32);
    assert_eq!(s.sensor.film.height, 200);
}
