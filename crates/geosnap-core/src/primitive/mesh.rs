//! Triangle meshes of primitives: smooth normals on curved surfaces, split vertices with
//! flat normals at sharp edges (cap rims, box edges), counter-clockwise front faces seen
//! from outside.

use glam::DVec3;

/// An indexed triangle mesh in model space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Unit vertex normals, one per position.
    pub normals: Vec<DVec3>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    fn vertex(&mut self, p: DVec3, n: DVec3) -> u32 {
        self.positions.push(p);
        self.normals.push(n.normalize_or_zero());
        (self.positions.len() - 1) as u32
    }

    /// The axis-aligned bounds `(min, max)`, `None` when empty.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
        )
    }

    /// Appends another mesh.
    pub fn append(&mut self, other: &Self) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    }

    /// The signed volume (positive for a closed mesh with outward faces).
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize]);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// A flat disc (cap) at `center` facing `normal`, with the rim points given.
    fn cap(&mut self, center: DVec3, normal: DVec3, rim: &[DVec3]) {
        let c = self.vertex(center, normal);
        let first = self.positions.len() as u32;
        for p in rim {
            self.vertex(*p, normal);
        }
        let n = rim.len() as u32;
        for i in 0..n {
            let (a, b) = (first + i, first + (i + 1) % n);
            // Orient counter-clockwise around the outward normal.
            let (pa, pb) = (self.positions[a as usize], self.positions[b as usize]);
            if (pa - center).cross(pb - center).dot(normal) >= 0.0 {
                self.triangles.push([c, a, b]);
            } else {
                self.triangles.push([c, b, a]);
            }
        }
    }

    /// A tube through rings of points with smooth normals, plus flat caps at both ends.
    ///
    /// `rings[i]` holds `segments` points around spine point `centers[i]`; consecutive
    /// rings are joined by quads. Ring points must run counter-clockwise around the spine
    /// direction (from ring 0 to the last ring).
    pub(crate) fn tube(centers: &[DVec3], rings: &[Vec<DVec3>], normals: &[Vec<DVec3>]) -> Self {
        let mut mesh = Self::default();
        let Some(segments) = rings.first().map(Vec::len) else {
            return mesh;
        };
        let base = mesh.positions.len() as u32;
        for (ring, ring_normals) in rings.iter().zip(normals) {
            for (p, n) in ring.iter().zip(ring_normals) {
                mesh.vertex(*p, *n);
            }
        }
        let s = segments as u32;
        for i in 0..rings.len().saturating_sub(1) as u32 {
            for j in 0..s {
                let a = base + i * s + j;
                let b = base + i * s + (j + 1) % s;
                let c = a + s;
                let d = b + s;
                mesh.triangles.push([a, b, d]);
                mesh.triangles.push([a, d, c]);
            }
        }
        if let (Some(first), Some(last)) = (rings.first(), rings.last()) {
            let n0 = (centers[0] - centers[1]).normalize_or_zero();
            let k = centers.len() - 1;
            let n1 = (centers[k] - centers[k - 1]).normalize_or_zero();
            mesh.cap(centers[0], n0, first);
            mesh.cap(centers[k], n1, last);
        }
        mesh
    }
}

/// Two unit vectors completing `axis` to a right-handed orthonormal frame (u, v, axis).
pub(crate) fn orthonormal_basis(axis: DVec3) -> (DVec3, DVec3) {
    let a = axis.normalize_or(DVec3::Y);
    let helper = if a.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = helper.cross(a).normalize();
    let v = a.cross(u);
    (u, v)
}

/// A surface of revolution about a straight axis: profile samples `(h, r)` from bottom
/// to top (h along `axis` from `bottom`), closed with flat caps.
pub(crate) fn revolution(
    bottom: DVec3,
    axis: DVec3,
    profile: &[(f64, f64)],
    segments: usize,
) -> TriMesh {
    let (u, v) = orthonormal_basis(axis);
    let a = axis.normalize_or(DVec3::Y);
    let mut centers = Vec::new();
    let mut rings = Vec::new();
    let mut normals = Vec::new();
    for (i, &(h, r)) in profile.iter().enumerate() {
        // Slope dr/dh from neighbouring samples, for the normals of a varying radius.
        let (lo, hi) = (
            profile[i.saturating_sub(1)],
            profile[(i + 1).min(profile.len() - 1)],
        );
        let slope = if (hi.0 - lo.0).abs() > 0.0 {
            (hi.1 - lo.1) / (hi.0 - lo.0)
        } else {
            0.0
        };
        let center = bottom + a * h;
        let mut ring = Vec::with_capacity(segments);
        let mut ring_normals = Vec::with_capacity(segments);
        for j in 0..segments {
            let t = std::f64::consts::TAU * j as f64 / segments as f64;
            let e = u * t.cos() + v * t.sin();
            ring.push(center + e * r);
            ring_normals.push(e - a * slope);
        }
        centers.push(center);
        rings.push(ring);
        normals.push(ring_normals);
    }
    TriMesh::tube(&centers, &rings, &normals)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::revolution;

    #[test]
    fn a_revolved_cylinder_is_closed_with_the_right_volume() {
        let mesh = revolution(DVec3::ZERO, DVec3::Y, &[(0.0, 1.0), (2.0, 1.0)], 256);
        let expected = std::f64::consts::PI * 2.0;
        assert!(
            (mesh.volume() - expected).abs() < 1e-3 * expected,
            "{}",
            mesh.volume()
        );
        let (lo, hi) = mesh.bounds().unwrap();
        assert!((lo - DVec3::new(-1.0, 0.0, -1.0)).length() < 1e-9);
        assert!((hi - DVec3::new(1.0, 2.0, 1.0)).length() < 1e-9);
        assert!(mesh
            .normals
            .iter()
            .all(|n| (n.length() - 1.0).abs() < 1e-12));
    }
}
