//! The scene's opaque triangles as a CPU ray check: the shadows' visibility in the reference
//! shading (`reference.rs`) and the lightmap baker.

use super::Scene;
use glam::DVec3;

/// The shadows' CPU visibility check: the scene's opaque triangles in world space (blended
/// surfaces, lines and points cast no shadow, as in the shadow pass), and whether a segment
/// between two points crosses one.
pub struct Occluders {
    triangles: Vec<[DVec3; 3]>,
}

impl Occluders {
    pub fn of(scene: &Scene) -> Self {
        let mut triangles = Vec::new();
        for o in &scene.objects {
            let Some(mesh) = scene.meshes.get(o.mesh) else { continue };
            if mesh.topology != crate::scene::Topology::Triangles
                || scene.materials.get(o.material).is_some_and(|m| m.is_blended())
            {
                continue;
            }
            let p = |i: u32| {
                mesh.vertices
                    .get(i as usize)
                    .map(|v| o.transform.transform_point3(glam::Vec3::from(v.position).as_dvec3()))
            };
            for t in mesh.indices.chunks_exact(3) {
                if let (Some(a), Some(b), Some(c)) = (p(t[0]), p(t[1]), p(t[2])) {
                    triangles.push([a, b, c]);
                }
            }
        }
        Self { triangles }
    }

    /// Whether the open segment from `from` to `to` crosses a triangle (Möller-Trumbore in
    /// f64; hits within 1e-9 of either end do not count).
    pub fn blocked(&self, from: DVec3, to: DVec3) -> bool {
        let d = to - from;
        self.triangles.iter().any(|[a, b, c]| {
            let (e1, e2) = (*b - *a, *c - *a);
            let p = d.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-300 {
                return false;
            }
            let inv = 1.0 / det;
            let s = from - *a;
            let u = s.dot(p) * inv;
            if !(0.0..=1.0).contains(&u) {
                return false;
            }
            let q = s.cross(e1);
            let v = d.dot(q) * inv;
            if v < 0.0 || u + v > 1.0 {
                return false;
            }
            let t = e2.dot(q) * inv;
            t > 1e-9 && t < 1.0 - 1e-9
        })
    }
}
