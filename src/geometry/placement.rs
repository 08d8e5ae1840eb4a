//! Where a scene's meshes sit in the world: their bounds after each object's transform. The light
//! budget ranks lights at object centres; directional shadow maps fit the whole scene.

use glam::DVec3;

use super::Mesh;
use crate::declarations::scene::Scene;

/// World-space bounds of every object together.
pub fn world_bounds(scene: &Scene, meshes: &[Mesh]) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::MAX);
    let mut hi = DVec3::splat(f64::MIN);
    for (o, mesh) in scene.objects.iter().zip(meshes) {
        let (a, b) = world_bounds_of(o, &mesh.bounds());
        lo = lo.min(a);
        hi = hi.max(b);
    }
    if lo.x > hi.x {
        (DVec3::ZERO, DVec3::ZERO)
    } else {
        (lo, hi)
    }
}

/// Each object's name and the centre of its world-space bounds.
pub fn object_centres(scene: &Scene, meshes: &[Mesh]) -> Vec<(String, DVec3)> {
    scene
        .objects
        .iter()
        .zip(meshes)
        .map(|(o, mesh)| {
            let (lo, hi) = mesh.bounds();
            let centre = (lo.as_dvec3() + hi.as_dvec3()) * 0.5;
            (o.name.clone(), o.transform.matrix().transform_point3(centre))
        })
        .collect()
}

/// The world-space box around an object's object-space `bounds` (its eight corners transformed).
pub fn world_bounds_of(o: &crate::declarations::scene::Object, bounds: &(glam::Vec3, glam::Vec3)) -> (DVec3, DVec3) {
    let (a, b) = *bounds;
    let m = o.transform.matrix();
    let mut lo = DVec3::splat(f64::MAX);
    let mut hi = DVec3::splat(f64::MIN);
    for corner in 0..8 {
        let c = DVec3::new(
            if corner & 1 == 0 { a.x } else { b.x } as f64,
            if corner & 2 == 0 { a.y } else { b.y } as f64,
            if corner & 4 == 0 { a.z } else { b.z } as f64,
        );
        let w = m.transform_point3(c);
        lo = lo.min(w);
        hi = hi.max(w);
    }
    (lo, hi)
}
