//! The scene description: what the Mitsuba 3 XML reader ([`crate::xml`]) produces and the
//! renderer consumes. Its types are named `*Desc` where a runtime type of the same plugin exists
//! (the film description [`FilmDesc`] and the film [`crate::film::Film`], ...). Plain data, no behaviour beyond small helpers; geometry is in object space
//! and each shape carries its `to_world`.
//!
//! Conventions follow Mitsuba 3 (`look_at` in `include/mitsuba/core/transform.h`,
//! `src/sensors/perspective.cpp`): camera space is +z forward, +y up,
//! +x left; `SensorDesc::fov_x_deg` is the horizontal field of view after the `fov_axis` /
//! `focal_length` conversion.

use glam::{Affine3A, Vec2, Vec3};
use gonio_core::Spectrum;
use gonio_core::sensor_response::SensorResponse;
use std::sync::Arc;

pub use crate::material::Material;
pub use crate::texture::Texture;

/// A whole scene: integrator, one sensor, shapes (with their area emitters), other emitters and
/// the materials the shapes index into.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The integrator settings.
    pub integrator: IntegratorDesc,
    /// The camera.
    pub sensor: SensorDesc,
    /// All shapes, in document order.
    pub shapes: Vec<ShapeDesc>,
    /// Emitters that are not attached to a shape (point, spot, directional, constant, envmap).
    pub emitters: Vec<EmitterDesc>,
    /// Materials; [`ShapeDesc::material`] indexes this list.
    pub materials: Vec<Material>,
    /// Participating media; [`ShapeDesc::media`] and [`Scene::sensor_medium`] index this list.
    pub media: Vec<crate::medium::Medium>,
    /// The medium the sensor is in (a `<medium>` nested in the `<sensor>`).
    pub sensor_medium: Option<crate::medium::MediumId>,
}

impl Scene {
    /// True when the scene holds participating media: the sensor's, or a shape that is the
    /// boundary between two media.
    pub fn has_media(&self) -> bool {
        self.sensor_medium.is_some() || self.shapes.iter().any(|s| s.media.is_transition())
    }

    /// True when the scene asks for a polarized render without being told: a `stokes`
    /// integrator, or a material that asks for it (`polarizer`, `retarder`, `circular`,
    /// `pplastic`, `measured_polarized`, also inside `twosided`, `blendbsdf`, `mask`, `normalmap`, `bumpmap`).
    pub fn asks_for_polarization(&self) -> bool {
        self.integrator.stokes
            || self
                .materials
                .iter()
                .any(|m| m.as_surface().asks_for_polarization())
    }
}

/// Description of the `<integrator>` (the `path` settings), as the scene file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct IntegratorDesc {
    /// Longest path, in segments; −1 = unbounded (Mitsuba `max_depth`, default −1).
    pub max_depth: i32,
    /// Depth at which Russian roulette starts (Mitsuba `rr_depth`, default 5).
    pub rr_depth: u32,
    /// Ours: the highest probability with which Russian roulette continues a path, in (0, 1)
    /// (default 0.99; Mitsuba's is 0.95, fixed).
    pub rr_survival: f32,
    /// Ours: Russian roulette continues a path with probability min(`rr_scale`·max(β)·η²,
    /// `rr_survival`) (default 4; Mitsuba's and pbrt-v4's rule is 1).
    pub rr_scale: f32,
    /// Hide directly visible emitters (Mitsuba `hide_emitters`, default false).
    pub hide_emitters: bool,
    /// A volumetric path tracer (`volpath`, `volpathmis`, `prbvolpath`): participating media
    /// take part (`crate::integrator::volpath`); `path` ignores them, as Mitsuba's does.
    pub volumetric: bool,
    /// Ours: shadow rays pass through `thindielectric` sheets, attenuated (default true).
    pub thin_shadows: bool,
    /// Ours: trace light paths for the caustics seen directly (emitter → specular chain → smooth
    /// surface → camera) instead of finding them by BSDF sampling (default true; see
    /// `integrator::caustics`).
    pub caustic_paths: bool,
    /// Ours: next-event estimation follows shadow rays through smooth glass, refracting
    /// (default true; see `integrator::refracted`).
    pub refracted_nee: bool,
    /// Ours: manifold next-event estimation through mirror spheres, for caustics seen through
    /// delta surfaces (default true; see `integrator::manifold`).
    pub manifold_nee: bool,
    /// Ours: at rough glass, a reflection or refraction that leaves the scene is added whole and
    /// the path follows the other lobe; at smooth and rough glass and `plastic`'s coat, an area
    /// light met by the outward (mirror) lobe adds its emission whole (default true; see `integrator::lobe_split`).
    pub split_escapes: bool,
    /// Ours: where the camera sees smooth glass directly, both lobes are followed, each whole
    /// (default true; see `integrator::PathTracer::visible_glass_split`).
    pub split_visible_glass: bool,
    /// Ours: next-event estimation samples every light at each vertex when the scene has at most
    /// this many (and at least two); 0 chooses one light per vertex, as Mitsuba (default 2).
    pub split_lights: u32,
    /// Ours: lights at infinity without a feature as narrow as a rough conductor's or glass's
    /// lobe are left to BSDF sampling there (default true; see
    /// `emitter::Lights::left_to_bsdf`).
    pub narrow_lobes: bool,
    /// Ours: candidates of resampled next-event estimation of the environment map at a
    /// single-scattering `roughconductor` (alone, or a side of a `twosided`) in a scene with one
    /// `envmap` (default 8; 0, Mitsuba's estimator: one light sample and one BSDF sample weighed
    /// by MIS; see `integrator::resampled`).
    pub ris_candidates: u32,
    /// Exponent β of the power heuristic between next-event estimation and BSDF sampling
    /// (default 1.25; Mitsuba's 2).
    pub mis_exponent: f32,
    /// Which algorithm: `path` (the fields above), `direct` or `depth`.
    pub kind: IntegratorKind,
    /// Mitsuba's `stokes` wrapper around this integrator: also write the Stokes vector S0..S3
    /// as the layers `S0.R` … `S3.B` (implies `polarized`).
    pub stokes: bool,
    /// Render polarized (paths carry Mueller matrices, `gonio render --polarized`; also set
    /// by a scene with a `stokes` integrator or a polarizing BSDF, see
    /// `render::PreparedScene::integrator`).
    pub polarized: bool,
    /// Mitsuba's `aov` or `moment` wrapper: film layers written beside the image by nested
    /// integrators (`integrator::layers`); `None` for a plain integrator. The other fields are
    /// then those of the first nested integrator (its image is the film's `R`, `G`, `B`).
    pub layers: Option<Box<LayersDesc>>,
}

/// The integrators Mitsuba's `aov` and `moment` wrap, and what they add to the film.
#[derive(Clone, Debug, PartialEq)]
pub enum LayersDesc {
    /// `aov`: per nested integrator the layer `name.R, .G, .B, .A`, then the nested integrators'
    /// own layers (`name.<layer>`), then each AOV's channels (`name.T`, `name.X`, ...).
    Aov {
        /// Nested integrators, in document order (as Mitsuba 3.9.1 takes them).
        nested: Vec<NestedIntegrator>,
        /// The `aovs` list: (layer name, what it records), in the order written.
        aovs: Vec<(String, AovType)>,
    },
    /// `moment`: per nested integrator its own layers and its image in CIE XYZ (`name.X, .Y,
    /// .Z`), then the square of every one of those channels (`m2_<channel>`).
    Moment {
        /// Nested integrators, in document order.
        nested: Vec<NestedIntegrator>,
    },
}

/// An integrator nested in `aov` or `moment`, with the name its layers carry (`_arg_N` for an
/// unnamed one, as Mitsuba names it).
#[derive(Clone, Debug, PartialEq)]
pub struct NestedIntegrator {
    /// Layer name.
    pub name: String,
    /// Its settings.
    pub desc: IntegratorDesc,
}

/// What an `aov` output records at the first surface a camera ray hits (Mitsuba 3
/// `src/integrators/aov.cpp`); every channel is 0 where the ray escapes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AovType {
    /// `depth`: distance along the camera ray (`name.T`).
    Depth,
    /// `position`: world-space hit point (`name.X, .Y, .Z`).
    Position,
    /// `uv`: texture coordinates (`name.U, .V`).
    Uv,
    /// `geo_normal`: geometric normal (`name.X, .Y, .Z`).
    GeoNormal,
    /// `sh_normal`: shading normal (`name.X, .Y, .Z`).
    ShNormal,
    /// `dp_du`: ∂p/∂u (`name.X, .Y, .Z`).
    DpDu,
    /// `dp_dv`: ∂p/∂v (`name.X, .Y, .Z`).
    DpDv,
    /// `duv_dx`: change of uv per pixel step in x, scaled by 1/√spp (`name.U, .V`).
    DuvDx,
    /// `duv_dy`: change of uv per pixel step in y, scaled by 1/√spp (`name.U, .V`).
    DuvDy,
    /// `prim_index`: triangle index within its mesh, 0 for an analytic shape (`name.I`).
    PrimIndex,
    /// `shape_index`: index of the shape in the scene's shape list (`name.I`).
    ShapeIndex,
}

impl AovType {
    /// Every type with its name in the `aovs` string.
    pub const ALL: [(&'static str, AovType); 11] = [
        ("depth", AovType::Depth),
        ("position", AovType::Position),
        ("uv", AovType::Uv),
        ("geo_normal", AovType::GeoNormal),
        ("sh_normal", AovType::ShNormal),
        ("dp_du", AovType::DpDu),
        ("dp_dv", AovType::DpDv),
        ("duv_dx", AovType::DuvDx),
        ("duv_dy", AovType::DuvDy),
        ("prim_index", AovType::PrimIndex),
        ("shape_index", AovType::ShapeIndex),
    ];

    /// The channel suffixes Mitsuba gives this type's layer.
    pub fn channels(self) -> &'static [&'static str] {
        match self {
            AovType::Depth => &["T"],
            AovType::Uv | AovType::DuvDx | AovType::DuvDy => &["U", "V"],
            AovType::PrimIndex | AovType::ShapeIndex => &["I"],
            _ => &["X", "Y", "Z"],
        }
    }
}

/// The integrator plugin a scene names; `path`'s settings are [`IntegratorDesc`]'s fields.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum IntegratorKind {
    /// `path`: the path tracer.
    #[default]
    Path,
    /// `direct` (Mitsuba 3 `src/integrators/direct.cpp`): emitters seen directly plus one
    /// bounce of direct lighting, `emitter_samples` light samples and `bsdf_samples` BSDF
    /// samples per hit, combined by the power heuristic.
    Direct {
        /// Light samples per hit.
        emitter_samples: u32,
        /// BSDF samples per hit.
        bsdf_samples: u32,
    },
    /// `depth` (Mitsuba 3 `src/integrators/depth.cpp`): the distance along the camera ray to
    /// the first hit, 0 where the ray escapes, in every colour channel.
    Depth,
    /// `ptracer` (Mitsuba 3 `src/integrators/ptracer.cpp`): light tracing, every light-path
    /// vertex joined to the camera and splatted (`max_depth`, `rr_depth`, `hide_emitters`).
    PTracer,
}

impl IntegratorDesc {
    /// The defaults with every estimator row of ours at Mitsuba's value: no sheets crossed by
    /// shadow rays, no light subpaths, refracted or manifold next-event estimation, lobe splits
    /// or narrow-lobe rule, one light per vertex, the power heuristic's exponent 2, Russian
    /// roulette on the throughput alone (the integrators that render with Mitsuba's estimator:
    /// `direct`, `depth`, `ptracer`, `prb`'s direct form).
    pub fn mitsuba_estimators() -> Self {
        Self {
            thin_shadows: false,
            caustic_paths: false,
            refracted_nee: false,
            manifold_nee: false,
            split_escapes: false,
            split_visible_glass: false,
            split_lights: 0,
            narrow_lobes: false,
            ris_candidates: 0,
            mis_exponent: 2.0,
            rr_scale: 1.0,
            ..Self::default()
        }
    }
}

impl Default for IntegratorDesc {
    /// Mitsuba's `path` defaults plus our `thin_shadows`, `caustic_paths`, `refracted_nee` and
    /// `manifold_nee` on.
    fn default() -> Self {
        Self {
            max_depth: -1,
            rr_depth: 5,
            rr_survival: 0.99,
            rr_scale: 4.0,
            hide_emitters: false,
            volumetric: false,
            thin_shadows: true,
            caustic_paths: true,
            refracted_nee: true,
            manifold_nee: true,
            split_escapes: true,
            split_visible_glass: true,
            split_lights: 2,
            narrow_lobes: true,
            ris_candidates: 8,
            mis_exponent: 1.25,
            kind: IntegratorKind::Path,
            stokes: false,
            polarized: false,
            layers: None,
        }
    }
}

/// Description of the `<sensor>` (a perspective camera), as the scene file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorDesc {
    /// Camera to world (camera space: +z forward, +y up, +x left).
    pub to_world: Affine3A,
    /// Horizontal field of view, degrees, after the `fov_axis` conversion (`perspective`,
    /// `thinlens`; unused by `orthographic`).
    pub fov_x_deg: f32,
    /// The sensor plugin: pinhole, orthographic or thin lens.
    pub projection: Projection,
    /// Near clipping distance (default 0.01).
    pub near_clip: f32,
    /// Far clipping distance (default 10000).
    pub far_clip: f32,
    /// The film.
    pub film: FilmDesc,
    /// The sampler.
    pub sampler: SamplerDesc,
    /// `batch`: the sensors side by side on the film, each on its share of the width (empty for
    /// every other sensor).
    pub children: Vec<SensorDesc>,
    /// `distant`: the shape its rays target (`None` for every other sensor).
    pub target_shape: Option<TargetShape>,
}

/// A shape that only guides a sensor's rays (`distant`'s `target`), not part of the scene;
/// equal when it is the same shape.
#[derive(Clone, Debug)]
pub struct TargetShape(pub Arc<ShapeDesc>);

impl PartialEq for TargetShape {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// How a sensor maps film positions to rays (Mitsuba 3 `src/sensors/`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Projection {
    /// `perspective`: a pinhole.
    #[default]
    Perspective,
    /// `orthographic`: parallel rays along +z from the camera-space rectangle
    /// [−1, 1] × [−1/aspect, 1/aspect] on the near plane (sized by `to_world`'s scale).
    Orthographic,
    /// `thinlens`: a thin lens of radius `aperture_radius` focused at `focus_distance`.
    ThinLens {
        /// Lens radius (camera-space units).
        aperture_radius: f32,
        /// Distance of the plane in focus, along +z.
        focus_distance: f32,
    },
    /// `radiancemeter`: one ray, from `to_world`'s origin along its +z (a film of one pixel).
    RadianceMeter,
    /// `batch`: [`SensorDesc::children`] side by side, left to right.
    Batch,
    /// `distant`: parallel rays along `to_world`'s +z from outside the scene, at `target_point`,
    /// at points of [`SensorDesc::target_shape`], or (neither) across the scene's bounding sphere.
    Distant {
        /// The point every ray passes through.
        target_point: Option<Vec3>,
    },
    /// `irradiancemeter`: cosine-weighted rays from uniform points of a shape, weighted π.
    IrradianceMeter {
        /// The shape, an index into [`Scene::shapes`].
        shape: usize,
    },
}

/// Description of the `<film>` (`hdrfilm`), as the scene file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmDesc {
    /// Width in pixels (default 768).
    pub width: u32,
    /// Height in pixels (default 576).
    pub height: u32,
    /// Reconstruction filter (default gaussian, stddev 0.5).
    pub filter: FilterDesc,
    /// What the image file holds (Mitsuba's `pixel_format`, `component_format`, `file_format`).
    pub output: FilmOutput,
    /// The part of the film that is rendered and written (Mitsuba's `crop_offset_x`, ...,
    /// `crop_height`; default the whole film).
    pub crop: Option<CropWindow>,
    /// Mitsuba's `sample_border`: also sample the band of pixels outside the image that the
    /// filter reaches, so the edge pixels see samples from both sides (default false).
    pub sample_border: bool,
    /// What the film records: linear sRGB (`hdrfilm`) or spectral bands (`specfilm`).
    pub response: SensorResponse,
}

/// A crop window: the rendered image is the `size` pixels of the full film starting at
/// `offset` (top-left origin); the camera still sees the full film's field of view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CropWindow {
    /// Top-left pixel (x, y) of the window in the full film.
    pub offset: (u32, u32),
    /// Width and height of the window, ≥ 1, inside the film.
    pub size: (u32, u32),
}

impl FilmDesc {
    /// Size of the image that is rendered: the crop window's, or the film's.
    pub fn image_size(&self) -> (u32, u32) {
        self.crop.map_or((self.width, self.height), |c| c.size)
    }
}

impl Default for FilmDesc {
    fn default() -> Self {
        Self {
            width: 768,
            height: 576,
            filter: FilterDesc::default(),
            output: FilmOutput::default(),
            crop: None,
            sample_border: false,
            response: SensorResponse::Srgb,
        }
    }
}

/// The channels of the developed image (Mitsuba's `hdrfilm` `pixel_format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PixelFormat {
    /// `R`, `G`, `B` (linear sRGB; the default).
    #[default]
    Rgb,
    /// `R`, `G`, `B`, `A`.
    Rgba,
    /// `Y` (CIE luminance).
    Luminance,
    /// `Y`, `A`.
    LuminanceAlpha,
    /// `X`, `Y`, `Z` (CIE 1931).
    Xyz,
    /// `X`, `Y`, `Z`, `A`.
    Xyza,
    /// The film's spectral bands, one channel each under its own name (`specfilm`).
    Bands,
}

impl PixelFormat {
    /// True when the image has an alpha channel.
    pub fn has_alpha(self) -> bool {
        matches!(self, Self::Rgba | Self::LuminanceAlpha | Self::Xyza)
    }
}

/// The number type of each stored value (Mitsuba's `component_format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ComponentFormat {
    /// Half floats (Mitsuba's default).
    #[default]
    Float16,
    /// Single floats.
    Float32,
    /// 32-bit unsigned integers (the value × 2³² − 1, clamped: what OpenEXR's UINT channels hold).
    Uint32,
}

/// The image file format (Mitsuba's `file_format`): it names the default output's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FileFormat {
    /// OpenEXR, `.exr` (the default).
    #[default]
    OpenExr,
    /// Radiance RGBE, `.hdr`.
    Rgbe,
    /// Portable float map, `.pfm`.
    Pfm,
}

impl FileFormat {
    /// The file name extension Mitsuba gives this format.
    pub fn extension(self) -> &'static str {
        match self {
            Self::OpenExr => "exr",
            Self::Rgbe => "hdr",
            Self::Pfm => "pfm",
        }
    }
}

/// What the film writes: channels, number type and file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct FilmOutput {
    /// Channels.
    pub pixel_format: PixelFormat,
    /// Number type of an EXR file's values.
    pub component_format: ComponentFormat,
    /// File format of the default output.
    pub file_format: FileFormat,
}

/// Description of the reconstruction filter (`<rfilter>`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterDesc {
    /// `box`, radius default 0.5.
    Box {
        /// Half width, pixels.
        radius: f32,
    },
    /// `tent`, radius default 1.
    Tent {
        /// Half width, pixels.
        radius: f32,
    },
    /// `gaussian`, stddev default 0.5, support 4σ.
    Gaussian {
        /// Standard deviation, pixels.
        stddev: f32,
    },
    /// `mitchell` (B = C = 1/3 by default) and `catmullrom` (B = 0, C = ½): radius 2.
    Mitchell {
        /// The cubic's B.
        b: f32,
        /// The cubic's C.
        c: f32,
    },
    /// `lanczos`, radius = lobes (default 3).
    Lanczos {
        /// Number of lobes.
        lobes: u32,
    },
}

impl Default for FilterDesc {
    fn default() -> Self {
        FilterDesc::Gaussian { stddev: 0.5 }
    }
}

impl FilterDesc {
    /// Support radius in pixels (gaussian: 4σ).
    pub fn radius(&self) -> f32 {
        match *self {
            FilterDesc::Box { radius } | FilterDesc::Tent { radius } => radius,
            FilterDesc::Gaussian { stddev } => 4.0 * stddev,
            FilterDesc::Mitchell { .. } => 2.0,
            FilterDesc::Lanczos { lobes } => lobes as f32,
        }
    }
}

/// Description of the `<sampler>`, as the scene file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplerDesc {
    /// Which sample pattern.
    pub kind: SamplerKind,
    /// Samples per pixel (default 4).
    pub sample_count: u32,
    /// Seed (default 0).
    pub seed: u64,
}

impl Default for SamplerDesc {
    fn default() -> Self {
        Self {
            kind: SamplerKind::Independent,
            sample_count: 4,
            seed: 0,
        }
    }
}

/// The Mitsuba sampler plugins we accept.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// `independent`.
    Independent,
    /// `stratified` (`jitter`, default true).
    Stratified {
        /// Jitter inside strata.
        jitter: bool,
    },
    /// `multijitter` (`jitter`, default true).
    MultiJitter {
        /// Jitter inside strata.
        jitter: bool,
    },
    /// `ldsampler` (rendered with our Owen-scrambled Sobol points).
    LowDiscrepancy,
    /// `orthogonal` (`jitter`, default true; rendered with our multi-jittered points).
    Orthogonal {
        /// Jitter inside strata.
        jitter: bool,
    },
}

/// Description of a `<shape>`: object-space geometry, its placement, its material and an
/// optional area light.
#[derive(Clone, Debug)]
pub struct ShapeDesc {
    /// Object-space geometry.
    pub geometry: Geometry,
    /// Object to world.
    pub to_world: Affine3A,
    /// Flip the geometric and shading normals (`flip_normals`, default false).
    pub flip_normals: bool,
    /// Ignore vertex normals, shade with face normals (`face_normals`, default false; meshes).
    pub face_normals: bool,
    /// Hit only from outside, never from within (the curve shapes, a tube Mitsuba's curves let
    /// every ray out of): a ray that meets the inside of its surface passes through.
    pub outside_only: bool,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// The media inside and outside (`<ref name="interior">`, `"exterior"`).
    pub media: crate::medium::MediumInterface,
    /// Area emitter attached to this shape.
    pub emitter: Option<AreaEmitterDesc>,
    /// The `id` attribute, if any.
    pub id: Option<String>,
}

/// Object-space geometry of a [`ShapeDesc`].
#[derive(Clone, Debug)]
pub enum Geometry {
    /// `sphere`: centre and radius (object space; `to_world` applies on top).
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
    },
    /// `rectangle`: [−1, 1]² in z = 0, normal +z, uv = ((x+1)/2, (y+1)/2).
    Rectangle,
    /// `disk`: unit disk in z = 0, normal +z.
    Disk,
    /// A triangle mesh (`obj`, `ply`, `cube`).
    Mesh(Arc<TriangleMesh>),
    /// `shapegroup`: shapes made available for instancing, not rendered by themselves (the
    /// scene reader leaves it out of [`Scene::shapes`]).
    Group(Arc<crate::geometry::instance::ShapeGroup>),
    /// `instance`: a [`Geometry::Group`] placed by `to_world`. The reader expands an instance
    /// into one shape per member of its group (`member: Some(i)`, with that member's material),
    /// all sharing the group's geometry and acceleration structure.
    Instance {
        /// The group.
        group: Arc<crate::geometry::instance::ShapeGroup>,
        /// The member this shape stands for (`None` before expansion).
        member: Option<usize>,
    },
    /// `sdfgrid`: a signed distance function sampled on a grid over the unit cube.
    SdfGrid(Arc<crate::geometry::sdfgrid::SdfGrid>),
}

/// An indexed triangle mesh in object space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Per-vertex normals (empty if none).
    pub normals: Vec<Vec3>,
    /// Per-vertex texture coordinates (empty if none).
    pub uvs: Vec<Vec2>,
    /// Triangles, counter-clockwise seen from the front.
    pub indices: Vec<[u32; 3]>,
}

/// Description of an emitter a shape carries (`area`, `directionalarea`): one-sided, on the side
/// the (possibly flipped) normal points to.
#[derive(Clone, Debug)]
pub struct AreaEmitterDesc {
    /// Emitted radiance (`radiance`, default 1 × D65 in spectral mode).
    pub radiance: Texture,
    /// The shape's mesh attributes, when `radiance` reads the hit (`mesh_attribute`, `volume`):
    /// set by the reader once the shape is known.
    pub hit: Option<Arc<crate::texture::hit::HitBinding>>,
    /// How the light leaves the surface.
    pub emission: SurfaceEmission,
}

/// The directions in which a shape's emitter sends its light.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SurfaceEmission {
    /// `area`: radiance `radiance` into the whole front hemisphere.
    #[default]
    Diffuse,
    /// `directionalarea`: only along the normal (a delta in direction; `radiance` is then the
    /// power per unit area that leaves along it).
    Directional {
        /// Next-event estimation along the beam through the shading point, on rectangles,
        /// disks, spheres and planar meshes (ours); false leaves the light to light paths, as
        /// Mitsuba 3.9.1 does.
        next_event: bool,
    },
}

/// Description of an `<emitter>` not attached to a shape.
#[derive(Clone, Debug)]
pub enum EmitterDesc {
    /// `point`: isotropic intensity, W/sr.
    Point {
        /// World position.
        position: Vec3,
        /// Radiant intensity.
        intensity: Spectrum,
    },
    /// `spot`: cone along +z of `to_world`.
    Spot {
        /// Light to world (position and orientation).
        to_world: Affine3A,
        /// Intensity at the cone centre.
        intensity: Spectrum,
        /// Outer cone angle, degrees (default 20).
        cutoff_angle_deg: f32,
        /// Full-intensity angle, degrees (default 3/4 of cutoff).
        beam_width_deg: f32,
        /// Mitsuba's `texture`: a pattern projected over the cone (uv from the direction).
        texture: Option<crate::texture::Texture>,
    },
    /// `projector`: a texture projected from a pinhole along +z of `to_world`.
    Projector {
        /// Light to world.
        to_world: Affine3A,
        /// E, the projected texture.
        irradiance: crate::texture::Texture,
        /// Multiplies E (and D65).
        scale: f32,
        /// Horizontal field of view, degrees.
        fov_x_deg: f32,
        /// The texture's width/height.
        aspect: f32,
        /// E is multiplied by D65 (false: Mitsuba 3.9.1's nested textures, `whitepoint="mitsuba"`).
        whitepoint: bool,
    },
    /// `directional`: light travelling along `direction`.
    Directional {
        /// World direction light travels in, normalized.
        direction: Vec3,
        /// Irradiance on a surface facing the light.
        irradiance: Spectrum,
    },
    /// `constant`: uniform environment.
    Constant {
        /// Radiance.
        radiance: Spectrum,
    },
    /// `sunsky`: the Hosek–Wilkie sky and sun.
    SunSky {
        /// The model's parameters (the sun's direction in the sky's local frame).
        params: gonio_core::sunsky::SunSkyParams,
        /// Sky to world (the local +z is the zenith).
        to_world: Affine3A,
    },
    /// `envmap`: lat-long environment image.
    EnvMap {
        /// The image (linear RGB).
        image: Arc<crate::image::RgbImage>,
        /// Scale factor (default 1).
        scale: f32,
        /// Environment to world.
        to_world: Affine3A,
        /// Mitsuba 3.9.1's texel layout and interpolation (`lookup="mitsuba"`).
        mitsuba_lookup: bool,
        /// Next-event samples ∝ max(L − L̄, 0) where the BSDF is sampled too (`mis_compensation`).
        mis_compensation: bool,
        /// Next-event samples × the clamped cosine where the BSDF is sampled too and only
        /// reflects (`product_sampling`, ours).
        product_sampling: bool,
    },
}
