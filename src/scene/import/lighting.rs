//! A first picture for a file that brings no lights and no useful camera: the framing viewpoint
//! and the default lights.
//!
//! **Framing.** The camera looks at the bounds' centre from the front, above and to the right,
//! at the distance where every vertex falls inside [`FRAME_FILL`] of a 16:9 view (the default
//! render and window shape): the model fills that share of the view's height or width.
//!
//! **Lights.** `count` point lights on a dome around the model: directions from a Fibonacci
//! spiral over the sphere, from straight above down to [`DOME_LOWEST`] below the horizon (lit
//! from above and around, a little from below), placed on the ellipsoid around the bounding
//! box that [`DOME_SCALE`] gives (a flat scene's dome is kept at least a quarter as high as it
//! is wide, so its lights stand above it rather than beside it). Each light reaches
//! [`REACH`] times its distance to the centre: past the centre, so the part of the model
//! nearer to it than the centre is in reach (a far corner facing it may not be). The
//! intensities are then set so that the lights give the median sampled vertex (among those
//! any light reaches) a diffuse irradiance of [`TARGET_IRRADIANCE`]: the picture's brightness
//! does not depend on the model's size or the light count. With [`FILL_AMBIENT`] and the fill
//! sun (0.6 cos θ), a surface at the median gets about 0.4 + 0.6 cos θ + 0.1, around 0.8:
//! under ACES at exposure 1 an 18% grey then reads about 130 of 255.

use super::*;

/// Share of the view's narrower side the framing view gives the bounding box.
pub const FRAME_FILL: f64 = 0.9;
/// The aspect ratio the framing view is fitted to (1280x720).
pub const FRAME_ASPECT: f64 = 16.0 / 9.0;
/// The dome's ellipsoid is the bounding box's (half extents) times this: the ellipsoid through
/// the box's corners (√3) with 15% to spare, so every light stands outside the box.
pub const DOME_SCALE: f64 = 1.732_050_8 * 1.15;
/// The lowest dome direction's height (its y on the unit sphere).
pub const DOME_LOWEST: f64 = -0.35;
/// A default light's radius over its distance to the bounds' centre.
pub const REACH: f64 = 1.25;
/// The diffuse irradiance the default lights give the median sampled vertex.
pub const TARGET_IRRADIANCE: f64 = 0.4;
/// Ambient light of a file without lights (a built-in scene's is 0.03): with the ambient
/// specular term it is what a metal shows away from its highlights.
pub const FILL_AMBIENT: f32 = 0.1;
/// Vertices sampled to set the default lights' intensity.
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

/// The default lights' positions and radii for bounds `lo`..`hi`.
pub fn dome(lo: DVec3, hi: DVec3, count: usize) -> Vec<(DVec3, f64)> {
    let centre = (lo + hi) * 0.5;
    let mut half = ((hi - lo) * 0.5).max(DVec3::splat(1e-3));
    let widest = half.x.max(half.z).max(half.y);
    half = half.max(DVec3::splat(widest * 0.1));
    half.y = half.y.max(0.25 * half.x.max(half.z));
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|k| {
            let t = (k as f64 + 0.5) / count as f64;
            let y = 1.0 - t * (1.0 - DOME_LOWEST);
            let ring = (1.0 - y * y).max(0.0).sqrt();
            let a = golden * k as f64;
            let dir = DVec3::new(ring * a.cos(), y, ring * a.sin());
            let position = centre + dir * half * DOME_SCALE;
            (position, (position - centre).length() * REACH)
        })
        .collect()
}

/// Up to `most` world-space (position, normal) pairs spread evenly over the scene's vertices.
pub(super) fn sample_vertices(scene: &Scene, most: usize) -> Vec<(DVec3, DVec3)> {
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

impl Importer<'_> {
    /// Sun, ambient and `options.lights` point lights for a scene that has no lights.
    pub(super) fn add_default_lights(&mut self, lo: DVec3, hi: DVec3) {
        self.scene.sun = Some(Sun::fill_sun());
        self.scene.ambient = Vec3::splat(FILL_AMBIENT);
        let n = self.options.lights;
        if n == 0 {
            return;
        }
        let placed: Vec<(DVec3, f64, Vec3)> = dome(lo, hi, n)
            .into_iter()
            .enumerate()
            .map(|(k, (p, r))| {
                (p, r, crate::scene::builtin::hue((k as f32 * 0.618_034).fract()) * 0.5 + Vec3::splat(0.5))
            })
            .collect();
        let intensity = normalising_intensity(&sample_vertices(&self.scene, IRRADIANCE_SAMPLES), &placed);
        for (position, radius, color) in placed {
            self.scene.lights_mut().push(Light::Point(PointLight {
                position,
                color,
                intensity,
                radius: radius as f32,
                cast_shadows: true,
                cookie: None,
                mask: crate::scene::ALL_LAYERS,
            }));
            self.stats.lights_added += 1;
        }
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
    fn the_dome_surrounds_the_bounds_from_above_and_the_median_gets_the_target() {
        let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
        let lights = dome(lo, hi, 64);
        assert_eq!(lights.len(), 64);
        // Mostly from above, some from below the horizon (DOME_LOWEST: 0.35 of 1.35 of the
        // heights, a quarter).
        let above = lights.iter().filter(|(p, _)| p.y > 0.0).count();
        let below = 64 - above;
        assert!(below > 0 && above > 2 * below, "{above} above, {below} below the centre");
        for (p, r) in &lights {
            // Outside the box, reaching past its centre.
            assert!(p.abs().max_element() > 1.0 && *r > p.length());
        }
        // Every side of the cube but its bottom faces some light (the lowest lights stand above
        // the bottom face's plane: a model is lit from above and around).
        let samples: Vec<(DVec3, DVec3)> = [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z]
            .into_iter()
            .map(|n| (n, n))
            .collect();
        let placed: Vec<_> = lights.iter().map(|&(p, r)| (p, r, Vec3::ONE)).collect();
        let i = normalising_intensity(&samples, &placed) as f64;
        let mut e: Vec<f64> = samples.iter().map(|&(p, n)| i * irradiance(p, n, &placed)).collect();
        assert!(e[3] == 0.0 && e.iter().enumerate().all(|(k, &x)| k == 3 || x > 0.0), "{e:?}");
        // The median of the five reached sides is the target.
        e.sort_by(f64::total_cmp);
        assert!((e[3] - TARGET_IRRADIANCE).abs() < 1e-4, "median {}", e[3]);
    }
}
