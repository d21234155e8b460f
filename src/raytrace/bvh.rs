//! Closest-hit tracing of a sphere scene through an obvhs compressed wide BVH (CWBVH).
//!
//! The BVH is traversed in f32, but every candidate sphere is intersected exactly in f64
//! ([`sphere::intersect`]) and the closest hit is kept in f64, ties going to the lowest
//! point index. The boxes handed to the builder are inflated by a margin that covers the
//! f32 rounding of the traversal, and the pruning distance given back to obvhs is the best
//! hit rounded up, so traversal never discards a sphere that the exact test would pick:
//! [`Tracer::trace`] returns exactly what [`trace_brute_force`] returns.

use std::time::{Duration, Instant};

use glam::{DVec3, Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::bvh2::reinsertion::ReinsertionOptimizer;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh;
use obvhs::cwbvh::node::CwBvhNode;
use obvhs::ploc::PlocBuilder;
use obvhs::ray::{Ray, RayHit};

pub use obvhs::BvhBuildParams;

use super::RaytraceError;
use crate::projection::sphere;
use crate::scene::Scene;

/// Box inflation relative to the scene's reach (largest |coordinate| + radius): some
/// 30 f32 ulps, well above the slab test's rounding (a few ulps of the distances involved).
const BOX_MARGIN_RELATIVE: f32 = 2e-6;

/// The closest sphere along a ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Index of the point in the scene.
    pub index: usize,
    /// Distance along the (unit) ray from its origin, metres.
    pub t: f64,
}

/// One sphere as the tracer stores it: 16 bytes, in BVH leaf order.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(C)]
struct SphereRecord {
    center: [f32; 3],
    radius: f32,
}

impl SphereRecord {
    #[inline]
    fn center(&self) -> DVec3 {
        Vec3::from_array(self.center).as_dvec3()
    }
}

/// Memory held by a built [`Tracer`], bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TracerMemory {
    /// CWBVH nodes (80 bytes each).
    pub nodes: usize,
    /// BVH leaf order to point index (4 bytes per point).
    pub primitive_indices: usize,
    /// Sphere records (16 bytes per point).
    pub spheres: usize,
}

impl TracerMemory {
    /// Sum of all parts.
    pub fn total(&self) -> usize {
        self.nodes + self.primitive_indices + self.spheres
    }
}

/// A BVH over a scene's spheres, built once and reusable for any number of frames.
#[derive(Debug, Clone)]
pub struct Tracer {
    bvh: CwBvh,
    spheres: Vec<SphereRecord>,
    build_time: Duration,
    padding: f64,
}

impl Tracer {
    /// Builds the BVH over `scene` with obvhs's medium preset.
    pub fn new(scene: &Scene) -> Result<Self, RaytraceError> {
        Self::with_params(scene, BvhBuildParams::medium_build())
    }

    /// Builds the BVH over `scene` with the given obvhs build parameters (CWBVH leaves hold
    /// at most 3 spheres whatever `max_prims_per_leaf` says).
    pub fn with_params(scene: &Scene, params: BvhBuildParams) -> Result<Self, RaytraceError> {
        Self::build(scene, params, 0.0)
    }

    /// Builds the BVH over `scene` with every sphere's box grown by `padding` metres, for
    /// [`Tracer::trace_own_rays`] with ray origins up to `padding` from the traversal origin.
    pub fn padded(scene: &Scene, padding: f64) -> Result<Self, RaytraceError> {
        Self::build(scene, BvhBuildParams::medium_build(), padding)
    }

    /// How far ([`Tracer::padded`]) the spheres' boxes were grown, metres.
    pub fn padding(&self) -> f64 {
        self.padding
    }

    fn build(scene: &Scene, params: BvhBuildParams, padding: f64) -> Result<Self, RaytraceError> {
        let start = Instant::now();
        let n = scene.len();
        if u32::try_from(n).is_err() {
            return Err(RaytraceError::TooManyPoints(n));
        }
        let mut reach = 0.0f32;
        for (i, p) in scene.positions.iter().enumerate() {
            let r = scene.radii.get(i);
            if !p.is_finite() {
                return Err(RaytraceError::NonFinitePosition(i));
            }
            if !(r.is_finite() && r >= 0.0) {
                return Err(RaytraceError::InvalidRadius {
                    index: i,
                    radius: r,
                });
            }
            reach = reach.max(p.abs().max_element() + r);
        }
        let padding = padding.max(0.0);
        let reach = reach.max(1.0) + padding as f32;
        let margin = BOX_MARGIN_RELATIVE * reach + padding as f32;
        let bvh = if n == 0 {
            CwBvh::default()
        } else {
            let aabbs: Vec<Aabb> = scene
                .positions
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let c = Vec3A::from(*p);
                    let e = Vec3A::splat(scene.radii.get(i) + margin);
                    Aabb::new(c - e, c + e)
                })
                .collect();
            let mut bvh2 = PlocBuilder::with_capacity(n).build(
                params.ploc_search_distance,
                &aabbs,
                (0..n as u32).collect(),
                params.sort_precision,
                params.search_depth_threshold,
            );
            drop(aabbs);
            ReinsertionOptimizer::default().run(&mut bvh2, params.reinsertion_batch_ratio, None);
            bvh2_to_cwbvh(&bvh2, params.max_prims_per_leaf.clamp(1, 3), true, false)
        };
        let spheres = bvh
            .primitive_indices
            .iter()
            .map(|&i| SphereRecord {
                center: scene.positions[i as usize].to_array(),
                radius: scene.radii.get(i as usize),
            })
            .collect();
        Ok(Tracer {
            bvh,
            spheres,
            build_time: start.elapsed(),
            padding,
        })
    }

    /// Number of spheres.
    pub fn len(&self) -> usize {
        self.spheres.len()
    }

    /// True when the tracer holds no sphere.
    pub fn is_empty(&self) -> bool {
        self.spheres.is_empty()
    }

    /// Wall time the build took (box computation, BVH build, sphere reordering).
    pub fn build_time(&self) -> Duration {
        self.build_time
    }

    /// Number of CWBVH nodes.
    pub fn node_count(&self) -> usize {
        self.bvh.nodes.len()
    }

    /// Memory held by the BVH and the sphere records.
    pub fn memory(&self) -> TracerMemory {
        TracerMemory {
            nodes: self.bvh.nodes.len() * size_of::<CwBvhNode>(),
            primitive_indices: self.bvh.primitive_indices.len() * size_of::<u32>(),
            spheres: self.spheres.len() * size_of::<SphereRecord>(),
        }
    }

    /// Closest sphere hit by the ray `origin + t·dir`, `t > 0` (`dir` need not be unit
    /// length; `t` is measured in units of the normalised direction). `None` on a miss or
    /// for a zero or non-finite direction.
    pub fn trace(&self, origin: DVec3, dir: DVec3) -> Option<Hit> {
        self.closest(origin, dir, |_| origin)
    }

    /// Closest hit when each sphere is seen along its own ray `origin_of(centre) + t dir`
    /// (a depth map, DESIGN §9), every origin within [`Tracer::padding`] of `center`; `t` is
    /// measured along the sphere's own ray, ties to the lowest index as [`Tracer::trace`].
    ///
    /// Traverses from `center`: a sphere's own hit at `t` lies within the padding of
    /// `center + t dir`, so the ray from `center` meets its padded box by `t`, and pruning at
    /// the best own-ray `t` drops no sphere that the exact test would pick.
    pub fn trace_own_rays(
        &self,
        center: DVec3,
        dir: DVec3,
        origin_of: impl Fn(DVec3) -> DVec3,
    ) -> Option<Hit> {
        self.closest(center, dir, |c| {
            let origin = origin_of(c);
            debug_assert!((origin - center).length() <= self.padding * (1.0 + 1e-9) + 1e-12);
            origin
        })
    }

    /// Traverses along `start + t dir` and tests each candidate sphere (centre `c`) with
    /// the ray from `origin_of(c)`; the nearest such hit, ties to the lowest index.
    fn closest(&self, start: DVec3, dir: DVec3, origin_of: impl Fn(DVec3) -> DVec3) -> Option<Hit> {
        let dir = unit(dir)?;
        if !start.is_finite() || self.spheres.is_empty() {
            return None;
        }
        let ray = Ray::new_inf(Vec3A::from(start.as_vec3()), Vec3A::from(dir.as_vec3()));
        let mut best: Option<(f64, u32)> = None;
        self.bvh.ray_traverse(ray, &mut RayHit::none(), |_, id| {
            let s = &self.spheres[id];
            let c = s.center();
            let Some(t) = sphere::intersect(origin_of(c), dir, c, s.radius as f64) else {
                return f32::INFINITY;
            };
            let index = self.bvh.primitive_indices[id];
            if is_closer(t, index, best) {
                best = Some((t, index));
                prune_distance(t)
            } else {
                f32::INFINITY
            }
        });
        best.map(|(t, index)| Hit {
            index: index as usize,
            t,
        })
    }
}

/// `dir` normalised in f64, or `None` when it is zero or not finite.
#[inline]
pub(crate) fn unit(dir: DVec3) -> Option<DVec3> {
    let len = dir.length();
    (len.is_finite() && len > 0.0).then(|| dir / len)
}

/// True when a hit at `t` on point `index` beats `best`: nearer, or as near with a lower
/// index (so results do not depend on traversal order).
#[inline]
fn is_closer(t: f64, index: u32, best: Option<(f64, u32)>) -> bool {
    match best {
        None => true,
        Some((bt, bi)) => t < bt || (t == bt && index < bi),
    }
}

/// The f32 distance handed to obvhs for pruning: the best hit rounded up by a few ulps so
/// a box whose entry rounds slightly past an exact tie is still visited.
#[inline]
fn prune_distance(t: f64) -> f32 {
    (t as f32) * (1.0 + 4.0 * f32::EPSILON) + f32::MIN_POSITIVE
}

/// Closest hit by testing every sphere of `scene` (the reference [`Tracer::trace`] must
/// equal): same intersection, same tie rule, no BVH.
pub fn trace_brute_force(scene: &Scene, origin: DVec3, dir: DVec3) -> Option<Hit> {
    let dir = unit(dir)?;
    let mut best: Option<(f64, u32)> = None;
    for (i, p) in scene.positions.iter().enumerate() {
        let r = scene.radii.get(i) as f64;
        if let Some(t) = sphere::intersect(origin, dir, p.as_dvec3(), r)
            && is_closer(t, i as u32, best)
        {
            best = Some((t, i as u32));
        }
    }
    best.map(|(t, index)| Hit {
        index: index as usize,
        t,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn empty_and_single_sphere_scenes() {
        let empty = Scene::new(DVec3::ZERO, vec![], 0.1);
        let t = Tracer::new(&empty).unwrap();
        assert!(t.trace(DVec3::ZERO, DVec3::Y).is_none());
        let one = Scene::new(DVec3::ZERO, vec![Vec3::new(0.0, 3.0, 0.0)], 0.5);
        let t = Tracer::new(&one).unwrap();
        let hit = t.trace(DVec3::ZERO, DVec3::Y).unwrap();
        assert_eq!(hit, Hit { index: 0, t: 2.5 });
        assert!(t.trace(DVec3::ZERO, -DVec3::Y).is_none());
        assert!(t.trace(DVec3::ZERO, DVec3::ZERO).is_none());
    }

    #[test]
    fn duplicate_points_resolve_to_the_lowest_index() {
        let mut pts = vec![Vec3::new(0.0, 3.0, 0.0); 50];
        pts.extend((0..200).map(|k| Vec3::new(k as f32 * 0.01, 5.0, 0.0)));
        let scene = Scene::new(DVec3::ZERO, pts, 0.5);
        let t = Tracer::new(&scene).unwrap();
        assert_eq!(t.trace(DVec3::ZERO, DVec3::Y).unwrap().index, 0);
        assert_eq!(
            trace_brute_force(&scene, DVec3::ZERO, DVec3::Y)
                .unwrap()
                .index,
            0
        );
    }

    #[test]
    fn bad_input_is_an_error_naming_the_point() {
        let scene = Scene::new(DVec3::ZERO, vec![Vec3::ZERO, Vec3::NAN], 0.1);
        let e = Tracer::new(&scene).unwrap_err();
        assert!(e.to_string().contains("point 1"), "{e}");
        let scene = Scene::new(DVec3::ZERO, vec![Vec3::ZERO], -0.1);
        assert!(Tracer::new(&scene).is_err());
    }

    #[test]
    fn own_rays_through_a_padded_bvh_equal_testing_every_sphere() {
        use crate::rng::SplitMix64;
        let mut rng = SplitMix64::new(7);
        let mut pts = Vec::new();
        let mut radii = Vec::new();
        for _ in 0..3000 {
            let d = 10f64.powf(rng.range(-0.5, 1.5));
            let dir = DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            pts.push((d * dir.normalize_or(DVec3::Y)).as_vec3());
            radii.push((rng.range(0.005, 0.05) * d) as f32);
        }
        let scene = Scene {
            radii: crate::scene::Radii::PerPoint(radii),
            ..Scene::new(DVec3::ZERO, pts, 0.1)
        };
        let pad = 0.2;
        let tracer = Tracer::padded(&scene, pad).unwrap();
        assert_eq!(tracer.padding(), pad);
        // Each sphere's own origin: up to `pad` from C along a side vector, by its distance.
        let side = DVec3::new(0.6, -0.8, 0.0);
        let origin_of = |c: DVec3| pad * (c.length() / 40.0).min(1.0) * side;
        let (mut hits, mut differ_from_c) = (0, 0);
        for _ in 0..3000 {
            let dir = DVec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            )
            .normalize_or(DVec3::Y);
            let got = tracer.trace_own_rays(DVec3::ZERO, dir, origin_of);
            // The direction as the tracer normalises it.
            let dir = unit(dir).unwrap();
            let mut want: Option<(f64, u32)> = None;
            for (i, p) in scene.positions.iter().enumerate() {
                let c = p.as_dvec3();
                let r = scene.radii.get(i) as f64;
                if let Some(t) = sphere::intersect(origin_of(c), dir, c, r)
                    && is_closer(t, i as u32, want)
                {
                    want = Some((t, i as u32));
                }
            }
            let want = want.map(|(t, i)| Hit {
                index: i as usize,
                t,
            });
            assert_eq!(got, want, "dir {dir}");
            hits += got.is_some() as u32;
            differ_from_c +=
                (got.map(|h| h.index) != tracer.trace(DVec3::ZERO, dir).map(|h| h.index)) as u32;
        }
        // Enough hits to judge, and the own rays matter.
        assert!(
            hits > 1000 && differ_from_c > 10,
            "{hits} hits, {differ_from_c} differ"
        );
    }

    #[test]
    fn memory_reports_sixteen_bytes_per_sphere() {
        let pts = (0..1000).map(|k| Vec3::new(k as f32, 0.0, 0.0)).collect();
        let t = Tracer::new(&Scene::new(DVec3::ZERO, pts, 0.1)).unwrap();
        let m = t.memory();
        assert_eq!(m.spheres, 16_000);
        assert_eq!(m.primitive_indices, 4_000);
        assert_eq!(m.nodes, 80 * t.node_count());
        assert!(t.node_count() > 0);
    }
}
