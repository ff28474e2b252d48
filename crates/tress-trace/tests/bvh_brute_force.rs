//! The BVH finds the same nearest hit, and the same set of crossed primitives, as testing every
//! primitive, on random scenes of capsules and triangles.

use glam::Vec3;
use proptest::prelude::*;
use tress_hair::Aabb;
use tress_hair::rng::Rng;
use tress_trace::bvh::{Bvh, Split, Visit};
use tress_trace::geometry::{Ray, intersect_capsule, intersect_triangle};

#[derive(Clone, Copy, Debug)]
enum Prim {
    Capsule { a: Vec3, b: Vec3, r: f32 },
    Tri { v0: Vec3, e1: Vec3, e2: Vec3 },
}

impl Prim {
    fn hit(&self, ray: &Ray) -> Option<f32> {
        match *self {
            Prim::Capsule { a, b, r } => intersect_capsule(ray, a, b, r).map(|h| h.t),
            Prim::Tri { v0, e1, e2 } => intersect_triangle(ray, v0, e1, e2).map(|h| h.t),
        }
    }

    fn bounds(&self) -> Aabb {
        match *self {
            Prim::Capsule { a, b, r } => Aabb {
                min: a.min(b) - Vec3::splat(r),
                max: a.max(b) + Vec3::splat(r),
            },
            Prim::Tri { v0, e1, e2 } => Aabb::EMPTY.grow(v0).grow(v0 + e1).grow(v0 + e2),
        }
    }
}

fn point(rng: &mut Rng, extent: f32) -> Vec3 {
    Vec3::new(
        rng.range(-extent, extent),
        rng.range(-extent, extent),
        rng.range(-extent, extent),
    )
}

/// Hair-like clutter: short thin capsules in chains, plus some triangles.
fn scene(seed: u64, capsules: usize, triangles: usize) -> Vec<Prim> {
    let mut rng = Rng::new(seed);
    let mut prims = Vec::new();
    while prims.len() < capsules {
        let mut p = point(&mut rng, 5.0);
        let dir = rng.on_sphere();
        for _ in 0..8 {
            let q = p + (dir + rng.on_sphere() * 0.5) * rng.range(0.1, 1.0);
            prims.push(Prim::Capsule {
                a: p,
                b: q,
                r: rng.range(0.005, 0.1),
            });
            p = q;
        }
    }
    for _ in 0..triangles {
        let v0 = point(&mut rng, 6.0);
        prims.push(Prim::Tri {
            v0,
            e1: rng.on_sphere() * rng.range(0.1, 2.0),
            e2: rng.on_sphere() * rng.range(0.1, 2.0),
        });
    }
    prims
}

fn check(seed: u64, capsules: usize, triangles: usize, rays: usize) -> Result<(), TestCaseError> {
    let prims = scene(seed, capsules, triangles);
    let bounds: Vec<Aabb> = prims.iter().map(Prim::bounds).collect();
    for split in [Split::Median, Split::Sah] {
        check_with(
            &prims,
            &Bvh::build(&bounds, split),
            seed,
            rays,
            capsules >= 1000,
        )?;
    }
    Ok(())
}

fn check_with(
    prims: &[Prim],
    bvh: &Bvh,
    seed: u64,
    rays: usize,
    dense: bool,
) -> Result<(), TestCaseError> {
    let order = bvh.order();
    let mut rng = Rng::new(seed ^ 0xabc);
    let mut hits = 0;
    for _ in 0..rays {
        // Rays from outside towards the clutter, some starting inside it, some short.
        let origin = point(&mut rng, 9.0);
        let target = point(&mut rng, 3.0);
        let dir = (target - origin).normalize();
        let t_max = if rng.f32() < 0.3 {
            rng.range(1.0, 10.0)
        } else {
            f32::INFINITY
        };
        let ray = Ray::new(origin, dir, 0.0, t_max);

        let brute = prims
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.hit(&ray).map(|t| (t, i)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let fast = bvh.nearest(&ray, |pos, r| {
            let i = order[pos] as usize;
            prims[i].hit(r).map(|t| (t, i))
        });
        prop_assert_eq!(brute.map(|b| b.1), fast.map(|f| f.1));
        prop_assert_eq!(brute.map(|b| b.0), fast.map(|f| f.0));
        hits += usize::from(brute.is_some());

        let mut all: Vec<usize> = prims
            .iter()
            .enumerate()
            .filter(|(_, p)| p.hit(&ray).is_some())
            .map(|(i, _)| i)
            .collect();
        let mut visited = Vec::new();
        bvh.for_each_hit(&ray, |pos| {
            let i = order[pos] as usize;
            if prims[i].hit(&ray).is_some() {
                visited.push(i);
            }
            Visit::Continue
        });
        all.sort_unstable();
        visited.sort_unstable();
        prop_assert_eq!(all, visited);
    }
    // Dense scenes make many rays hit something, so the comparison is not vacuous.
    if dense {
        prop_assert!(hits * 4 > rays, "only {} of {} rays hit", hits, rays);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn bvh_nearest_and_all_hits_match_brute_force(
        seed in any::<u64>(),
        capsules in 0usize..3000,
        triangles in 0usize..200,
    ) {
        check(seed, capsules, triangles, 200)?;
    }
}

#[test]
fn large_scene_matches_brute_force() {
    // Large enough for the parallel build and the median fallback to matter.
    check(7, 40_000, 2_000, 300).unwrap();
}

#[test]
fn early_stop_visits_no_more() {
    let prims = scene(3, 2000, 0);
    let bounds: Vec<Aabb> = prims.iter().map(Prim::bounds).collect();
    let bvh = Bvh::build(&bounds, Split::Sah);
    let ray = Ray::new(Vec3::new(-20.0, 0.0, 0.0), Vec3::X, 0.0, f32::INFINITY);
    let mut n = 0;
    bvh.for_each_hit(&ray, |_| {
        n += 1;
        if n == 3 { Visit::Stop } else { Visit::Continue }
    });
    assert_eq!(n, 3);
}
