//! Triangle meshes traced by Intel Embree 3 (issue #13: faster traversal for mesh-heavy scenes).
//!
//! Embree's BVH8 traversal and its four-at-a-time triangle tests run in the widest vector unit
//! the CPU has (SSE2, AVX2 or AVX-512, chosen by Embree at run time), which our scalar triangle
//! test over obvhs' CWBVH cannot match: on the corpus's material previews and the 1M-triangle
//! terrain, ray queries took 35–45 % of the render time before (bench/RESULTS.md).
//!
//! The library is loaded at run time (`libembree3.so.3`, Debian's `libembree3-3`, which
//! `.ci/run` installs with `libembree-dev`), never linked: without it, or with
//! `GONIO_EMBREE=off`, [`super::Accel`] keeps its own BVH for triangles, and images differ only
//! by the rounding of the two triangle tests (both watertight, same barycentric convention:
//! `p = (1 − u − v)·p0 + u·p1 + v·p2`). The declarations below are Embree 3.13's
//! (`rtcore_*.h`, `RTC_MAX_INSTANCE_LEVEL_COUNT` 1, `RTC_MIN_WIDTH` 0, as Debian builds it);
//! no binding crate targets the system's Embree 3 without linking it, so these few are ours.
//!
//! Only triangles go to Embree; analytic shapes and instances stay in our own structure and a
//! query takes the closer of the two answers. Queries match ours: hits with `0 < t < tmax`
//! (Embree's `tnear` is the smallest positive float, its `tfar` the float below `tmax`).

use crate::geometry::shape::PrimHit;
use crate::geometry::{Ray, ShapeKind, WorldShape};
use std::ffi::{c_char, c_int, c_uint, c_void};
use std::sync::OnceLock;

type Device = *mut c_void;
type Scene = *mut c_void;
type Geometry = *mut c_void;

const GEOMETRY_TYPE_TRIANGLE: c_uint = 0;
const BUFFER_TYPE_INDEX: c_uint = 0;
const BUFFER_TYPE_VERTEX: c_uint = 1;
const FORMAT_UINT3: c_uint = 0x5003;
const FORMAT_FLOAT3: c_uint = 0x9003;
const SCENE_FLAG_CONTEXT_FILTER_FUNCTION: c_uint = 1 << 3;
const BUILD_QUALITY_MEDIUM: c_uint = 1;
const INVALID_GEOMETRY_ID: c_uint = u32::MAX;

/// `struct RTCIntersectContext` (flags, filter, instID[1]).
#[repr(C)]
struct IntersectContext {
    flags: c_uint,
    filter: Option<unsafe extern "C" fn(*const FilterArgs)>,
    inst_id: [c_uint; 1],
}

impl IntersectContext {
    /// `rtcInitIntersectContext` (a header-inline function): incoherent rays, no filter.
    fn new() -> Self {
        Self {
            flags: 0,
            filter: None,
            inst_id: [INVALID_GEOMETRY_ID],
        }
    }
}

/// `struct RTCRay`.
#[repr(C, align(16))]
#[derive(Clone, Copy)]
struct RtcRay {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: c_uint,
    id: c_uint,
    flags: c_uint,
}

/// `struct RTCHit`.
#[repr(C, align(16))]
#[derive(Clone, Copy)]
struct RtcHit {
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: c_uint,
    geom_id: c_uint,
    inst_id: [c_uint; 1],
}

/// `struct RTCRayHit`.
#[repr(C, align(16))]
struct RayHit {
    ray: RtcRay,
    hit: RtcHit,
}

/// Rays in a packet of [`PACKET`] (`RTCRay16`: structure of arrays, 64-byte aligned).
#[repr(C, align(64))]
struct Ray16 {
    org: [[f32; PACKET]; 3],
    tnear: [f32; PACKET],
    dir: [[f32; PACKET]; 3],
    time: [f32; PACKET],
    tfar: [f32; PACKET],
    mask: [c_uint; PACKET],
    id: [c_uint; PACKET],
    flags: [c_uint; PACKET],
}

/// `struct RTCHit16`.
#[repr(C, align(64))]
struct Hit16 {
    ng: [[f32; PACKET]; 3],
    u: [f32; PACKET],
    v: [f32; PACKET],
    prim_id: [c_uint; PACKET],
    geom_id: [c_uint; PACKET],
    inst_id: [[c_uint; PACKET]; 1],
}

/// `struct RTCRayHit16`.
#[repr(C)]
struct RayHit16 {
    ray: Ray16,
    hit: Hit16,
}

/// The lanes of a packet query that carry a ray (−1) and those that do not (0), as Embree's
/// `valid` argument (64-byte aligned).
#[repr(C, align(64))]
struct Valid16([c_int; PACKET]);

/// Rays per packet query: Embree's widest (`rtcIntersect16`), 16 lanes of AVX-512, two halves
/// of AVX2 elsewhere (Embree picks the kernel).
pub(super) const PACKET: usize = 16;

/// `struct RTCFilterFunctionNArguments` (for single rays, `ray` and `hit` point at an `RtcRay`
/// and an `RtcHit`).
#[repr(C)]
struct FilterArgs {
    valid: *mut c_int,
    geometry_user_ptr: *mut c_void,
    context: *mut IntersectContext,
    ray: *mut RtcRay,
    hit: *mut RtcHit,
    n: c_uint,
}

/// The entry points we use, resolved once from the shared library.
struct Api {
    new_scene: unsafe extern "C" fn(Device) -> Scene,
    set_scene_flags: unsafe extern "C" fn(Scene, c_uint),
    set_scene_build_quality: unsafe extern "C" fn(Scene, c_uint),
    new_geometry: unsafe extern "C" fn(Device, c_uint) -> Geometry,
    set_new_geometry_buffer:
        unsafe extern "C" fn(Geometry, c_uint, c_uint, c_uint, usize, usize) -> *mut c_void,
    commit_geometry: unsafe extern "C" fn(Geometry),
    attach_geometry_by_id: unsafe extern "C" fn(Scene, Geometry, c_uint),
    release_geometry: unsafe extern "C" fn(Geometry),
    commit_scene: unsafe extern "C" fn(Scene),
    release_scene: unsafe extern "C" fn(Scene),
    get_device_error: unsafe extern "C" fn(Device) -> c_int,
    intersect1: unsafe extern "C" fn(Scene, *mut IntersectContext, *mut RayHit),
    occluded1: unsafe extern "C" fn(Scene, *mut IntersectContext, *mut RtcRay),
    intersect16: unsafe extern "C" fn(*const c_int, Scene, *mut IntersectContext, *mut RayHit16),
    device: Device,
    _lib: libloading::Library,
}

// The device is thread-safe (Embree's documented contract); the pointers are only passed back.
unsafe impl Send for Api {}
unsafe impl Sync for Api {}

/// Embree, loaded on first use; `None` when the library is missing or `GONIO_EMBREE=off`.
fn api() -> Option<&'static Api> {
    static API: OnceLock<Option<Api>> = OnceLock::new();
    API.get_or_init(|| {
        if std::env::var("GONIO_EMBREE").is_ok_and(|v| v == "off" || v == "0") {
            return None;
        }
        // SAFETY: loading Embree runs only its (side-effect free) static initializers, and every
        // symbol is given the signature of Embree 3's public header.
        unsafe {
            let lib = ["libembree3.so.3", "libembree3.so"]
                .iter()
                .find_map(|name| libloading::Library::new(name).ok())?;
            macro_rules! sym {
                ($name:literal) => {
                    *lib.get(concat!($name, "\0").as_bytes()).ok()?
                };
            }
            let new_device: unsafe extern "C" fn(*const c_char) -> Device = sym!("rtcNewDevice");
            let device = new_device(c"threads=0,verbose=0".as_ptr());
            if device.is_null() {
                return None;
            }
            Some(Api {
                new_scene: sym!("rtcNewScene"),
                set_scene_flags: sym!("rtcSetSceneFlags"),
                set_scene_build_quality: sym!("rtcSetSceneBuildQuality"),
                new_geometry: sym!("rtcNewGeometry"),
                set_new_geometry_buffer: sym!("rtcSetNewGeometryBuffer"),
                commit_geometry: sym!("rtcCommitGeometry"),
                attach_geometry_by_id: sym!("rtcAttachGeometryByID"),
                release_geometry: sym!("rtcReleaseGeometry"),
                commit_scene: sym!("rtcCommitScene"),
                release_scene: sym!("rtcReleaseScene"),
                get_device_error: sym!("rtcGetDeviceError"),
                intersect1: sym!("rtcIntersect1"),
                occluded1: sym!("rtcOccluded1"),
                intersect16: sym!("rtcIntersect16"),
                device,
                _lib: lib,
            })
        }
    })
    .as_ref()
}

/// Whether Embree is available to this process (and not turned off by `GONIO_EMBREE=off`).
pub fn available() -> bool {
    api().is_some()
}

/// An Embree scene holding the triangle meshes of a shape list; geometry `g` is shape `g`.
pub(super) struct Triangles {
    scene: Scene,
}

// Embree scenes are immutable after commit and safe to query from any thread.
unsafe impl Send for Triangles {}
unsafe impl Sync for Triangles {}

impl Drop for Triangles {
    fn drop(&mut self) {
        if let Some(api) = api() {
            // SAFETY: the scene was made by this device and is released once.
            unsafe { (api.release_scene)(self.scene) }
        }
    }
}

impl Triangles {
    /// The meshes of `shapes` in one committed scene; `None` without Embree, without meshes,
    /// or when Embree reports an error (the caller then keeps its own BVH).
    pub(super) fn new(shapes: &[WorldShape]) -> Option<Self> {
        let api = api()?;
        // SAFETY: buffers are filled within the item counts Embree allocated them with, and
        // every handle is released by the rule of Embree's reference counting.
        unsafe {
            let scene = (api.new_scene)(api.device);
            if scene.is_null() {
                return None;
            }
            let this = Self { scene };
            (api.set_scene_flags)(scene, SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
            (api.set_scene_build_quality)(scene, BUILD_QUALITY_MEDIUM);
            let mut any = false;
            for (id, shape) in shapes.iter().enumerate() {
                let ShapeKind::Mesh(m) = &shape.kind else { continue };
                if m.indices.is_empty() {
                    continue;
                }
                let geom = (api.new_geometry)(api.device, GEOMETRY_TYPE_TRIANGLE);
                if geom.is_null() {
                    return None;
                }
                let v = (api.set_new_geometry_buffer)(
                    geom,
                    BUFFER_TYPE_VERTEX,
                    0,
                    FORMAT_FLOAT3,
                    12,
                    m.positions.len(),
                ) as *mut [f32; 3];
                let i = (api.set_new_geometry_buffer)(
                    geom,
                    BUFFER_TYPE_INDEX,
                    0,
                    FORMAT_UINT3,
                    12,
                    m.indices.len(),
                ) as *mut [u32; 3];
                if v.is_null() || i.is_null() {
                    (api.release_geometry)(geom);
                    return None;
                }
                for (k, p) in m.positions.iter().enumerate() {
                    v.add(k).write(p.to_array());
                }
                for (k, t) in m.indices.iter().enumerate() {
                    i.add(k).write(*t);
                }
                (api.commit_geometry)(geom);
                (api.attach_geometry_by_id)(scene, geom, id as c_uint);
                (api.release_geometry)(geom);
                any = true;
            }
            if !any {
                return None;
            }
            (api.commit_scene)(scene);
            ((api.get_device_error)(api.device) == 0).then_some(this)
        }
    }

    fn rtc_ray(ray: &Ray) -> RtcRay {
        RtcRay {
            org: ray.o.to_array(),
            tnear: f32::MIN_POSITIVE,
            dir: ray.d.to_array(),
            time: 0.0,
            tfar: ray.tmax.next_down(),
            mask: u32::MAX,
            id: 0,
            flags: 0,
        }
    }

    fn empty_hit() -> RtcHit {
        RtcHit {
            ng: [0.0; 3],
            u: 0.0,
            v: 0.0,
            prim_id: INVALID_GEOMETRY_ID,
            geom_id: INVALID_GEOMETRY_ID,
            inst_id: [INVALID_GEOMETRY_ID],
        }
    }

    /// The closest triangle hit in `(0, ray.tmax)`: (shape, triangle, hit).
    #[inline]
    pub(super) fn closest(&self, ray: &Ray) -> Option<(u32, u32, PrimHit)> {
        if !(ray.tmax > 0.0) {
            return None;
        }
        let api = api()?;
        let mut ctx = IntersectContext::new();
        let mut rh = RayHit {
            ray: Self::rtc_ray(ray),
            hit: Self::empty_hit(),
        };
        // SAFETY: a committed scene, an initialized context and a 16-byte aligned ray-hit.
        unsafe { (api.intersect1)(self.scene, &mut ctx, &mut rh) };
        (rh.hit.geom_id != INVALID_GEOMETRY_ID).then(|| {
            let hit = PrimHit {
                t: rh.ray.tfar,
                a: rh.hit.u,
                b: rh.hit.v,
            };
            (rh.hit.geom_id, rh.hit.prim_id, hit)
        })
    }

    /// [`Self::closest`] of up to [`PACKET`] rays in one packet query (`rtcIntersect16`):
    /// `out[i]` for `rays[i]`. Rays with `tmax ≤ 0` (or NaN) fill no lane and get `None`.
    pub(super) fn closest_packet(&self, rays: &[Ray], out: &mut [Option<(u32, u32, PrimHit)>]) {
        assert!(rays.len() <= PACKET && out.len() == rays.len());
        out.fill(None);
        let Some(api) = api() else { return };
        let mut valid = Valid16([0; PACKET]);
        // Zeroed lanes beyond the rays; Embree reads only the valid ones.
        let mut rh = RayHit16 {
            ray: Ray16 {
                org: [[0.0; PACKET]; 3],
                tnear: [f32::MIN_POSITIVE; PACKET],
                dir: [[0.0; PACKET]; 3],
                time: [0.0; PACKET],
                tfar: [0.0; PACKET],
                mask: [u32::MAX; PACKET],
                id: [0; PACKET],
                flags: [0; PACKET],
            },
            hit: Hit16 {
                ng: [[0.0; PACKET]; 3],
                u: [0.0; PACKET],
                v: [0.0; PACKET],
                prim_id: [INVALID_GEOMETRY_ID; PACKET],
                geom_id: [INVALID_GEOMETRY_ID; PACKET],
                inst_id: [[INVALID_GEOMETRY_ID; PACKET]],
            },
        };
        for (i, ray) in rays.iter().enumerate() {
            if !(ray.tmax > 0.0) {
                continue;
            }
            valid.0[i] = -1;
            for k in 0..3 {
                rh.ray.org[k][i] = ray.o[k];
                rh.ray.dir[k][i] = ray.d[k];
            }
            rh.ray.tfar[i] = ray.tmax.next_down();
        }
        if valid.0.iter().all(|&v| v == 0) {
            return;
        }
        let mut ctx = IntersectContext::new();
        // SAFETY: a committed scene, an initialized context, a 64-byte aligned valid mask and
        // ray-hit packet of Embree 3's layout.
        unsafe { (api.intersect16)(valid.0.as_ptr(), self.scene, &mut ctx, &mut rh) };
        for (i, o) in out.iter_mut().enumerate() {
            if valid.0[i] != 0 && rh.hit.geom_id[i] != INVALID_GEOMETRY_ID {
                let hit = PrimHit {
                    t: rh.ray.tfar[i],
                    a: rh.hit.u[i],
                    b: rh.hit.v[i],
                };
                *o = Some((rh.hit.geom_id[i], rh.hit.prim_id[i], hit));
            }
        }
    }

    /// Whether any triangle is hit in `(0, ray.tmax)`.
    #[inline]
    pub(super) fn any(&self, ray: &Ray) -> bool {
        if !(ray.tmax > 0.0) {
            return false;
        }
        let Some(api) = api() else { return false };
        let mut ctx = IntersectContext::new();
        let mut r = Self::rtc_ray(ray);
        // SAFETY: as in `closest`; Embree sets `tfar` to −∞ on a hit.
        unsafe { (api.occluded1)(self.scene, &mut ctx, &mut r) };
        r.tfar == f32::NEG_INFINITY
    }

    /// Calls `f(shape, triangle, hit)` for every triangle hit in `(0, ray.tmax)`, in no
    /// particular order, until it returns `true`; whether it did.
    pub(super) fn each(&self, ray: &Ray, f: &mut dyn FnMut(u32, u32, PrimHit) -> bool) -> bool {
        if !(ray.tmax > 0.0) {
            return false;
        }
        let Some(api) = api() else { return false };
        /// The context Embree passes to the filter, with the visitor behind it.
        #[repr(C)]
        struct Visit<'a> {
            ctx: IntersectContext,
            f: &'a mut dyn FnMut(u32, u32, PrimHit) -> bool,
            stopped: bool,
        }
        /// Visits the candidate hit, then rejects it so that traversal goes on to the next.
        unsafe extern "C" fn filter(args: *const FilterArgs) {
            // SAFETY: Embree calls this during `rtcIntersect1` with the context we gave it,
            // which is the first field of a live `Visit` (repr(C)), for one ray (N = 1).
            unsafe {
                let args = &*args;
                let visit = &mut *(args.context as *mut Visit);
                let (ray, hit) = (&*args.ray, &*args.hit);
                if !visit.stopped {
                    let h = PrimHit {
                        t: ray.tfar,
                        a: hit.u,
                        b: hit.v,
                    };
                    visit.stopped = (visit.f)(hit.geom_id, hit.prim_id, h);
                }
                *args.valid = 0;
            }
        }
        let mut visit = Visit {
            ctx: IntersectContext {
                filter: Some(filter),
                ..IntersectContext::new()
            },
            f,
            stopped: false,
        };
        let mut rh = RayHit {
            ray: Self::rtc_ray(ray),
            hit: Self::empty_hit(),
        };
        // SAFETY: as in `closest`; the filter only runs inside this call, while `visit` lives.
        unsafe { (api.intersect1)(self.scene, &mut visit.ctx, &mut rh) };
        visit.stopped
    }
}
