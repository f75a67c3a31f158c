//! Bounding meshes for light volumes. A low-poly sphere whose vertices lie on the radius cuts
//! the light off between its vertices (a failure users of other deferred renderers report), so both meshes are scaled until
//! they **circumscribe** the true shape: every face plane lies at or beyond the radius.

use crate::renderer::records::{LightRecord, LIGHT_KIND_SPOT};
use glam::{Vec3, Vec4};

/// Relative safety margin on top of exact circumscription, for rasterisation of faces that
/// coincide with geometry.
pub const VOLUME_MARGIN: f32 = 1.002;

/// Spot lights wider than this are bounded by a sphere: the capped pyramid's volume
/// (R^3 tan^2(a) * 4/3 for a square base, larger for more sides) exceeds the sphere's
/// (4/3 pi R^3) once tan(a) > ~1.8, i.e. about 61 degrees. We switch at 60.
pub const CONE_MAX_ANGLE_DEG: f32 = 60.0;

/// Orthonormal basis around a unit vector (Duff et al. 2017), the same as `basis` in
/// `culling/lights.wgsl`, so CPU-side placement matches what the GPU draws.
pub fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// Places a unit-mesh vertex on light `l`'s bounding volume (view space), as `volume_position`
/// in the shader.
pub fn place_light(v: Vec4, l: &LightRecord) -> Vec3 {
    place(v, l.position.into(), l.radius, l.direction.into(), l.volume_tan, l.volume_pad)
}

/// Places a unit-mesh vertex on a light (view space), grown all round by `pad`. A sphere's
/// radius grows by `pad`. A cone of tangent t moves its apex back by b = pad (1 + 1/t) and
/// reaches radius + pad + b: a point within `pad` of one inside the old cone lies at most `pad`
/// further along the axis and `pad` further out, and (z + b) t >= z t + pad holds from
/// z = -pad on.
pub fn place(v: Vec4, position: Vec3, radius: f32, direction: Vec3, volume_tan: f32, pad: f32) -> Vec3 {
    if v.w < 0.5 {
        return position + v.truncate() * (radius + pad);
    }
    let (t, u) = basis(direction);
    let back = pad * (1.0 + 1.0 / volume_tan);
    let length = radius + pad + back;
    let r = length * volume_tan;
    position - direction * back + t * (v.x * r) + u * (v.y * r) + direction * (v.z * length)
}

/// A unit mesh: positions with w = 0 (sphere) or 1 (cone), and triangle indices.
#[derive(Clone, Debug)]
pub struct VolumeMesh {
    pub vertices: Vec<Vec4>,
    pub indices: Vec<u32>,
}

impl VolumeMesh {
    /// An icosphere with `subdivisions` levels, scaled to circumscribe the unit sphere.
    pub fn sphere(subdivisions: u32) -> Self {
        let t = (1.0 + 5f32.sqrt()) / 2.0;
        let mut v: Vec<Vec3> = [
            (-1.0, t, 0.0),
            (1.0, t, 0.0),
            (-1.0, -t, 0.0),
            (1.0, -t, 0.0),
            (0.0, -1.0, t),
            (0.0, 1.0, t),
            (0.0, -1.0, -t),
            (0.0, 1.0, -t),
            (t, 0.0, -1.0),
            (t, 0.0, 1.0),
            (-t, 0.0, -1.0),
            (-t, 0.0, 1.0),
        ]
        .iter()
        .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
        .collect();
        let mut f: Vec<[u32; 3]> = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        for _ in 0..subdivisions {
            let mut cache = std::collections::HashMap::new();
            let mut mid = |a: u32, b: u32, v: &mut Vec<Vec3>| -> u32 {
                let key = (a.min(b), a.max(b));
                *cache.entry(key).or_insert_with(|| {
                    v.push(((v[a as usize] + v[b as usize]) * 0.5).normalize());
                    (v.len() - 1) as u32
                })
            };
            let mut next = Vec::with_capacity(f.len() * 4);
            for [a, b, c] in f {
                let ab = mid(a, b, &mut v);
                let bc = mid(b, c, &mut v);
                let ca = mid(c, a, &mut v);
                next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
            }
            f = next;
        }
        // Inradius: the nearest face plane. Scaling by its inverse puts every face at >= 1.
        let inradius = f
            .iter()
            .map(|&[a, b, c]| {
                let (a, b, c) = (v[a as usize], v[b as usize], v[c as usize]);
                (b - a).cross(c - a).normalize().dot(a).abs()
            })
            .fold(f32::INFINITY, f32::min);
        let scale = VOLUME_MARGIN / inradius;
        Self {
            vertices: v.iter().map(|p| (*p * scale).extend(0.0)).collect(),
            indices: f.iter().flatten().copied().collect(),
        }
    }

    /// A pyramid with `sides` sides: apex at the origin, axis +z, flat base at z = 1 whose
    /// polygon circumscribes the unit circle. Scaled per light by (R t, R), t its
    /// `LightRecord::volume_tan` (the outer angle widened by the shader test's rounding), it
    /// contains the spot's shape as the shaders test it: every point within distance R of the
    /// apex and that angle of the axis has z <= R and radial distance <= z t.
    pub fn cone(sides: u32) -> Self {
        let r = VOLUME_MARGIN / (std::f32::consts::PI / sides as f32).cos();
        let mut vertices = vec![Vec4::new(0.0, 0.0, 0.0, 1.0)];
        // The apex sits exactly on the light; pull it back a hair so faces that graze the
        // apex never exclude it.
        vertices[0].z = -0.002;
        for i in 0..sides {
            let a = i as f32 / sides as f32 * std::f32::consts::TAU;
            vertices.push(Vec4::new(r * a.cos(), r * a.sin(), VOLUME_MARGIN, 1.0));
        }
        let mut indices = Vec::new();
        for i in 0..sides {
            let a = 1 + i;
            let b = 1 + (i + 1) % sides;
            // Sides, counter-clockwise seen from outside.
            indices.extend([0, b, a]);
        }
        for i in 1..sides - 1 {
            // Base cap, facing +z.
            indices.extend([1, 1 + i, 2 + i]);
        }
        Self { vertices, indices }
    }

    /// Signed distance from the origin-centred mesh's nearest face plane along direction `d`:
    /// the distance to the mesh surface along the ray from `origin` in direction `d`
    /// (for convex meshes containing `origin`).
    pub fn ray_exit(&self, origin: Vec3, d: Vec3) -> f32 {
        let mut t_exit = f32::INFINITY;
        for tri in self.indices.chunks(3) {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| self.vertices[i as usize].truncate());
            let n = (b - a).cross(c - a).normalize();
            // Orient outward (the origin of the unit mesh is inside).
            let n = if n.dot(a) < 0.0 { -n } else { n };
            let denom = n.dot(d);
            if denom > 1e-9 {
                let t = n.dot(a - origin) / denom;
                t_exit = t_exit.min(t);
            }
        }
        t_exit
    }
}

/// Which bounding mesh a light uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeKind {
    Sphere,
    Cone,
}

impl VolumeKind {
    /// Spots narrower than [`CONE_MAX_ANGLE_DEG`] get a cone, everything else a sphere.
    pub fn of(light: &LightRecord) -> Self {
        if light.kind == LIGHT_KIND_SPOT && light.cos_outer > CONE_MAX_ANGLE_DEG.to_radians().cos() {
            VolumeKind::Cone
        } else {
            VolumeKind::Sphere
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            VolumeKind::Sphere => "sphere",
            VolumeKind::Cone => "cone",
        }
    }
}

/// The sphere and the cone at one tessellation, in one vertex and one index buffer.
pub struct Volumes {
    pub sphere: VolumeMesh,
    pub cone: VolumeMesh,
    /// (sphere subdivisions, cone sides) the meshes were built with.
    pub tessellation: (u32, u32),
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
}

impl Volumes {
    pub fn new(device: &wgpu::Device, tessellation: (u32, u32)) -> Self {
        let sphere = VolumeMesh::sphere(tessellation.0);
        let cone = VolumeMesh::cone(tessellation.1);
        let all_vertices: Vec<Vec4> = sphere.vertices.iter().chain(cone.vertices.iter()).copied().collect();
        let all_indices: Vec<u32> = sphere.indices.iter().chain(cone.indices.iter()).copied().collect();
        let (vertices, indices) =
            crate::renderer::kit::mesh_buffers(device, "light volume", &all_vertices, &all_indices);
        Self { sphere, cone, tessellation, vertices, indices }
    }

    pub fn mesh(&self, kind: VolumeKind) -> &VolumeMesh {
        match kind {
            VolumeKind::Sphere => &self.sphere,
            VolumeKind::Cone => &self.cone,
        }
    }

    /// The index range and base vertex of `kind`'s mesh in the shared buffers.
    pub fn range(&self, kind: VolumeKind) -> (std::ops::Range<u32>, i32) {
        let ns = self.sphere.indices.len() as u32;
        match kind {
            VolumeKind::Sphere => (0..ns, 0),
            VolumeKind::Cone => (ns..ns + self.cone.indices.len() as u32, self.sphere.vertices.len() as i32),
        }
    }

    /// Binds the volume meshes as the vertex and index buffer of `pass`.
    pub fn bind(&self, pass: &mut wgpu::RenderPass<'_>) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn directions(n: usize) -> impl Iterator<Item = Vec3> {
        // Fibonacci sphere.
        (0..n).map(move |i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).sqrt();
            let a = i as f32 * 2.399_963;
            Vec3::new(r * a.cos(), y, r * a.sin())
        })
    }

    #[test]
    fn sphere_circumscribes_the_unit_sphere() {
        // Every tessellation `Settings::sphere_subdivisions` allows.
        for level in 0..=crate::renderer::settings::MAX_SPHERE_SUBDIVISIONS {
            let m = VolumeMesh::sphere(level);
            let min = directions(20_000).map(|d| m.ray_exit(Vec3::ZERO, d)).fold(f32::INFINITY, f32::min);
            assert!(min >= 1.0, "level {level}: the mesh reaches only {min} of the radius");
            // And it is not wastefully large.
            assert!(min < 1.01, "level {level}: nearest face at {min}");
        }
    }

    #[test]
    fn uncorrected_icosphere_would_cut_light_off() {
        // The failure the scaling prevents: vertices on the radius leave faces inside it.
        let m = VolumeMesh::sphere(1);
        let scale = m.vertices[0].truncate().length();
        let min = directions(20_000).map(|d| m.ray_exit(Vec3::ZERO, d) / scale).fold(f32::INFINITY, f32::min);
        assert!(min < 0.97, "an icosphere with vertices on the sphere reaches {min}");
    }

    #[test]
    fn faces_wind_counter_clockwise_seen_from_outside() {
        // Culling of front or back faces depends on it.
        let spheres = (0..=crate::renderer::settings::MAX_SPHERE_SUBDIVISIONS).map(VolumeMesh::sphere);
        let cones = [3, 6, 12, 24, 64].into_iter().map(VolumeMesh::cone);
        for m in spheres.chain(cones) {
            let centre = m.vertices.iter().map(|v| v.truncate()).sum::<Vec3>() / m.vertices.len() as f32;
            for tri in m.indices.chunks(3) {
                let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| m.vertices[i as usize].truncate());
                assert!((b - a).cross(c - a).dot(a - centre) > 0.0, "a face winds inward");
            }
        }
    }

    #[test]
    fn cone_contains_the_spot_shape() {
        // At every number of sides `Settings::cone_sides` allows, from the 3-sided extreme.
        for sides in [3, 4, 6, 12, 24, 64] {
            cone_contains_the_spot_shape_with(sides);
        }
    }

    #[test]
    fn a_cone_through_the_cap_circle_would_cut_the_spot_off() {
        // The failure the base polygon's scaling prevents: with its corners on the cap circle
        // (no 1/cos(pi/sides)), the middle of each side lies inside the cone.
        for sides in [6u32, 12, 24] {
            let m = VolumeMesh::cone(sides);
            let corner = m.vertices[1].truncate();
            let shrink = (std::f32::consts::PI / sides as f32).cos();
            let a = m.vertices[1].truncate() * Vec3::new(shrink, shrink, 1.0);
            let b = m.vertices[2].truncate() * Vec3::new(shrink, shrink, 1.0);
            let mid = (a + b) * 0.5;
            let radial = (mid.x * mid.x + mid.y * mid.y).sqrt() / mid.z;
            assert!(radial < 1.0, "{sides} sides: the side's middle is at {radial} of the cap");
            assert!(corner.z > 0.0);
        }
    }

    fn cone_contains_the_spot_shape_with(sides: u32) {
        let m = VolumeMesh::cone(sides);
        // Points of the true shape in unit space, for a given outer angle a, have
        // radial <= z tan(a) and |p| <= 1; the mesh is scaled by (tan a, tan a, 1).
        for a_deg in [1.0f32, 20.0, 45.0, 60.0] {
            let ta = a_deg.to_radians().tan();
            for d in directions(4000) {
                let ang = d.z.clamp(-1.0, 1.0).acos();
                if ang > a_deg.to_radians() {
                    continue;
                }
                // Points along d up to distance 1 (the radius), in mesh space.
                for k in 1..=10 {
                    let p = d * (k as f32 / 10.0);
                    let q = Vec3::new(p.x / ta, p.y / ta, p.z);
                    let inside = m.indices.chunks(3).all(|tri| {
                        let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| m.vertices[i as usize].truncate());
                        let n = (b - a).cross(c - a);
                        n.dot(q - a) <= 1e-5 * n.length()
                    });
                    assert!(inside, "{sides} sides, angle {a_deg}: point {p} of the spot lies outside its cone mesh");
                }
            }
        }
    }

    /// Whether `q` lies inside mesh `m` placed by `place` (every face's outward side tested).
    fn inside_placed(m: &VolumeMesh, placed: &[Vec3], q: Vec3) -> bool {
        m.indices.chunks(3).all(|tri| {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| placed[i as usize]);
            let n = (b - a).cross(c - a);
            n.dot(q - a) <= 1e-5 * n.length() * (1.0 + a.length())
        })
    }

    #[test]
    fn a_padded_volume_holds_every_point_within_its_pad_of_the_light() {
        // Points of the light's shape (distance <= radius, angle <= outer) moved by the pad in
        // every direction stay inside the placed mesh; without the pad some leave it.
        let (pos, dir, radius, pad) = (Vec3::new(0.3, -0.2, -4.0), Vec3::new(0.6, 0.0, -0.8), 2.0f32, 0.05f32);
        let sphere = VolumeMesh::sphere(1);
        let cone = VolumeMesh::cone(12);
        let (t, u) = basis(dir);
        for (m, outer) in [(&sphere, None), (&cone, Some(0.0f32)), (&cone, Some(0.3)), (&cone, Some(1.4))] {
            let tan = outer.map_or(0.0, |a| crate::renderer::records::volume_tan(f64::from(a.cos())));
            let placed = |pad| m.vertices.iter().map(|v| place(*v, pos, radius, dir, tan, pad)).collect::<Vec<_>>();
            let (grown, bare) = (placed(pad), placed(0.0));
            let mut left_bare = 0;
            for d in directions(300) {
                let off = match outer {
                    None => d,
                    // A direction of the cone at up to its outer angle.
                    Some(a) => {
                        let ang = (d.z * 0.5 + 0.5) * a;
                        let side = (t * d.x + u * d.y).normalize_or(t);
                        dir * ang.cos() + side * ang.sin()
                    }
                };
                for k in [0.0f32, 0.01, 0.5, 1.0] {
                    let p = pos + off * (radius * k);
                    for e in directions(40) {
                        let q = p + e * pad;
                        assert!(
                            inside_placed(m, &grown, q),
                            "outer {outer:?}: {q} within {pad} of the light lies outside"
                        );
                        left_bare += usize::from(!inside_placed(m, &bare, q));
                    }
                }
            }
            assert!(left_bare > 0, "outer {outer:?}: the unpadded volume held every point");
        }
    }

    #[test]
    fn the_widened_cone_holds_every_direction_the_f32_spot_test_admits() {
        // The shaders' test, dot(normalize(v), direction) >= cos_outer in f32, against
        // directions just outside the outer angle: those it admits lie within the widened cone.
        for outer in [0.0f32, 1e-4, 1e-3, 0.02, 0.5, 1.5] {
            let cos_outer = outer.cos();
            let half = crate::renderer::records::volume_tan(f64::from(cos_outer)).atan() as f64;
            assert!(half >= f64::from(outer));
            let dir = Vec3::new(0.48, -0.6, 0.64).normalize();
            let (t, _) = basis(dir);
            let mut admitted_past_outer = 0;
            for i in 0..2000 {
                let ang = f64::from(outer) + (i as f64) * 1e-6;
                let v = (dir.as_dvec3() * ang.cos() + t.as_dvec3() * ang.sin()) * (1.0 + i as f64 * 0.37);
                let c = v.as_vec3().normalize().dot(dir);
                if c >= cos_outer {
                    assert!(ang <= half, "outer {outer}: admitted at {ang}, the cone reaches {half}");
                    admitted_past_outer += usize::from(ang > f64::from(outer));
                }
            }
            if outer == 0.0 {
                // The case the widening exists for: the f32 test admits directions off the axis.
                assert!(admitted_past_outer > 0);
            }
        }
    }
}
