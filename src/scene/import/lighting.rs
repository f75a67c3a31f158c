//! A first picture for a file that brings no lights and no useful camera: the framing viewpoint
//! and the default lights.
//!
//! **Framing.** The camera looks at the bounds' centre from the front, above and to the right,
//! at the distance where every vertex falls inside [`FRAME_FILL`] of a 16:9 view (the default
//! render and window shape): the model fills that share of the view's height or width.
//!
//! **Lights.** `count` point lights placed where the surfaces are, each sized to the patch of
//! surface it is there for rather than to the whole model (see [`surface_rig`]): the surface is
//! sampled by area ([`sample_surface`]), the samples are cut by recursive median bisection into
//! `count` cells of equal area, and each cell gets one light above its centroid, along its mean
//! normal, reaching just past the cell's farthest sample. Lights stand in front of every part
//! of the surface, and each pixel is shaded by the few lights of the cells around it, not by
//! every light: a light's cost follows its cell's area, so the frame's lighting cost is a few
//! times the model's pixels whatever the light count. The intensities are then set so that the
//! lights give the median area sample (among those any light reaches) a diffuse irradiance of
//! [`TARGET_IRRADIANCE`]: the picture's brightness does not depend on the model's size, its
//! tessellation or the light count ([`irradiance_samples`]). Against the dome of lights it
//! replaced (normalised over vertices), the mean picture brightness of five files and the
//! room's two lightless models lies from 11% below to 4% above (docs/gltf.md). With
//! [`FILL_AMBIENT`] and the fill sun (0.6 cos θ), a surface at the median
//! gets about 0.4 + 0.6 cos θ + 0.1, around 0.8: under ACES at exposure 1 an 18% grey then
//! reads about 130 of 255.

use super::*;

/// Share of the view's narrower side the framing view gives the bounding box.
pub const FRAME_FILL: f64 = 0.9;
/// The aspect ratio the framing view is fitted to (1280x720).
pub const FRAME_ASPECT: f64 = 16.0 / 9.0;
/// Surface samples per default light: enough that each cell's centroid, mean normal and
/// farthest sample are those of its patch of surface (at 16 the farthest of a disc's samples
/// lies within about 15% of its rim), at least [`IRRADIANCE_SAMPLES`] in all.
pub const SAMPLES_PER_LIGHT: usize = 16;
/// Most surface samples the rig takes (two million: 96 MB of positions and normals); past
/// this the cells of a very large light count hold fewer samples each, at least one.
pub const MAX_SURFACE_SAMPLES: usize = 1 << 21;
/// A light's radius over its distance to its cell's farthest sample: that sample sits at
/// 1/1.3 = 0.77 of the radius, where the falloff (1 − (d/r)²)² is 1/6, so a cell's rim gets a
/// sixth of what the light gives at its reach's centre, before the neighbouring cells' lights
/// add to it. Measured on third-party files against √2 (rim at 1/4): the same coverage within
/// 1%, 15% fewer shaded fragments.
pub const RIM_REACH: f64 = 1.3;
/// A light's height above its cell's centroid, along the mean normal, over the cell's radius
/// (estimated as √2 × the samples' RMS distance from the centroid, exact for a uniformly
/// sampled disc). For a disc of radius R with the light at height tR and the rim at 1/√2 of
/// the radius (the falloff 1/4 there), the rim receives t / (4 √(1 + t²)) of what the cell's
/// centre does at the same height and the light shades (t² + 2) R² of the plane's area, π
/// times that: t = 1 gives the rim 0.18 and each light about three cells' area (t = 0.5: 0.11
/// and 2.25 cells; t = 2: 0.22 and 6 cells); [`RIM_REACH`]'s 1/6 lowers both a little. Each
/// rim point also lies within reach of the neighbouring cells' lights, which evens the picture
/// out. Measured on third-party files, t = 0.5 lost up to half the model's pixels that the
/// point lights reach (light too grazing at the rims of curved cells).
pub const HEIGHT_OVER_RADIUS: f64 = 1.0;
/// The diffuse irradiance the default lights give the median area sample they reach.
pub const TARGET_IRRADIANCE: f64 = 0.4;
/// Ambient light of a file without lights (a built-in scene's is 0.03): with the ambient
/// specular term it is what a metal shows away from its highlights.
pub const FILL_AMBIENT: f32 = 0.1;
/// The most area samples the default lights' intensity is set over ([`irradiance_samples`]),
/// and the fewest surface samples the rig places them by.
pub const IRRADIANCE_SAMPLES: usize = 4096;
/// Vertices the framing view fits (all of them up to this count, else an even sample).
pub const FRAMING_SAMPLES: usize = 1 << 20;

/// The framing viewpoint for a scene with bounds `lo`..`hi` whose points (vertices) are
/// `points`; without points, the bounds' corners are framed.
pub fn framing(lo: DVec3, hi: DVec3, points: &[DVec3]) -> Camera {
    let centre = (lo + hi) * 0.5;
    let half = (hi - lo) * 0.5;
    let radius = half.length().max(1e-3);
    let fov: f64 = 50f64.to_radians();
    let back = DVec3::new(0.45, 0.35, 1.0).normalize();
    // The view's axes for a camera looking along -back.
    let look = Camera::looking_at(centre + back, centre);
    let (right, forward) = (look.right(), look.forward());
    let up = right.cross(forward);
    let tan_y = (fov * 0.5).tan() * FRAME_FILL;
    let tan_x = (fov * 0.5).tan() * FRAME_ASPECT * FRAME_FILL;
    let fit = |target: DVec3, points: &[DVec3]| -> f64 {
        // A point at offset p from the target sits at depth d - p.back and must satisfy
        // |p.right| <= tan_x (d - p.back) and |p.up| <= tan_y (d - p.back).
        points.iter().fold(0.0f64, |d, &q| {
            let p = q - target;
            let depth_offset = p.dot(back);
            d.max(depth_offset + p.dot(right).abs() / tan_x).max(depth_offset + p.dot(up).abs() / tan_y)
        })
    };
    let corners: Vec<DVec3> = (0..8)
        .map(|k| {
            centre
                + DVec3::new(
                    if k & 1 == 0 { -half.x } else { half.x },
                    if k & 2 == 0 { -half.y } else { half.y },
                    if k & 4 == 0 { -half.z } else { half.z },
                )
        })
        .collect();
    let points = if points.is_empty() { &corners[..] } else { points };
    // Aim at the middle of the model's projection rather than the bounds' centre, so that the
    // model reaches the fill share on both sides: a few rounds of fitting the distance, then
    // moving the target by the projection's off-centre share.
    let mut target = centre;
    let mut distance = fit(target, points);
    for _ in 0..4 {
        let (mut lo, mut hi) = (glam::DVec2::splat(f64::INFINITY), glam::DVec2::splat(f64::NEG_INFINITY));
        for &q in points {
            let p = q - target;
            let depth = (distance - p.dot(back)).max(1e-9);
            let s = glam::DVec2::new(p.dot(right) / tan_x, p.dot(up) / tan_y) / depth;
            (lo, hi) = (lo.min(s), hi.max(s));
        }
        let mid = (lo + hi) * 0.5;
        target += (right * mid.x * tan_x + up * mid.y * tan_y) * distance;
        distance = fit(target, points);
    }
    let distance = distance.max(radius * 1e-2);
    let mut camera = Camera::looking_at(target + back * distance, target);
    camera.fov_y = fov;
    let from_centre = (camera.position - centre).length();
    camera.near = (from_centre - radius).max(radius * 1e-3) * 0.5;
    camera.far = (from_centre + radius) * 3.0;
    camera
}

/// `count` points spread over the scene's triangles by area, each with its surface normal
/// (interpolated from the vertices', else the face's), in world space: stratified over the
/// cumulative area, with barycentric coordinates from the R2 sequence (Roberts' generalised
/// golden ratio), so the samples are the same on every run. A scene without triangles (points
/// and lines only) gives its vertices instead ([`sample_vertices`]).
pub fn sample_surface(scene: &Scene, count: usize) -> Vec<(DVec3, DVec3)> {
    // (object, first index of the triangle, cumulative area up to and including it)
    let mut triangles: Vec<(usize, usize, f64)> = Vec::new();
    let mut total = 0.0;
    let normal_matrices: Vec<glam::DMat3> =
        scene.objects.iter().map(|o| glam::DMat3::from_mat4(o.transform).inverse().transpose()).collect();
    let corner = |o: &Object, mesh: &Mesh, i: u32| -> Option<DVec3> {
        let v = mesh.vertices.get(i as usize)?;
        Some(o.transform.transform_point3(Vec3::from(v.position).as_dvec3()))
    };
    for (k, o) in scene.objects.iter().enumerate() {
        let Some(mesh) = scene.meshes.get(o.mesh) else { continue };
        if mesh.topology != Topology::Triangles {
            continue;
        }
        for (t, ix) in mesh.indices.chunks_exact(3).enumerate() {
            let (Some(a), Some(b), Some(c)) = (corner(o, mesh, ix[0]), corner(o, mesh, ix[1]), corner(o, mesh, ix[2]))
            else {
                continue;
            };
            let area = (b - a).cross(c - a).length() * 0.5;
            if area.is_finite() && area > 0.0 {
                total += area;
                triangles.push((k, t * 3, total));
            }
        }
    }
    if triangles.is_empty() || count == 0 {
        return sample_vertices(scene, count);
    }
    // The R2 sequence's steps: the reciprocals of the plastic number and its square.
    let (g1, g2) = (0.754_877_666_246_692_8, 0.569_840_290_998_053_3);
    let mut out = Vec::with_capacity(count);
    for s in 0..count {
        let target = (s as f64 + 0.5) / count as f64 * total;
        let pick = triangles.partition_point(|&(_, _, c)| c < target).min(triangles.len() - 1);
        let (k, first, _) = triangles[pick];
        let o = &scene.objects[k];
        let mesh = &scene.meshes[o.mesh];
        let ix = &mesh.indices[first..first + 3];
        let (mut u, mut v) = ((0.5 + g1 * s as f64).fract(), (0.5 + g2 * s as f64).fract());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        let w = [1.0 - u - v, u, v];
        let vert = |j: usize| &mesh.vertices[ix[j] as usize];
        let p: DVec3 =
            (0..3).map(|j| o.transform.transform_point3(Vec3::from(vert(j).position).as_dvec3()) * w[j]).sum();
        let shading: DVec3 = (0..3).map(|j| Vec3::from(vert(j).normal).as_dvec3() * w[j]).sum();
        let mut n = (normal_matrices[k] * shading).normalize_or_zero();
        if n == DVec3::ZERO || !n.is_finite() {
            let c = |j: usize| o.transform.transform_point3(Vec3::from(vert(j).position).as_dvec3());
            n = (c(1) - c(0)).cross(c(2) - c(0)).normalize_or_zero();
        }
        if p.is_finite() {
            out.push((p, if n.is_finite() { n } else { DVec3::ZERO }));
        }
    }
    out
}

/// The default lights' positions and radii for surface samples `samples` (position, normal):
/// `count` cells of equal area (as many samples each, give or take one), cut by recursive
/// median bisection across each cell's longest side (a k-d split), and one light per cell, at
/// [`HEIGHT_OVER_RADIUS`] × the cell's radius along its mean normal from its centroid,
/// reaching [`RIM_REACH`] × its distance to the cell's farthest sample. No light is smaller
/// than a thousandth of `extent` (the model's size), so a cell of coincident samples still gets
/// a light that reaches them. Deterministic: the same samples give the same lights.
pub fn surface_rig(samples: &[(DVec3, DVec3)], count: usize, extent: f64) -> Vec<(DVec3, f64)> {
    if samples.is_empty() || count == 0 {
        return Vec::new();
    }
    let mut cells = samples.to_vec();
    let mut out = Vec::with_capacity(count);
    // A cell shares its samples among its lights until one light is left; a cell with fewer
    // samples than lights (more lights than samples) repeats its samples' light.
    fn split(cell: &mut [(DVec3, DVec3)], lights: usize, extent: f64, out: &mut Vec<(DVec3, f64)>) {
        if lights == 0 {
            return;
        }
        if lights == 1 || cell.len() <= 1 {
            let light = place(cell, extent);
            out.extend(std::iter::repeat_n(light, lights));
            return;
        }
        let (lo, hi) = cell
            .iter()
            .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(l, h), s| (l.min(s.0), h.max(s.0)));
        let side = hi - lo;
        let axis = if side.x >= side.y && side.x >= side.z {
            0
        } else if side.y >= side.z {
            1
        } else {
            2
        };
        let left = lights / 2;
        // The left cell's share of the samples: the left lights' share, so that every light
        // keeps the same share of the area; at least one sample each while there are enough.
        let cut = (cell.len() * left / lights).clamp(1, cell.len() - 1);
        cell.select_nth_unstable_by(cut, |a, b| a.0[axis].total_cmp(&b.0[axis]));
        let (a, b) = cell.split_at_mut(cut);
        split(a, left, extent, out);
        split(b, lights - left, extent, out);
    }
    fn place(cell: &[(DVec3, DVec3)], extent: f64) -> (DVec3, f64) {
        let n = cell.len().max(1) as f64;
        let centroid = cell.iter().map(|&(p, _)| p).sum::<DVec3>() / n;
        let normal = (cell.iter().map(|&(_, m)| m).sum::<DVec3>() / n).normalize_or_zero();
        let rms = (cell.iter().map(|&(p, _)| p.distance_squared(centroid)).sum::<f64>() / n).sqrt();
        let position = centroid + normal * (HEIGHT_OVER_RADIUS * std::f64::consts::SQRT_2 * rms);
        let farthest = cell.iter().map(|&(p, _)| p.distance(position)).fold(0.0, f64::max);
        (position, (farthest * RIM_REACH).max(extent * 1e-3))
    }
    split(&mut cells, count, extent, &mut out);
    out
}

/// Up to `most` world-space (position, normal) pairs spread evenly over the scene's vertices.
pub fn sample_vertices(scene: &Scene, most: usize) -> Vec<(DVec3, DVec3)> {
    let total: usize = scene.objects.iter().filter_map(|o| scene.meshes.get(o.mesh)).map(|m| m.vertices.len()).sum();
    let stride = total.div_ceil(most.max(1)).max(1);
    let mut out = Vec::with_capacity(total.min(most));
    let mut k = 0usize;
    for o in &scene.objects {
        let Some(mesh) = scene.meshes.get(o.mesh) else { continue };
        let normal_matrix = glam::DMat3::from_mat4(o.transform).inverse().transpose();
        for v in &mesh.vertices {
            k += 1;
            if !k.is_multiple_of(stride) {
                continue;
            }
            let p = o.transform.transform_point3(Vec3::from(v.position).as_dvec3());
            let n = (normal_matrix * Vec3::from(v.normal).as_dvec3()).normalize_or_zero();
            // Kept without a normal too (points and lines): framed, though no light reaches them.
            if p.is_finite() {
                out.push((p, if n.is_finite() { n } else { DVec3::ZERO }));
            }
        }
    }
    out
}

/// Diffuse irradiance at a point `p` with normal `n` from lights (position, radius, colour) of
/// unit intensity, with the renderer's falloff (1 - (d/r)^2)^2 and cos θ; colour counts by its
/// luminance.
pub fn irradiance(p: DVec3, n: DVec3, lights: &[(DVec3, f64, Vec3)]) -> f64 {
    lights
        .iter()
        .map(|&(lp, r, c)| {
            let to = lp - p;
            let d = to.length();
            if d >= r || d <= 0.0 || d.is_nan() {
                return 0.0;
            }
            let x = d / r;
            let w = (1.0 - x * x).powi(2);
            let lum = c.dot(crate::scene::luminance_weights()) as f64;
            lum * w * n.dot(to / d).max(0.0)
        })
        .sum()
}

/// The intensity that gives the median reached sample [`TARGET_IRRADIANCE`] from `lights`
/// ([`irradiance`] at unit intensity). 1 when no sample is reached.
pub fn normalising_intensity(samples: &[(DVec3, DVec3)], lights: &[(DVec3, f64, Vec3)]) -> f32 {
    let mut reached: Vec<f64> = samples.iter().map(|&(p, n)| irradiance(p, n, lights)).filter(|&e| e > 0.0).collect();
    if reached.is_empty() {
        return 1.0;
    }
    reached.sort_by(f64::total_cmp);
    let median = reached[reached.len() / 2];
    (TARGET_IRRADIANCE / median).clamp(1e-3, 1e4) as f32
}

/// Light `k`'s colour: a tint of [`RIG_TINT`] around the hue circle (golden-ratio steps). Each
/// light lights its own patch of the surface, so a strong tint shows as coloured patches
/// across the model; this much tells the lights apart in the viewer's lists and wireframes and
/// leaves the model's own colours in the first picture.
pub fn rig_colour(k: usize) -> Vec3 {
    crate::scene::builtin::hue((k as f32 * 0.618_034).fract()) * RIG_TINT + Vec3::splat(1.0 - RIG_TINT)
}

/// The share of a default light's colour that is its hue (the rest is white).
pub const RIG_TINT: f32 = 0.15;

/// The area-weighted surface samples ([`sample_surface`]) that `count` rig lights are placed
/// from: [`SAMPLES_PER_LIGHT`] a light, at least [`IRRADIANCE_SAMPLES`].
pub fn rig_samples(scene: &Scene, count: usize) -> Vec<(DVec3, DVec3)> {
    sample_surface(
        scene,
        count.saturating_mul(SAMPLES_PER_LIGHT).clamp(IRRADIANCE_SAMPLES, MAX_SURFACE_SAMPLES.max(count)),
    )
}

/// What the rig's intensity is normalised over: at most [`IRRADIANCE_SAMPLES`] of the
/// placement's area-weighted samples, evenly strided. The surface by area, not its vertices,
/// whose density follows the tessellation: a box's vertices all sit at its corners, where the
/// lights over its faces reach least, and normalising over them left a blue box 21% darker than
/// the dome it replaced.
pub fn irradiance_samples(samples: &[(DVec3, DVec3)]) -> Vec<(DVec3, DVec3)> {
    let stride = samples.len().div_ceil(IRRADIANCE_SAMPLES).max(1);
    samples.iter().step_by(stride).copied().collect()
}

/// Adds `count` default point lights to `scene` ([`surface_rig`]) at the intensity
/// [`normalising_intensity`] gives them over [`irradiance_samples`]. Returns how many were added.
pub fn add_surface_lights(scene: &mut Scene, count: usize) -> usize {
    if count == 0 {
        return 0;
    }
    let extent = scene.bounds().map_or(1.0, |(lo, hi)| (hi - lo).length()).max(1e-6);
    let samples = rig_samples(scene, count);
    let placed: Vec<(DVec3, f64, Vec3)> =
        surface_rig(&samples, count, extent).into_iter().enumerate().map(|(k, (p, r))| (p, r, rig_colour(k))).collect();
    let intensity = normalising_intensity(&irradiance_samples(&samples), &placed);
    let added = placed.len();
    scene.lights_mut().extend(placed.into_iter().map(|l| default_light(l, intensity)));
    added
}

/// A default light: point light `(position, radius, colour)` at `intensity`, casting shadows,
/// on every layer.
pub fn default_light((position, radius, color): (DVec3, f64, Vec3), intensity: f32) -> Light {
    Light::Point(PointLight {
        position,
        color,
        intensity,
        radius: radius as f32,
        cast_shadows: true,
        cookie: None,
        mask: crate::scene::ALL_LAYERS,
    })
}

impl Importer<'_> {
    /// Sun, ambient and `options.lights` point lights for a scene that has no lights.
    pub(super) fn add_default_lights(&mut self) {
        self.scene.sun = Some(Sun::fill_sun());
        self.scene.ambient = Vec3::splat(FILL_AMBIENT);
        self.stats.lights_added += add_surface_lights(&mut self.scene, self.options.lights);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_framing_view_puts_every_corner_inside_the_fill_share() {
        for (lo, hi) in [
            (DVec3::splat(-1.0), DVec3::splat(1.0)),
            (DVec3::new(-50.0, 0.0, -50.0), DVec3::new(50.0, 3.0, 50.0)),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(0.2, 5.0, 0.2)),
        ] {
            let c = framing(lo, hi, &[]);
            let (tan_x, tan_y) = ((c.fov_y * 0.5).tan() * FRAME_ASPECT, (c.fov_y * 0.5).tan());
            let mut widest: f64 = 0.0;
            for k in 0..8 {
                let p = DVec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                let v = c.to_view(p);
                let (x, y) = ((v.x / -v.z) / tan_x, (v.y / -v.z) / tan_y);
                assert!(x.abs() <= FRAME_FILL + 1e-9 && y.abs() <= FRAME_FILL + 1e-9, "corner at {x}, {y}");
                widest = widest.max(x.abs()).max(y.abs());
            }
            // The box touches the fill share on some side: it is framed, not lost in the view.
            assert!(widest > FRAME_FILL - 1e-6, "{lo} {hi}: widest corner at {widest}");
        }
    }

    #[test]
    fn the_rig_puts_a_light_over_each_equal_share_of_the_surface_and_the_median_gets_the_target() {
        // A cube of side 2 centred on the origin: 24 square units of surface, 64 lights.
        let mut scene = Scene::new("cube", Camera::looking_at(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO));
        scene.meshes.push(Mesh::cube());
        scene.materials.push(Material::diffuse(Vec3::ONE));
        scene.objects.push(Object { mesh: 0, material: 0, transform: DMat4::from_scale(DVec3::splat(2.0)), layer: 0 });
        let samples = sample_surface(&scene, 4096);
        assert_eq!(samples.len(), 4096);
        // By area: each face holds a sixth of the samples, each on the face its normal says.
        for axis in [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z] {
            let on: Vec<_> = samples.iter().filter(|(_, n)| n.dot(axis) > 0.99).collect();
            assert!((on.len() as f64 - 4096.0 / 6.0).abs() <= 2.0, "{axis}: {} samples", on.len());
            assert!(on.iter().all(|(p, _)| (p.dot(axis) - 1.0).abs() < 1e-9));
        }
        let lights = surface_rig(&samples, 64, 12f64.sqrt());
        assert_eq!(lights.len(), 64);
        assert_eq!(lights, surface_rig(&samples, 64, 12f64.sqrt()), "the same samples give the same lights");
        // A cell is 24/64 square units, a disc of radius 0.35 (a corner cell folds over the
        // cube's edges): each light stands outside the cube, in front of its cell, and reaches
        // a neighbourhood of it, not the model (the cube's half diagonal is 1.73).
        for (p, r) in &lights {
            assert!(p.abs().max_element() > 1.0 && *r < 1.73, "light at {p}, radius {r}");
        }
        let placed: Vec<_> = lights.iter().map(|&(p, r)| (p, r, Vec3::ONE)).collect();
        let reached = samples.iter().filter(|&&(p, n)| irradiance(p, n, &placed) > 0.0).count();
        assert!(reached * 1000 >= samples.len() * 999, "{reached} of {} samples lit", samples.len());
        // Each sample is within reach of a few lights, not of all of them.
        let mean_reaching = samples
            .iter()
            .map(|&(p, _)| placed.iter().filter(|&&(l, r, _)| l.distance(p) < r).count() as f64)
            .sum::<f64>()
            / samples.len() as f64;
        assert!(mean_reaching < 6.0, "a sample is within reach of {mean_reaching:.1} lights on average");
        let i = normalising_intensity(&samples, &placed) as f64;
        let mut e: Vec<f64> =
            samples.iter().map(|&(p, n)| i * irradiance(p, n, &placed)).filter(|&e| e > 0.0).collect();
        e.sort_by(f64::total_cmp);
        assert!((e[e.len() / 2] - TARGET_IRRADIANCE).abs() < 1e-5, "median {}", e[e.len() / 2]);
    }

    #[test]
    fn more_lights_than_samples_and_coincident_samples_still_give_every_light_a_reach() {
        let samples = vec![(DVec3::ONE, DVec3::Y); 3];
        let lights = surface_rig(&samples, 5, 2.0);
        assert_eq!(lights.len(), 5);
        for (p, r) in &lights {
            assert!(*r >= 2e-3 && p.distance(DVec3::ONE) < *r, "light at {p}, radius {r}");
        }
        assert!(surface_rig(&samples, 0, 2.0).is_empty() && surface_rig(&[], 4, 2.0).is_empty());
    }
}
