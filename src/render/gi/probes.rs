//! Light probes from the bake's sums: each probe's SH L2 (the traced radiance projected, then
//! convolved with the cosine lobe over π, as the ambient term reads it: environment::sh), and an
//! object's probe as Unity interpolates it — the barycentric blend of the four probes of the
//! tetrahedron holding the object's bounds centre (LightProbes.GetInterpolatedProbe). The grid's
//! cubes are cut into six tetrahedra about their main diagonal (Kuhn's subdivision, a valid
//! Delaunay tetrahedralisation of a cube's cospherical corners); a centre outside the grid is
//! clamped onto it, where Unity would extrapolate from the hull's outer cells.

use glam::DVec3;

use crate::declarations::gi::ProbeGrid;
use crate::render::truth::bake::{BakeSums, BAKE_STRIDE};

/// One probe: SH coefficients of E(n)/π (environment::sh's convention), and the visibility of
/// each shadow-mask light (Unity's probe occlusion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probe {
    pub sh: [[f64; 3]; 9],
    pub occlusion: [f64; 4],
}

/// The probe of each grid point from the bake's sums at `sums[first..]`.
pub fn probes_from_sums(sums: &BakeSums, first: usize, count: usize) -> Vec<Probe> {
    sums[first..first + count]
        .iter()
        .map(|s: &[[f32; 4]; BAKE_STRIDE]| {
            let n = (s[9][3] as f64).max(1.0);
            let mut c = [[0.0; 3]; 9];
            for (ci, si) in c.iter_mut().zip(s) {
                *ci = [si[0] as f64 / n, si[1] as f64 / n, si[2] as f64 / n];
            }
            Probe { sh: crate::environment::sh::convolve(c), occlusion: s[10].map(|v| v as f64 / n) }
        })
        .collect()
}

/// The probe an object whose bounds centre is `p` takes from the grid's `probes`.
pub fn interpolate(grid: &ProbeGrid, probes: &[Probe], p: DVec3) -> Probe {
    let [nx, ny, nz] = grid.counts.map(|c| c as usize);
    let (min, max) = (DVec3::from(grid.min), DVec3::from(grid.max));
    // Cell coordinates: the cube (i, j, k) and the position within it, clamped onto the grid.
    let mut cell = [0usize; 3];
    let mut t = [0.0f64; 3];
    for (a, n) in [nx, ny, nz].into_iter().enumerate() {
        if n < 2 {
            continue;
        }
        let u = ((p[a] - min[a]) / (max[a] - min[a])).clamp(0.0, 1.0) * (n - 1) as f64;
        let i = (u.floor() as usize).min(n - 2);
        cell[a] = i;
        t[a] = u - i as f64;
    }
    let index = |d: [usize; 3]| {
        let at = |a: usize, n: usize| if n < 2 { 0 } else { cell[a] + d[a] };
        at(0, nx) + nx * (at(1, ny) + ny * at(2, nz))
    };
    // Kuhn's tetrahedron: walk from corner 000 to 111 along the axes in decreasing order of t;
    // the barycentric weights are the gaps between the sorted coordinates.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| t[b].total_cmp(&t[a]).then(a.cmp(&b)));
    let sorted = order.map(|a| t[a]);
    let weights = [1.0 - sorted[0], sorted[0] - sorted[1], sorted[1] - sorted[2], sorted[2]];
    let mut corner = [0usize; 3];
    let mut out = Probe { sh: [[0.0; 3]; 9], occlusion: [0.0; 4] };
    for (k, w) in weights.into_iter().enumerate() {
        if k > 0 {
            corner[order[k - 1]] = 1;
        }
        let probe = &probes[index(corner)];
        for (o, c) in out.sh.iter_mut().zip(&probe.sh) {
            for ch in 0..3 {
                o[ch] += w * c[ch];
            }
        }
        for (o, c) in out.occlusion.iter_mut().zip(&probe.occlusion) {
            *o += w * c;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(v: f64) -> Probe {
        let mut sh = [[0.0; 3]; 9];
        sh[0] = [v; 3];
        Probe { sh, occlusion: [v; 4] }
    }

    #[test]
    fn interpolation_is_linear_inside_a_tetrahedron_and_exact_at_probes() {
        let grid = ProbeGrid { min: [0.0; 3], max: [2.0, 1.0, 1.0], counts: [3, 2, 2] };
        // A linear field f = x + 2y + 3z at the probes is reproduced exactly everywhere.
        let f = |p: [f64; 3]| p[0] + 2.0 * p[1] + 3.0 * p[2];
        let probes: Vec<Probe> = grid.positions().into_iter().map(|p| probe(f(p))).collect();
        for p in [[0.0, 0.0, 0.0], [0.3, 0.7, 0.2], [1.6, 0.1, 0.9], [2.0, 1.0, 1.0], [1.0, 0.5, 0.5]] {
            let got = interpolate(&grid, &probes, DVec3::from(p)).sh[0][0];
            assert!((got - f(p)).abs() < 1e-12, "{p:?}: {got} vs {}", f(p));
        }
        // Outside the grid: clamped onto it.
        let got = interpolate(&grid, &probes, DVec3::new(5.0, -1.0, 0.5)).sh[0][0];
        assert!((got - f([2.0, 0.0, 0.5])).abs() < 1e-12);
        // The weights are a partition of unity.
        let ones: Vec<Probe> = grid.positions().into_iter().map(|_| probe(1.0)).collect();
        let got = interpolate(&grid, &ones, DVec3::new(0.77, 0.31, 0.64)).occlusion[2];
        assert!((got - 1.0).abs() < 1e-12);
    }
}
