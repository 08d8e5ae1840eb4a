//! Eight samples of one pixel traced in lockstep: the same paths as `Tracer::path`, each lane with
//! its own random numbers drawn in the same order, so the result is the scalar tracer's to the bit.
//!
//! Why: one path at a time keeps the CPU waiting on one thing after another (a BVH node, a row
//! of the sky's tables, a square root), and its rays go to Embree one by one. Eight paths side by
//! side give the CPU eight independent chains to overlap, and give Embree packets of eight rays:
//! the camera rays of one pixel and the shadow rays from its hits to a light are nearly parallel,
//! and a packet traverses the BVH once for them all. Only scenes whose rays stop at the first
//! surface they meet (`CpuTruthInputs::all_opaque`) go this way: a ray that may pass a surface
//! draws random numbers inside its trace, which a packet cannot.

use glam::DVec3;

use super::environment::PendingEnvironmentSample;
use super::{CpuScene, Hit, LightSample, PathState, Rng, SurfacePoint, Tracer, RAY_EPSILON};

/// Paths traced side by side.
pub(super) const LANES: usize = 8;

/// Embree reads a packet's mask with aligned 32-byte loads (its `ValidMaskN` is 16-aligned).
#[repr(C, align(32))]
struct Mask(embree3::ValidMaskN<LANES>);

impl Mask {
    fn of(live: &[bool; LANES]) -> Mask {
        let lane = |l: bool| if l { embree3::ValidMask::Valid } else { embree3::ValidMask::Invalid };
        Mask(embree3::ValidMaskN::new(live.map(lane)))
    }
}

/// A packet of the rays `CpuScene::ray` builds from each lane's (o, d, t_max).
fn packet(o: &[DVec3; LANES], d: &[DVec3; LANES], t_max: &[f64; LANES]) -> embree3::Ray8 {
    let mut r = embree3::Ray8::empty();
    for i in 0..LANES {
        let one = CpuScene::ray(o[i], d[i], t_max[i]);
        (r.org_x[i], r.org_y[i], r.org_z[i]) = (one.org_x, one.org_y, one.org_z);
        (r.dir_x[i], r.dir_y[i], r.dir_z[i]) = (one.dir_x, one.dir_y, one.dir_z);
        (r.tnear[i], r.tfar[i]) = (one.tnear, one.tfar);
    }
    r
}

impl CpuScene {
    /// `trace` for each live lane.
    fn trace8(
        &self,
        o: &[DVec3; LANES],
        d: &[DVec3; LANES],
        live: &[bool; LANES],
        coherent: bool,
    ) -> [Option<Hit>; LANES] {
        let Some(scene) = self.rays.as_ref() else { return std::array::from_fn(|_| None) };
        let mut rays =
            embree3::sys::RTCRayHit8 { ray: packet(o, d, &[f64::INFINITY; LANES]), hit: embree3::Hit8::new() };
        let mut context =
            if coherent { embree3::IntersectContext::coherent() } else { embree3::IntersectContext::incoherent() };
        scene.intersect8(&mut context, &mut rays, &Mask::of(live).0);
        std::array::from_fn(|i| {
            (live[i] && rays.hit.geomID[i] != embree3::INVALID_ID)
                .then(|| self.hit(o[i], d[i], rays.hit.primID[i] as usize))
        })
    }

    /// `occluded` for each lane that asks.
    fn occluded8(
        &self,
        o: &[DVec3; LANES],
        d: &[DVec3; LANES],
        t_max: &[f64; LANES],
        ask: &[bool; LANES],
    ) -> [bool; LANES] {
        let Some(scene) = self.rays.as_ref() else { return [false; LANES] };
        if !ask.contains(&true) {
            return [false; LANES];
        }
        let mut rays = packet(o, d, t_max);
        scene.occluded8(&mut embree3::IntersectContext::incoherent(), &mut rays, &Mask::of(ask).0);
        // Embree sets an occluded ray's tfar to −∞.
        std::array::from_fn(|i| ask[i] && rays.tfar[i] == f32::NEG_INFINITY)
    }
}

impl Tracer<'_> {
    /// Whether this cell's paths can be traced in lockstep (see the module comment).
    pub(super) fn lockstep(&self) -> bool {
        self.inputs.all_opaque() && !self.baking
    }

    /// `path(x, y, rng)` for each of `rngs`, in lockstep: the same sums and first objects.
    pub(super) fn paths(&self, x: u32, y: u32, rngs: &mut [Rng]) -> [(DVec3, Option<usize>); LANES] {
        debug_assert!(self.lockstep() && !rngs.is_empty() && rngs.len() <= LANES);
        let env = &self.scene.environment;
        let mut live: [bool; LANES] = std::array::from_fn(|i| i < rngs.len());
        let mut paths: [PathState; LANES] = std::array::from_fn(|i| {
            let d = rngs.get_mut(i).map_or(DVec3::Z, |rng| self.camera_ray(x, y, rng));
            PathState::new(self.camera, d, None)
        });
        let last = self.last_bounce();
        let mut points: [Option<(SurfacePoint, Option<PendingEnvironmentSample>)>; LANES] =
            std::array::from_fn(|_| None);
        for bounce in 0..=last {
            if !live.contains(&true) {
                break;
            }
            let hits = self.scene.trace8(&paths.each(|p| p.o), &paths.each(|p| p.d), &live, bounce == 0);
            // Every lane's environment sample is begun before any point is built, so that the
            // guide entries its prefetches ask for arrive while the eight points are built.
            let mut environments: [Option<PendingEnvironmentSample>; LANES] = std::array::from_fn(|i| {
                let drawn = live[i] && hits[i].is_some() && bounce != last && self.env_scale > 0.0;
                drawn.then(|| env.begin_sample(&mut rngs[i]))
            });
            for (i, (path, hit)) in paths.iter_mut().zip(hits).enumerate() {
                points[i] = None;
                if !live[i] {
                    continue;
                }
                let Some(hit) = hit else {
                    path.c += self.missed(path, self.inputs.background);
                    live[i] = false;
                    continue;
                };
                let environment = environments[i].take();
                let sp = self.surface_at(&hit, path.d);
                if let Some(pending) = &environment {
                    env.prefetch_texel(pending);
                }
                if bounce == 0 {
                    path.first_object = Some(sp.object);
                }
                path.c += path.throughput * sp.emission;
                if bounce == last {
                    live[i] = false;
                    continue;
                }
                points[i] = Some((sp, environment));
            }
            let direct = self.direct_light8(&paths, &points, rngs);
            for (i, path) in paths.iter_mut().enumerate() {
                let Some((sp, _)) = &points[i] else { continue };
                path.c += path.throughput * direct[i];
                live[i] = self.continue_path(path, sp, bounce, &mut rngs[i]);
            }
        }
        paths.map(|p| (p.c, p.first_object))
    }

    /// `direct_light` at each lane's point with every light's weight 1, the shadow rays cast as
    /// packets: light by light, then the environment's sample, each lane summing in that order.
    fn direct_light8(
        &self,
        paths: &[PathState; LANES],
        points: &[Option<(SurfacePoint, Option<PendingEnvironmentSample>)>; LANES],
        rngs: &mut [Rng],
    ) -> [DVec3; LANES] {
        let mut c = [DVec3::ZERO; LANES];
        let origin = points.each(|p| p.as_ref().map_or(DVec3::ZERO, |(sp, _)| sp.p + sp.ng * RAY_EPSILON));
        let mut add = |samples: [Option<LightSample>; LANES]| {
            let ask = samples.each(Option::is_some);
            let l = samples.each(|s| s.as_ref().map_or(DVec3::Z, |s| s.l));
            let distance = samples.each(|s| s.as_ref().map_or(0.0, |s| s.distance));
            let blocked = self.scene.occluded8(&origin, &l, &distance, &ask);
            for (i, sample) in samples.into_iter().enumerate() {
                // `direct_light`'s weight, 1 in the truth, multiplies by one: the same sum.
                match sample {
                    Some(sample) if !blocked[i] => c[i] += sample.radiance,
                    _ => {}
                }
            }
        };
        for light in &self.lights {
            add(std::array::from_fn(|i| {
                let (sp, _) = points[i].as_ref()?;
                self.light_sample(light, sp, -paths[i].d, &mut rngs[i])
            }));
        }
        add(std::array::from_fn(|i| {
            let (sp, Some(pending)) = points[i].as_ref()? else { return None };
            self.environment_sample(sp, -paths[i].d, pending)
        }));
        c
    }
}

/// A value per lane.
trait Each<T> {
    fn each<U>(&self, f: impl Fn(&T) -> U) -> [U; LANES];
}

impl<T> Each<T> for [T; LANES] {
    fn each<U>(&self, f: impl Fn(&T) -> U) -> [U; LANES] {
        std::array::from_fn(|i| f(&self[i]))
    }
}

#[cfg(test)]
mod tests {
    use super::super::{trace_paths, CpuEnvironment, CpuTruthInputs};
    use super::*;
    use crate::render::truth::bvh::TruthGeometry;
    use crate::render::truth::TruthKind;
    use crate::render::uniforms::{FrameUniforms, GpuLight, GpuMaterial};
    use bytemuck::Zeroable;
    use glam::{DMat4, DVec3};

    /// Two spheres (a metal, a checkered dielectric) on a floor under a sky with a bright spot,
    /// lit by a point light, a directional light and a rect: every kind of draw the paths make.
    fn scene() -> CpuScene {
        use crate::geometry::procedural::{plane, uv_sphere};
        let sphere = uv_sphere(0.5, 16, 32);
        let floor = plane(8.0, 8.0, 2);
        let geometry = TruthGeometry::build([
            (0, &sphere, DMat4::from_translation(DVec3::new(-0.6, 0.5, 0.0))),
            (1, &sphere, DMat4::from_translation(DVec3::new(0.6, 0.5, 0.3))),
            (2, &floor, DMat4::IDENTITY),
        ]);
        let (w, h) = (64, 32);
        let texels = (0..w * h)
            .map(|i| match (i % w, i / w) {
                (40..=42, 8..=9) => DVec3::new(300.0, 280.0, 250.0),
                (x, y) => DVec3::new(0.2 + 0.01 * y as f64, 0.3, 0.4 + 0.005 * x as f64),
            })
            .collect();
        let image = crate::environment::prefilter::EquirectImage { width: w, height: h, texels };
        CpuScene::new(geometry, CpuEnvironment::new(&image)).expect("an Embree scene")
    }

    fn material(base: [f32; 3], metallic: f32, smoothness: f32, checker: f32) -> GpuMaterial {
        GpuMaterial {
            base_color: [base[0], base[1], base[2], 1.0],
            params: [metallic, smoothness, checker, 0.0],
            checker_color: [0.9, 0.9, 0.9, 1.0],
            ..GpuMaterial::zeroed()
        }
    }

    fn light(kind: f32, position: [f32; 3], direction: [f32; 3], color: f32, params: [f32; 4]) -> GpuLight {
        GpuLight {
            position: [position[0], position[1], position[2], kind],
            direction: [direction[0], direction[1], direction[2], 0.0],
            color: [color, color, color, 1.0],
            params,
            shape: [1.0, 0.0, 0.0, 0.0],
            ..GpuLight::zeroed()
        }
    }

    #[test]
    fn the_lockstep_paths_are_the_scalar_paths_to_the_bit() {
        let scene = scene();
        let mut frame = FrameUniforms::zeroed();
        let camera = DVec3::new(0.0, 1.2, 3.5);
        let view = DMat4::look_at_rh(camera, DVec3::new(0.0, 0.4, 0.0), DVec3::Y);
        let inv = (DMat4::perspective_rh(0.8, 1.0, 0.1, 100.0) * view).inverse().as_mat4();
        frame.inv_view_proj = inv.to_cols_array_2d();
        frame.camera_pos = [camera.x as f32, camera.y as f32, camera.z as f32, 1.0];
        frame.env = [0.0, 1.0, 0.0, 0.0];
        frame.subject = material([0.9, 0.6, 0.3], 1.0, 0.7, 0.0);
        let lights = [
            light(1.0, [1.0, 2.5, 1.5], [0.0, -1.0, 0.0], 6.0, [10.0, 0.0, 0.0, 0.0]),
            light(0.0, [0.0; 3], [0.3, -1.0, -0.4], 1.5, [0.0; 4]),
            light(LIGHT_RECT_KIND, [-1.0, 2.0, 1.0], [0.3, -1.0, -0.2], 4.0, [0.0, 0.4, 0.25, 0.0]),
        ];
        let materials = [
            (frame.subject, true),
            (material([0.2, 0.5, 0.8], 0.0, 0.4, 0.1), false),
            (material([0.6, 0.6, 0.6], 0.0, 0.2, 0.5), false),
        ];
        let fixed_maps = crate::materials::fixed::FixedMaps::default();
        for kind in [TruthKind::Physical, TruthKind::SameBrdf] {
            let twin: Option<&dyn crate::shading::twin::SurfaceTwin> = Some(&crate::shading::twin::UrpLit);
            let inputs = CpuTruthInputs {
                pipeline: crate::pipelines::Pipeline::Urp,
                kind,
                subject_twin: twin,
                fixed_twin: twin,
                frame: &frame,
                lights: &lights,
                materials: &materials,
                glass: &[false; 3],
                background: true,
                size: (12, 10),
                subject_role: 2,
                fixed_role: 1,
                fixed_maps: &fixed_maps,
                subject_coverage: 1.0,
                subject_maps: None,
                subject_detail: false,
                subject_surface: Default::default(),
            };
            for roulette in [false, true] {
                let tracer = Tracer::new(&scene, &inputs, 2, roulette);
                assert!(tracer.lockstep());
                // Every path, lane by lane: the same f64 sums and first objects as one at a time.
                for (x, y, first) in [(0, 0, 0), (5, 4, 8), (6, 5, 3), (11, 9, 40), (3, 8, 17)] {
                    for n in [1, 5, LANES] {
                        let mut rngs: Vec<Rng> = (0..n).map(|k| Rng::new(y * 12 + x, first + k as u32)).collect();
                        let lockstep = tracer.paths(x, y, &mut rngs);
                        for (k, got) in lockstep.iter().take(n).enumerate() {
                            let want = tracer.path(x, y, &mut Rng::new(y * 12 + x, first + k as u32));
                            assert_eq!(got.1, want.1, "{kind:?} ({x}, {y}) sample {k}");
                            assert_eq!(got.0.to_array().map(f64::to_bits), want.0.to_array().map(f64::to_bits));
                        }
                    }
                }
                // Whole truths, with a batch that leaves partial packets.
                let settings = crate::render::truth::TruthSettings {
                    kind,
                    spp: 27,
                    noise: 0.0,
                    bounces: 2,
                    batch: 13,
                    roulette,
                    ..Default::default()
                };
                let (a, b) = (
                    trace_paths(&scene, &inputs, &settings, true).unwrap(),
                    trace_paths(&scene, &inputs, &settings, false).unwrap(),
                );
                let bits = |t: &crate::render::truth::Truth| {
                    (t.mean.iter().flatten().map(|v| v.to_bits()).collect::<Vec<_>>(), t.roles.clone())
                };
                assert_eq!(bits(&a), bits(&b), "{kind:?}, roulette {roulette}");
                assert!(a.mean.iter().flatten().any(|&v| v > 0.0), "the scene is lit");
            }
        }
    }

    /// scene.wgsl's rect-light kind, as the GPU light records it.
    const LIGHT_RECT_KIND: f32 = super::super::LIGHT_RECT as f32;
}
