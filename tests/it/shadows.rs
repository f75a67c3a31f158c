//! Shadows. The GPU's shadow factor (the light a pixel gets with shadows over the
//! light it gets without, one light at a time) against a CPU visibility check (a segment from
//! the surface point to the light against every opaque triangle, `reference::Occluders`);
//! acne on a plane lit at a grazing angle; a thin wall; the point light's cube faces; every
//! culling mode; the hard cases with shadows on; the stats' fallbacks.

// `!(a > b)` also skips NaN, as the shaders' tests are written.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::common::*;
use glam::{DMat3, DVec3, Vec3};
use lampshade::compare::max_channel_difference;
use lampshade::headless::render_image;
use lampshade::reference::Occluders;
use lampshade::renderer::records::ShadowTile;
use lampshade::renderer::{CullingMode, Renderer, Settings, ShadowCube, ShadowFilter, ShadowMode, OUTPUT_FORMAT};
use lampshade::scene::{Light, Scene};

const W: u32 = 320;
const H: u32 = 180;

/// A frame's per-pixel diffuse light (max channel), view-space points, and the renderer's
/// shadow tiles and per-light tiles.
struct Lit {
    diffuse: Vec<f32>,
    points: Vec<Option<Vec3>>,
    tiles: Vec<ShadowTile>,
    lights: Vec<(u32, u32)>,
    sun: [u32; 4],
    splits: [f32; 4],
    stats: lampshade::renderer::FrameStats,
    image: image::RgbaImage,
}

fn lit(scene: &Scene, settings: &Settings) -> Lit {
    let gpu = gpu();
    let mut r = Renderer::new(gpu, OUTPUT_FORMAT, settings).expect("renderer");
    let (image, stats) = render_image(gpu, &mut r, scene, settings, W, H).expect("render");
    let (d, _) = r.last_frame().read_accumulation(gpu).expect("accumulation");
    let plan = r.last_frame().shadow_plan();
    Lit {
        diffuse: d.chunks_exact(4).map(|c| c[0].max(c[1]).max(c[2])).collect(),
        points: r.last_frame().view_positions(gpu).expect("positions"),
        tiles: plan.tiles.clone(),
        lights: plan.lights.clone(),
        sun: plan.params.sun,
        splits: plan.params.splits,
        stats,
        image,
    }
}

fn settings(shadows: ShadowMode) -> Settings {
    Settings { shadows, count_fragments: false, ..Settings::default() }
}

/// Both layouts of a point light's six faces (`--shadow-cube`): the tests about cubes run
/// with each.
const CUBES: [ShadowCube; 2] = [ShadowCube::Unrolled, ShadowCube::Array];

/// With seed 002's indirection too, which reads the unrolled tiles: the tests of what happens
/// at the faces' edges (`the_cube_indirection_shadows_the_pixels_the_face_pick_does` holds
/// it to the face pick everywhere else).
const ALL_CUBES: [ShadowCube; 3] = [ShadowCube::Unrolled, ShadowCube::Array, ShadowCube::Indirect];

fn cube_name(c: ShadowCube) -> &'static str {
    match c {
        ShadowCube::Unrolled => "unrolled",
        ShadowCube::Array => "array",
        ShadowCube::Indirect => "indirect",
    }
}

/// The CPU checks' settings: a 64 MiB atlas (4096 texels; 1024 a cascade) and 4 cascades, so
/// the edge band leaves enough of the shadows' insides to compare.
fn fine(shadows: ShadowMode) -> Settings {
    Settings { shadow_budget_mb: 64.0, shadow_cascades: 4, ..settings(shadows) }
}

/// The `shadows` scene with only the lights `keep` accepts (index, light), the sun if `sun`,
/// and no ambient light: each pixel's diffuse light is the kept lights' alone.
fn only(keep: impl Fn(usize, &Light) -> bool, sun: bool) -> Scene {
    let mut s = scene("shadows");
    s.set_lights(s.lights.iter().enumerate().filter(|(i, l)| keep(*i, l)).map(|(_, l)| *l).collect());
    if !sun {
        s.sun = None;
    }
    s.ambient = Vec3::ZERO;
    s
}

/// World position and normal (from the neighbouring pixels' points, `None` where the four
/// neighbours are not on one plane: geometric edges) of pixel `i`.
fn surface(scene: &Scene, points: &[Option<Vec3>], i: usize) -> Option<(DVec3, DVec3)> {
    let (x, y) = ((i as u32 % W) as i64, (i as u32 / W) as i64);
    if x < 1 || y < 1 || x + 1 >= W as i64 || y + 1 >= H as i64 {
        return None;
    }
    let at = |dx: i64, dy: i64| points[((y + dy) * W as i64 + x + dx) as usize].map(|p| p.as_dvec3());
    let (p, l, r, u, d) = (at(0, 0)?, at(-1, 0)?, at(1, 0)?, at(0, -1)?, at(0, 1)?);
    // The four one-sided normals must agree: a pixel beside a geometric edge has none.
    let mut n = (r - l).cross(d - u).normalize_or_zero();
    if n == DVec3::ZERO {
        return None;
    }
    if n.dot(-p) < 0.0 {
        n = -n;
    }
    for (a, b) in [(r, d), (d, l), (l, u), (u, r)] {
        let m = (a - p).cross(b - p).normalize_or_zero();
        if m.dot(n).abs() < 0.999 {
            return None;
        }
    }
    let to_world = scene.camera.rotation().transpose();
    Some((scene.camera.position + to_world * p, to_world * n))
}

/// The cube face (`shadows::FACES` order: +x, -x, +y, -y, +z, -z) of the major axis of the
/// light-to-point vector `d`, as `cube_face` in lookup.wgsl picks it.
fn major_face(d: DVec3) -> u32 {
    let a = d.abs();
    if a.x >= a.y && a.x >= a.z {
        (d.x < 0.0) as u32
    } else if a.y >= a.z {
        2 + (d.y < 0.0) as u32
    } else {
        4 + (d.z < 0.0) as u32
    }
}

/// A texel's world size at view-space point `p` in tile `t` (`ShadowTile::info.y` x w).
fn texel_at(t: &ShadowTile, p: DVec3) -> f64 {
    let m = glam::Mat4::from_cols_array_2d(&t.to_light).as_dmat4();
    let q = m.transform_point3(p);
    let w = if t.info[0] == lampshade::renderer::shadows::TILE_ORTHOGRAPHIC { 1.0 } else { -q.z };
    t.info[1] as f64 * w
}

/// How a pixel compares: `None` when excluded (no light without shadows, near a shadow edge,
/// grazing, on a geometric edge), else (CPU visible, GPU factor).
struct Check<'a> {
    scene: &'a Scene,
    occluders: Occluders,
    plain: &'a Lit,
    shadowed: &'a Lit,
    /// Edge band in texels (see [`band_texels`]).
    band_texels: f64,
    /// The shadowed frame with the pixels that disagree marked (yellow: visible on the CPU,
    /// red: blocked), written to `target/image-tests/` when the check fails.
    misses: std::cell::RefCell<Option<image::RgbaImage>>,
    /// Compare only these pixels (`None`: all).
    pixels: Option<Vec<bool>>,
    /// Compare with this frame's shadow (its factor over `plain`'s, > 0.5 lit) instead of the
    /// CPU's visibility (the pixels near the CPU's shadow edges are left out all the same).
    against: Option<&'a Lit>,
}

/// The edge band: pixels whose CPU visibility changes within this many shadow-map texels
/// (projected onto the receiver: divided by N.L) are left out. The GPU's edge can sit that far
/// from the true one: the lookup point moves (reach + normal offset) texels along the normal
/// (3 with the default `pcf3x3` and offset 1), the kernel reads depths up to its reach from
/// there (2), and the rasterised occluder's edge is quantised to a texel (1): 6 texels.
fn band_texels(s: &Settings) -> f64 {
    let reach = s.shadow_filter.reach() as f64;
    2.0 * reach + s.shadow_normal_offset as f64 + 1.0
}

impl Check<'_> {
    /// `light_at(world point)` is the light's world position (for the sun, a point far along
    /// its direction); `texel(view point)` the texel size there.
    fn run(&self, light_at: impl Fn(DVec3) -> DVec3, texel: impl Fn(DVec3) -> Option<f64>) -> (usize, usize, usize) {
        let (mut agree, mut total, mut shadowed) = (0, 0, 0);
        let rot = self.scene.camera.rotation();
        for i in 0..(W * H) as usize {
            let base = self.plain.diffuse[i];
            if !(base > 1e-3) || self.pixels.as_ref().is_some_and(|m| !m[i]) {
                continue;
            }
            let Some((p, n)) = surface(self.scene, &self.plain.points, i) else { continue };
            let to_light = (light_at(p) - p).normalize();
            let ndl = n.dot(to_light);
            if ndl < 0.2 {
                continue;
            }
            let view_p = rot * (p - self.scene.camera.position);
            let Some(texel) = texel(view_p) else { continue };
            let band = self.band_texels * texel / ndl;
            // The ray starts off the surface by more than the point's reconstruction error (the
            // f32 depth copy: about 1e-4 of the distance here), so the receiver's own face
            // never blocks it.
            let lift = 1e-3 * (1.0 + view_p.length());
            let visible = |q: DVec3| !self.occluders.blocked(q + n * lift, light_at(q));
            let v = visible(p);
            // Two tangents of the receiver, and 8 points on a circle of the band's radius.
            let t1 = n.any_orthonormal_vector();
            let t2 = n.cross(t1);
            // Near a shadow's edge: a point of the circle sees the light differently. Near a
            // contact (an occluder standing on the receiver within the band, where the biases
            // move the GPU's edge to the occluder's foot): something lies above a point of
            // the circle, or above the point itself, within the band.
            let near_edge = (0..9).any(|k| {
                let a = k as f64 * std::f64::consts::FRAC_PI_4;
                let q = if k == 8 { p } else { p + (t1 * a.cos() + t2 * a.sin()) * band };
                (k < 8 && visible(q) != v) || self.occluders.blocked(q + n * lift, q + n * band)
            });
            if near_edge {
                continue;
            }
            let factor = self.shadowed.diffuse[i] / base;
            let v = self.against.map_or(v, |a| a.diffuse[i] / base > 0.5);
            total += 1;
            shadowed += !v as usize;
            if v == (factor > 0.5) {
                agree += 1;
            } else if let Some(img) = self.misses.borrow_mut().as_mut() {
                img.put_pixel(i as u32 % W, i as u32 / W, image::Rgba([255, if v { 255 } else { 0 }, 0, 255]));
            }
        }
        (agree, total, shadowed)
    }
}

fn check_light(name: &str, scene: &Scene, mode: ShadowMode, sun: bool) {
    check_light_at(name, scene, &fine(mode), sun, None, (1000, 200));
}

/// `check_light` at the pixels `pixels` selects, asking for at least `least.0` compared pixels
/// of which `least.1` are in shadow.
fn check_light_at(
    name: &str,
    scene: &Scene,
    st: &Settings,
    sun: bool,
    pixels: Option<Vec<bool>>,
    least: (usize, usize),
) {
    let plain = lit(scene, &settings(ShadowMode::None));
    let shadowed = lit(scene, st);
    assert_finite_values(&shadowed.diffuse, name);
    let band_texels = band_texels(st);
    let misses = std::cell::RefCell::new(Some(shadowed.image.clone()));
    let check = Check {
        scene,
        occluders: Occluders::of(scene),
        plain: &plain,
        shadowed: &shadowed,
        band_texels,
        misses,
        pixels,
        against: None,
    };
    let rot = scene.camera.rotation();
    let (agree, total, blocked) = if sun {
        let s = scene.sun.expect("a sun");
        let to_sun = -s.direction.as_dvec3().normalize();
        let (first, count) = (shadowed.sun[0], shadowed.sun[1]);
        assert!(count >= 1, "{name}: the sun cast no cascade");
        let splits = shadowed.splits;
        check.run(
            |p| p + to_sun * 1e4,
            |vp| {
                let c = (0..count as usize).find(|&c| -vp.z <= splits[c] as f64)?;
                Some(texel_at(&shadowed.tiles[first as usize + c], vp))
            },
        )
    } else {
        let light = scene.lights[0];
        let (first, count) = shadowed.lights[0];
        assert!(count >= 1, "{name}: the light cast no shadow");
        let lp_view = rot * (light.position() - scene.camera.position);
        check.run(
            |_| light.position(),
            |vp| {
                let t = if count == 6 {
                    let d = vp - lp_view;
                    let a = d.abs();
                    let face = if a.x >= a.y && a.x >= a.z {
                        if d.x > 0.0 {
                            0
                        } else {
                            1
                        }
                    } else if a.y >= a.z {
                        if d.y > 0.0 {
                            2
                        } else {
                            3
                        }
                    } else if d.z > 0.0 {
                        4
                    } else {
                        5
                    };
                    first + face
                } else {
                    first
                };
                Some(texel_at(&shadowed.tiles[t as usize], vp))
            },
        )
    };
    let share = agree as f64 / total.max(1) as f64;
    eprintln!("{name}: {agree} of {total} pixels agree ({:.4}); {blocked} of them shadowed on the CPU", share);
    if share < 0.99 {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/image-tests");
        let _ = std::fs::create_dir_all(&dir);
        if let Some(img) = check.misses.borrow().as_ref() {
            let _ = img.save(dir.join(format!("shadows-{name}-misses.png")));
        }
    }
    assert!(total > least.0, "{name}: only {total} pixels compared");
    assert!(blocked > least.1, "{name}: only {blocked} compared pixels are in shadow: the scene shows no shadow");
    assert!(share >= 0.99, "{name}: the GPU's shadow agrees with the CPU's rays at {share:.4} of {total} pixels");
}

fn assert_finite_values(v: &[f32], what: &str) {
    let bad = v.iter().filter(|x| !x.is_finite()).count();
    assert_eq!(bad, 0, "{what}: {bad} non-finite values");
}

#[test]
fn cpu_rays_agree_with_the_spot_lights_shadow() {
    let s = only(|_, l| matches!(l, Light::Spot(_)), false);
    check_light("spot", &s, ShadowMode::Spots, false);
}

#[test]
fn cpu_rays_agree_with_the_point_lights_cube_shadow() {
    let s = only(|_, l| matches!(l, Light::Point(_)), false);
    for cube in CUBES {
        let st = Settings { shadow_cube: cube, ..fine(ShadowMode::All) };
        check_light_at(&format!("point-{}", cube_name(cube)), &s, &st, false, None, (1000, 200));
    }
}

#[test]
fn cpu_rays_agree_with_the_suns_cascaded_shadow() {
    let s = only(|_, _| false, true);
    check_light("sun", &s, ShadowMode::Sun, true);
}

/// A floor alone under a light at a grazing angle: nothing occludes it, so every lit pixel must
/// keep all its light (a factor below 0.999 is self-shadowing: acne), with every kernel.
#[test]
fn a_plane_lit_at_a_grazing_angle_shows_no_acne_with_the_default_bias() {
    for (name, sun) in [("spot", false), ("sun", true)] {
        let mut s = scene("shadows");
        s.objects.truncate(1); // the floor
        s.ambient = Vec3::ZERO;
        if sun {
            s.lights_mut().clear();
            // 80 degrees from the floor's normal.
            let a = 80f32.to_radians();
            s.sun.as_mut().expect("sun").direction = Vec3::new(a.sin(), -a.cos(), 0.0);
        } else {
            s.sun = None;
            s.lights_mut().retain(|l| matches!(l, Light::Spot(_)));
            if let Light::Spot(sp) = &mut s.lights_mut()[0] {
                // Low over the floor, pointing across it: N.L from 0.05 to 0.3 where it lands.
                sp.position = DVec3::new(-6.0, 0.6, 0.0);
                sp.direction = Vec3::new(1.0, -0.12, 0.0).normalize();
                sp.outer_angle = 30f32.to_radians();
                sp.inner_angle = 20f32.to_radians();
            }
        }
        let mode = if sun { ShadowMode::Sun } else { ShadowMode::Spots };
        let plain = lit(&s, &settings(ShadowMode::None));
        let count_acne = |st: &Settings| {
            let f = lit(&s, st);
            let (mut acne, mut n) = (0, 0);
            for (a, b) in plain.diffuse.iter().zip(&f.diffuse) {
                if *a > 1e-3 {
                    n += 1;
                    acne += (*b < 0.999 * *a) as usize;
                }
            }
            (acne, n)
        };
        for filter in [ShadowFilter::Pcf2x2, ShadowFilter::Pcf3x3, ShadowFilter::Poisson16] {
            let (acne, n) = count_acne(&Settings { shadow_filter: filter, ..settings(mode) });
            eprintln!("{name}/{}: {acne} of {n} lit pixels lose light with the default bias", filter.name());
            assert!(n > 4000, "{name}: only {n} lit pixels");
            assert_eq!(
                acne,
                0,
                "{name}/{}: {acne} of {n} pixels of an unoccluded floor are self-shadowed",
                filter.name()
            );
        }
    }
}

/// Per pixel, whether the lights' shadows take more than half its diffuse light under `base`
/// with shadows `mode` (against the same settings without shadows).
fn shadowed_pixels(scene: &Scene, base: &Settings, mode: ShadowMode) -> Vec<bool> {
    let plain = lit(scene, &Settings { shadows: ShadowMode::None, ..base.clone() });
    let f = lit(scene, &Settings { shadows: mode, ..base.clone() });
    plain.diffuse.iter().zip(&f.diffuse).map(|(a, b)| *a > 1e-3 && *b < 0.5 * *a).collect()
}

/// The pixels where `other` differs from `reference` away from a shadow's edge (a pixel whose
/// 8 neighbours all agree with it in `reference`).
fn differ_off_edges(reference: &[bool], other: &[bool]) -> Vec<usize> {
    let w = W as i64;
    let edge = |k: usize| {
        let (x, y) = (k as i64 % w, k as i64 / w);
        (-1..=1).any(|dy| {
            (-1..=1).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                nx >= 0 && ny >= 0 && nx < w && ny < H as i64 && reference[(ny * w + nx) as usize] != reference[k]
            })
        })
    };
    (0..reference.len()).filter(|&k| other[k] != reference[k] && !edge(k)).collect()
}

/// Seed 000's and seed 002's fp16 stored positions widen the shadow bias by their rounding
/// (`stored_position_error`: sqrt(3) 2^-11 |p| (1 + tan)); at the scene's own distances that
/// must not move shadows: every light's shadowed pixels (factor below 1/2) are the depth
/// layout's, but for pixels at a shadow's edge (a neighbour differs in `compact`). (Seed 000
/// differs at 31 of 1,402 pixels away from an edge with or without the widening: its
/// world-space fp16 normal and view vector move the normal offset; not tested here.)
#[test]
fn fp16_stored_positions_shadow_the_pixels_depth_layouts_shadow() {
    use lampshade::renderer::LayoutChoice;
    let s = scene("shadows");
    let at = |layout| shadowed_pixels(&s, &Settings { layout, ..settings(ShadowMode::None) }, ShadowMode::All);
    let depth = at(LayoutChoice::Compact);
    let n = depth.iter().filter(|b| **b).count();
    assert!(n > 1000, "only {n} shadowed pixels");
    let off = differ_off_edges(&depth, &at(LayoutChoice::Seed002));
    eprintln!("seed002: {} of {n} shadowed pixels differ away from an edge", off.len());
    assert!(off.is_empty(), "seed002: {} pixels away from a shadow edge differ, first {:?}", off.len(), off.first());
}

/// Seed 002's shadow formats (`--shadow-format`): D24 and D16 maps shadow the pixels the
/// Depth32Float maps shadow (but at shadow edges), for the atlas and the cube array, and the
/// stats report the format and its bytes: 2 a texel for D16, whose atlas doubles its side where
/// the budget allows the next power of two.
#[test]
fn every_shadow_format_shadows_the_pixels_depth32_shadows() {
    use lampshade::renderer::ShadowFormat;
    let s = scene("shadows");
    for cube in CUBES {
        let at = |format| {
            let base = Settings { shadow_format: format, shadow_cube: cube, ..settings(ShadowMode::None) };
            shadowed_pixels(&s, &base, ShadowMode::All)
        };
        let d32 = at(ShadowFormat::Depth32);
        let n = d32.iter().filter(|b| **b).count();
        assert!(n > 1000, "only {n} shadowed pixels");
        for format in [ShadowFormat::Depth24, ShadowFormat::Depth16] {
            let off = differ_off_edges(&d32, &at(format));
            eprintln!("{} {format:?}: {} of {n} shadowed pixels differ away from an edge", cube_name(cube), off.len());
            assert!(
                off.is_empty(),
                "{} {format:?}: {} pixels away from a shadow edge differ",
                cube_name(cube),
                off.len()
            );
        }
    }
    for (format, bytes, side) in [(ShadowFormat::Depth32, 4, 2048), (ShadowFormat::Depth16, 2, 4096)] {
        let st = Settings { shadow_format: format, shadow_budget_mb: 32.0, ..settings(ShadowMode::All) };
        let sh = lit(&s, &st).stats.shadow.expect("shadow stats");
        assert_eq!((sh.format, sh.atlas_side, sh.atlas_bytes), (format, side, side as u64 * side as u64 * bytes));
    }
}

/// A 2 cm wall between a point light and the floor behind it, wider than the light's reach:
/// behind it, past the edge band at its foot, no light at all.
#[test]
fn a_thin_wall_leaks_no_light() {
    let mut s = only(|_, l| matches!(l, Light::Point(_)), false);
    s.objects.truncate(1);
    let wall = s.objects[0].material;
    // The wall: x = -4.52 .. -4.50, 20 units long, 3 high; the light 1 unit in front of it.
    let t = glam::DMat4::from_translation(DVec3::new(-4.51, 1.5, 0.0))
        * glam::DMat4::from_scale(DVec3::new(0.02, 3.0, 20.0));
    s.objects.push(lampshade::scene::Object { mesh: 0, material: wall, transform: t, layer: 0 });
    if let Light::Point(p) = &mut s.lights_mut()[0] {
        p.position = DVec3::new(-3.5, 1.2, 0.0);
        p.radius = 5.0;
    }
    s.camera = lampshade::scene::Camera::looking_at(DVec3::new(-9.0, 6.0, 6.0), DVec3::new(-5.0, 0.0, 0.0));
    let plain = lit(&s, &settings(ShadowMode::None));
    for cube in CUBES {
        let f = lit(&s, &Settings { shadow_cube: cube, ..settings(ShadowMode::All) });
        let (mut behind, mut leaks, mut worst) = (0, 0, 0.0f32);
        let to_world = s.camera.rotation().transpose();
        for i in 0..(W * H) as usize {
            let Some(p) = f.points[i] else { continue };
            let w = s.camera.position + to_world * p.as_dvec3();
            // The floor behind the wall, past 0.1 (the band: 4 texels of the face, ~0.02 each
            // at that distance, and the wall's own thickness) from its back face.
            if w.y < 0.01 && w.x < -4.62 && plain.diffuse[i] > 1e-3 {
                behind += 1;
                if f.diffuse[i] > 0.0 {
                    leaks += 1;
                    worst = worst.max(f.diffuse[i] / plain.diffuse[i]);
                }
            }
        }
        let name = cube_name(cube);
        eprintln!("thin wall/{name}: {behind} pixels behind it lit without shadows; {leaks} leak (worst {worst})");
        assert!(behind > 500, "only {behind} pixels behind the wall");
        assert_eq!(leaks, 0, "{name}: {leaks} of {behind} pixels behind the wall get light (worst {worst})");
    }
}

/// A point light over a bare floor: every face boundary of its cube crosses the floor. Nothing
/// occludes, so a pixel that loses light is a seam (or acne); and the face boundaries are on
/// screen (pixels whose neighbours use another face). Then with the boxes: at the pixels within
/// 3 of a face boundary, the GPU's shadow agrees with the CPU's rays (a lit seam inside a
/// shadow: the lookup point offset past its face's border).
#[test]
fn a_point_lights_cube_shows_no_seams_at_face_edges() {
    let s = only(|_, l| matches!(l, Light::Point(_)), false);
    let probe = lit(&s, &fine(ShadowMode::All));
    let rot = s.camera.rotation();
    let lp = rot * (s.lights[0].position() - s.camera.position);
    let face = |p: Vec3| {
        let d = p.as_dvec3() - lp;
        let a = d.abs();
        if a.x >= a.y && a.x >= a.z {
            (d.x > 0.0) as u8
        } else if a.y >= a.z {
            2 + (d.y > 0.0) as u8
        } else {
            4 + (d.z > 0.0) as u8
        }
    };
    let mut near = vec![false; (W * H) as usize];
    for y in 0..H as i64 {
        for x in 0..W as i64 {
            let Some(f0) = probe.points[(y * W as i64 + x) as usize].map(face) else { continue };
            for (dx, dy) in [(1, 0), (0, 1)] {
                let (x1, y1) = (x + dx, y + dy);
                if x1 >= W as i64 || y1 >= H as i64 {
                    continue;
                }
                if probe.points[(y1 * W as i64 + x1) as usize].map(face).is_some_and(|f1| f1 != f0) {
                    for yy in (y - 3).max(0)..=(y + 3).min(H as i64 - 1) {
                        for xx in (x - 3).max(0)..=(x + 3).min(W as i64 - 1) {
                            near[(yy * W as i64 + xx) as usize] = true;
                        }
                    }
                }
            }
        }
    }
    for cube in ALL_CUBES {
        let st = Settings { shadow_cube: cube, ..fine(ShadowMode::All) };
        let name = format!("point at face edges-{}", cube_name(cube));
        check_light_at(&name, &s, &st, false, Some(near.clone()), (300, 30));
    }
    for (filter, cube) in [ShadowFilter::Pcf2x2, ShadowFilter::Pcf3x3, ShadowFilter::Poisson16]
        .into_iter()
        .flat_map(|f| ALL_CUBES.map(|c| (f, c)))
    {
        let mut s = only(|_, l| matches!(l, Light::Point(_)), false);
        s.objects.truncate(1);
        if let Light::Point(p) = &mut s.lights_mut()[0] {
            p.position = DVec3::new(0.0, 1.5, 0.0);
            p.radius = 9.0;
        }
        s.camera = lampshade::scene::Camera::looking_at(DVec3::new(0.0, 9.0, 7.0), DVec3::new(0.0, 0.0, 0.0));
        let st = Settings { shadow_filter: filter, shadow_cube: cube, ..settings(ShadowMode::All) };
        let f = lit(&s, &st);
        assert_eq!(f.tiles[f.lights[0].0 as usize].info[0] == 2.0, cube == ShadowCube::Array, "the cube's layout");
        let plain = lit(&s, &settings(ShadowMode::None));
        let rot = s.camera.rotation();
        let lp = rot * (s.lights[0].position() - s.camera.position);
        let face = |p: Vec3| {
            let d = p.as_dvec3() - lp;
            let a = d.abs();
            if a.x >= a.y && a.x >= a.z {
                (d.x > 0.0) as u8
            } else if a.y >= a.z {
                2 + (d.y > 0.0) as u8
            } else {
                4 + (d.z > 0.0) as u8
            }
        };
        let (mut lit_px, mut seams, mut boundary) = (0, 0, 0);
        for i in 0..(W * H) as usize {
            if !(plain.diffuse[i] > 1e-3) {
                continue;
            }
            lit_px += 1;
            if f.diffuse[i] < 0.999 * plain.diffuse[i] {
                seams += 1;
            }
            let (x, y) = (i as u32 % W, i as u32 / W);
            if let (Some(p), Some(q)) = (f.points[i], f.points.get(i + 1).copied().flatten()) {
                if x + 1 < W && face(p) != face(q) {
                    boundary += 1;
                }
            }
            let _ = y;
        }
        let name = format!("{}/{}", filter.name(), cube_name(cube));
        eprintln!("{name}: {lit_px} lit pixels, {boundary} on a face boundary, {seams} lose light");
        assert!(boundary > 100, "the cube's face boundaries are not on screen ({boundary} pixels)");
        assert_eq!(seams, 0, "{name}: {seams} of {lit_px} pixels of a bare floor lose light");
    }
}

#[test]
fn every_culling_mode_gives_the_same_shadowed_picture() {
    let s = scene("shadows");
    let unshadowed = render(&s, &Settings { culling: CullingMode::Fullscreen, ..settings(ShadowMode::None) }, W, H);
    let mut failures = Vec::new();
    for cube in CUBES {
        let st = |culling| Settings { culling, shadow_cube: cube, ..settings(ShadowMode::All) };
        let reference = render(&s, &st(CullingMode::Fullscreen), W, H);
        assert_finite(&reference, "shadows");
        let shadow_steps = max_channel_difference(&reference.image, &unshadowed.image);
        assert!(shadow_steps > 20, "{}: the shadows change the picture by only {shadow_steps} steps", cube_name(cube));
        for mode in CullingMode::ALL.into_iter().skip(1) {
            let f = render(&s, &st(mode), W, H);
            assert_finite(&f, mode.name().as_str());
            let step = max_channel_difference(&reference.image, &f.image);
            if step > 1 {
                failures.push(format!("{} {}: {step} steps from fullscreen", cube_name(cube), mode.name()));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// With few casting lights (`demo`'s spots, 4 of 1,028 lights) only they run the shadow
/// lookups (`ShadowCode::casters_apart`; on lavapipe a lookup in the shader costs every light
/// that runs it): the light pass draws the others with a pipeline without lookups, the tiled
/// and clustered passes shade a list's casters in a loop of their own. Two mechanisms, one
/// picture: every mode gives `fullscreen`'s within a step, and `fullscreen`'s shows the spots'
/// shadows (it differs from the sun-only picture by more than 20 steps).
#[test]
fn casting_lights_shaded_apart_give_the_fullscreen_picture() {
    use lampshade::renderer::shadows::ShadowCode;
    let st = |culling, shadows| Settings { culling, ..settings(shadows) };
    // `demo` as built (its spots are its last lights), and with two spots moved to the front:
    // then a list can hold casters at both ends and other lights between them, which the
    // casters' loop walks past and the light pass draws in three runs.
    let mut spread = scene("demo");
    spread.lights_mut().rotate_right(2);
    assert!(matches!(spread.lights[0], Light::Spot(_)) && matches!(spread.lights[1027], Light::Spot(_)));
    for (name, s) in [("demo", scene("demo")), ("demo, spots at both ends", spread)] {
        assert!(
            ShadowCode::of(Some(&s), &st(CullingMode::Clustered, ShadowMode::Spots).shadow_options()).casters_apart
        );
        assert!(!ShadowCode::of(Some(&s), &st(CullingMode::Clustered, ShadowMode::All).shadow_options()).casters_apart);
        let reference = render(&s, &st(CullingMode::Fullscreen, ShadowMode::Spots), W, H);
        let sun_only = render(&s, &st(CullingMode::Fullscreen, ShadowMode::Sun), W, H);
        let spot_shadows = max_channel_difference(&reference.image, &sun_only.image);
        assert!(spot_shadows > 20, "{name}: the spots' shadows change the picture by only {spot_shadows} steps");
        for mode in CullingMode::ALL.into_iter().skip(1) {
            let f = render(&s, &st(mode, ShadowMode::Spots), W, H);
            assert_finite(&f, mode.name().as_str());
            let step = max_channel_difference(&reference.image, &f.image);
            assert!(step <= 1, "{name}, {}: {step} steps from fullscreen", mode.name());
        }
    }
}

/// `--shadow-cube array` and `unrolled` shadow the same pixels: the point light alone over the
/// `shadows` scene, each pixel's factor (light with shadows over light without) taken as lit
/// (> 0.5) or not in both layouts, at the CPU check's pixels (away from the CPU's shadow edges
/// by the edge band of `band_texels`, with the coarser of the two layouts' texels; off
/// geometric edges; N.L >= 0.2). Each layout is within that band of the true edge (the CPU
/// check), so outside it the two must agree: the same 99% as the CPU check, and the compared
/// pixels must include shadowed ones. The layouts differ in storage (the array's faces have
/// no border, so a different texel size) and filtering (seamless across face edges).
#[test]
fn the_cube_array_and_the_unrolled_cube_shadow_the_same_pixels() {
    let s = only(|_, l| matches!(l, Light::Point(_)), false);
    let plain = lit(&s, &settings(ShadowMode::None));
    let unrolled = lit(&s, &Settings { shadow_cube: ShadowCube::Unrolled, ..fine(ShadowMode::All) });
    let array = lit(&s, &Settings { shadow_cube: ShadowCube::Array, ..fine(ShadowMode::All) });
    for (f, c) in [(&unrolled, ShadowCube::Unrolled), (&array, ShadowCube::Array)] {
        assert_eq!(f.lights[0].1, 6, "{}: the point light cast no cube", cube_name(c));
        assert_eq!(f.tiles[f.lights[0].0 as usize].info[0] == 2.0, c == ShadowCube::Array);
    }
    let sh = array.stats.shadow.as_ref().expect("shadow stats");
    assert_eq!(sh.cube_layers, 6);
    assert!(sh.cube_side >= 32 && sh.bytes() <= 64 << 20, "{sh:?}");
    let check = Check {
        scene: &s,
        occluders: Occluders::of(&s),
        plain: &plain,
        shadowed: &array,
        band_texels: band_texels(&fine(ShadowMode::All)),
        misses: std::cell::RefCell::new(Some(array.image.clone())),
        pixels: None,
        against: Some(&unrolled),
    };
    let rot = s.camera.rotation();
    let lp = rot * (s.lights[0].position() - s.camera.position);
    let texel = |f: &Lit, vp: DVec3| texel_at(&f.tiles[(f.lights[0].0 + major_face(vp - lp)) as usize], vp);
    let light = s.lights[0].position();
    let (agree, total, blocked) = check.run(|_| light, |vp| Some(texel(&unrolled, vp).max(texel(&array, vp))));
    let share = agree as f64 / total.max(1) as f64;
    eprintln!("array vs unrolled: {agree} of {total} pixels agree ({share:.4}); {blocked} shadowed in unrolled");
    if share < 0.99 {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/image-tests");
        let _ = std::fs::create_dir_all(&dir);
        if let Some(img) = check.misses.borrow().as_ref() {
            let _ = img.save(dir.join("shadows-array-vs-unrolled-misses.png"));
        }
    }
    assert!(total > 1000 && blocked > 200, "only {total} pixels compared, {blocked} shadowed");
    assert!(share >= 0.99, "the cube array and the unrolled cube agree at {share:.4} of {total} pixels");
}

/// `--shadow-cube indirect` (seed 002's indirection cube) and `unrolled` (the major-axis pick)
/// read the same tiles, so they shadow the same pixels except within the indirection's lateral
/// error of an edge: the point light alone over the `shadows` scene, each pixel's factor taken
/// as lit (> 0.5) or not in both, compared at the pixels farther from the CPU's shadow edges
/// than the usual band plus sqrt(2) x `indirection_error` texels of the largest face. There
/// every pixel must agree (the lookups differ by less than the band; the wider depth bias
/// only removes shadow within its own slope's reach, inside the band too), and the compared
/// pixels must include shadowed ones. Then the same against the CPU's visibility, as every
/// light is checked. `--shadow-budget 64`: an atlas of 4096 and an indirection cube of 1024
/// (the faces at 320x180 take 128 texels).
#[test]
fn the_cube_indirection_shadows_the_pixels_the_face_pick_does() {
    use lampshade::renderer::shadows::{indirection_error, BORDER};
    let s = only(|_, l| matches!(l, Light::Point(_)), false);
    let plain = lit(&s, &settings(ShadowMode::None));
    let unrolled = lit(&s, &Settings { shadow_cube: ShadowCube::Unrolled, ..fine(ShadowMode::All) });
    let indirect = lit(&s, &Settings { shadow_cube: ShadowCube::Indirect, ..fine(ShadowMode::All) });
    let (first, count) = indirect.lights[0];
    assert_eq!(count, 6, "the point light cast no cube");
    assert_eq!(unrolled.lights[0], indirect.lights[0]);
    for f in 0..6 {
        let (a, b) = (&unrolled.tiles[(first + f) as usize], &indirect.tiles[(first + f) as usize]);
        assert_eq!((a.to_light, a.proj, a.rect), (b.to_light, b.proj, b.rect), "face {f}: the same tile");
    }
    let sh = indirect.stats.shadow.as_ref().expect("shadow stats");
    assert_eq!((sh.indirection_side, sh.indirection_bytes), (1024, 6 * 4 * 1024 * 1024), "{sh:?}");
    assert_eq!(unrolled.stats.shadow.as_ref().map(|s| s.indirection_bytes), Some(0));
    let largest = (0..6).map(|f| indirect.tiles[(first + f) as usize].info[2]).fold(0.0f32, f32::max) as f64;
    let lateral = 2f64.sqrt() * indirection_error(largest - 2.0 * BORDER as f64, sh.indirection_side);
    eprintln!("faces up to {largest} texels: the indirection's lookup within {lateral:.3} texels");
    let rot = s.camera.rotation();
    let lp = rot * (s.lights[0].position() - s.camera.position);
    let texel = |vp: DVec3| Some(texel_at(&unrolled.tiles[(first + major_face(vp - lp)) as usize], vp));
    let light = s.lights[0].position();
    let band = band_texels(&fine(ShadowMode::All)) + lateral;
    for against in [Some(&unrolled), None] {
        let check = Check {
            scene: &s,
            occluders: Occluders::of(&s),
            plain: &plain,
            shadowed: &indirect,
            band_texels: band,
            misses: std::cell::RefCell::new(Some(indirect.image.clone())),
            pixels: None,
            against,
        };
        let (agree, total, blocked) = check.run(|_| light, texel);
        let share = agree as f64 / total.max(1) as f64;
        let what = if against.is_some() { "the face pick" } else { "the CPU" };
        eprintln!("indirect vs {what}: {agree} of {total} pixels agree ({share:.5}); {blocked} shadowed");
        let least = if against.is_some() { 1.0 } else { 0.99 };
        if share < least {
            let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/image-tests");
            let _ = std::fs::create_dir_all(&dir);
            if let Some(img) = check.misses.borrow().as_ref() {
                let _ = img.save(dir.join("shadows-indirect-misses.png"));
            }
        }
        assert!(total > 1000 && blocked > 200, "only {total} pixels compared, {blocked} shadowed");
        assert!(share >= least, "the indirection and {what} agree at {share:.5} of {total} pixels");
    }
}

/// Every hard case with every light casting: finite, and no pixel gets more light than without
/// shadows (a shadow factor is in 0 ..= 1 and fp16 rounding is monotone, so with the same
/// lights blended in the same order the sum cannot grow; one fp16 step allowed).
#[test]
fn the_hard_cases_stay_finite_with_shadows_on() {
    for &name in HARD_CASES {
        let s = scene(name);
        let (w, h) = hard_case_size(name);
        let plain = render(&s, &settings(ShadowMode::None), w, h);
        for (filter, cube) in
            [ShadowFilter::Pcf2x2, ShadowFilter::Poisson16].into_iter().flat_map(|f| CUBES.map(|c| (f, c)))
        {
            let st = Settings { shadow_filter: filter, shadow_cube: cube, ..settings(ShadowMode::All) };
            let f = render(&s, &st, w, h);
            assert_finite(&f, name);
            let grown = f
                .diffuse
                .iter()
                .zip(&plain.diffuse)
                .chain(f.specular.iter().zip(&plain.specular))
                .filter(|(a, b)| **a > **b * (1.0 + 1.0 / 1024.0))
                .count();
            assert_eq!(grown, 0, "{name}/{}/{}: {grown} values grew with shadows on", filter.name(), cube_name(cube));
            let sh = f.stats.shadow.as_ref().expect("shadow stats");
            assert!(sh.casting > 0 || s.lights.is_empty() && s.sun.is_none(), "{name}: nothing cast");
        }
    }
}

/// Lights off screen and lights past the budget are counted, never dropped silently.
#[test]
fn fallbacks_are_counted_in_the_stats() {
    let mut s = only(|_, l| matches!(l, Light::Spot(_)), true);
    // A copy of the spot far behind the camera: off screen.
    let mut off = s.lights[0];
    if let Light::Spot(sp) = &mut off {
        sp.position = DVec3::new(0.0, 5.0, 80.0);
        sp.radius = 3.0;
    }
    s.lights_mut().push(off);
    // And 40 point lights on screen: with a 0.25 MiB atlas (256 texels) the sun's cascades take
    // 3 x 64², so at most 10 of them (6 x 32² each) fit.
    for k in 0..40 {
        let a = k as f64 * 0.157;
        s.lights_mut().push(Light::Point(lampshade::scene::PointLight {
            position: DVec3::new(3.0 * a.cos(), 1.0, 3.0 * a.sin()),
            color: Vec3::ONE,
            intensity: 0.1,
            radius: 2.0,
            cast_shadows: k != 0,
            cookie: None,
            mask: lampshade::scene::ALL_LAYERS,
        }));
    }
    for cube in CUBES {
        let st = Settings { shadow_budget_mb: 0.25, shadow_cube: cube, ..settings(ShadowMode::All) };
        let f = lit(&s, &st);
        let sh = f.stats.shadow.expect("shadow stats");
        eprintln!("{}: {sh:?}", cube_name(cube));
        match cube {
            ShadowCube::Unrolled | ShadowCube::Indirect => {
                assert_eq!(sh.atlas_side, 256);
                assert_eq!(sh.cube_bytes, 0);
            }
            // The atlas shrinks to what the sun and the spot take (128²); the cubes get the
            // rest of the 0.25 MiB: (262144 - 65536) / (6 x 4 x 32²) = 8 cubes of 32 texels.
            ShadowCube::Array => {
                assert_eq!(sh.atlas_side, 128);
                assert_eq!((sh.cube_side, sh.cube_layers), (32, 48), "{sh:?}");
                assert!(sh.bytes() <= 256 << 10, "{} bytes over the budget", sh.bytes());
            }
        }
        assert_eq!(sh.fallback_off_screen, 1);
        assert_eq!(sh.flag_off, 1);
        assert!(sh.fallback_budget > 0, "no light fell back for the budget");
        assert_eq!(
            sh.casting + sh.fallback_budget,
            1 + 1 + 39,
            "the sun, the spot and 39 points: each casts or is counted"
        );
        assert!(sh.atlas_used <= 1.0);
        let unshadowed = f.lights.iter().filter(|l| l.0 == lampshade::renderer::records::NO_SHADOW).count();
        assert_eq!(unshadowed as u32, sh.fallback_budget + sh.fallback_off_screen + sh.flag_off);
        let _ = (&f.image, DMat3::IDENTITY);
    }
}

/// glTF: `"extras": {"cast_shadows": false}` on a KHR_lights_punctual light turns its shadow
/// off; another type is a warning naming the light, and the light casts.
#[test]
fn gltf_extras_set_a_lights_shadow_flag() {
    use lampshade::scene::import::{self, ImportOptions};
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/gltf-tests/shadow-extras");
    let _ = std::fs::remove_dir_all(&dir);
    lampshade::scene::room::write(&dir).expect("write the room");
    let path = dir.join("room.gltf");
    let original: serde_json::Value = serde_json::from_slice(&std::fs::read(&path).expect("room.gltf")).expect("json");
    let load = |extras: [serde_json::Value; 2]| {
        let mut v = original.clone();
        let lights = v["extensions"]["KHR_lights_punctual"]["lights"].as_array_mut().expect("the room's lights");
        assert!(lights.len() >= 2, "the room has {} lights", lights.len());
        for (l, e) in lights.iter_mut().zip(extras) {
            l["extras"] = e;
        }
        std::fs::write(&path, serde_json::to_vec(&v).expect("json")).expect("write");
        import::load(&path, &ImportOptions::default(), &mut |_| {}).expect("the room loads")
    };
    let plain = load([serde_json::json!({}), serde_json::json!({})]);
    let flags = |i: &import::Imported| i.scene.lights.iter().map(|l| l.cast_shadows()).collect::<Vec<_>>();
    assert!(flags(&plain).iter().all(|&c| c), "without extras every light casts");
    let off = load([serde_json::json!({"cast_shadows": false}), serde_json::json!({"cast_shadows": "no"})]);
    let f = flags(&off);
    assert_eq!(f.iter().filter(|&&c| !c).count(), 1, "exactly one light's flag is off: {f:?}");
    assert!(
        off.warnings.iter().any(|w| w.contains("cast_shadows")),
        "a non-boolean cast_shadows is a warning: {:?}",
        off.warnings
    );
}

/// Per pixel, how many 8-bit steps the shadows take off (largest channel of the frame without
/// shadows minus the frame with every light casting) on `path`.
fn darkening(s: &Scene, path: lampshade::renderer::RenderPath) -> Vec<i32> {
    let gpu = gpu();
    let image = |shadows| {
        let st = Settings { path, ..settings(shadows) };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &st).expect("renderer");
        render_image(gpu, &mut r, s, &st, W, H).expect("render").0
    };
    let (shadowed, bare) = (image(ShadowMode::All), image(ShadowMode::None));
    shadowed
        .pixels()
        .zip(bare.pixels())
        .map(|(a, b)| (0..3).map(|c| b[c] as i32 - a[c] as i32).max().unwrap_or(0))
        .collect()
}

/// The other paths (light pre-pass, forward single- and multi-pass) shade each light
/// through `shade_light` and the sun through `ambient_sun`, as deferred does, and the shadow
/// pass runs before every path: each must darken the pixels deferred shadows, and only those.
/// Compared away from shadow edges (a pixel whose 3x3 neighbourhood is all in deferred's
/// shadow by >= 24 steps, or whose 5x5 neighbourhood is all untouched by it, <= 1 step): the
/// forward paths shade with the exact normal and position where deferred reads the G-buffer's
/// quantised ones, and the normal offset moves the lookup with the normal, which can move a
/// penumbra's faint outer edge by a pixel or two (a first run with a 3x3 neighbourhood outside
/// found one such pixel on each forward path).
#[test]
fn every_render_path_shadows_the_same_pixels() {
    use lampshade::renderer::RenderPath;
    let s = scene("shadows");
    let reference = darkening(&s, RenderPath::Deferred);
    let (w, h) = (W as usize, H as usize);
    let neighbourhood = |i: usize, r: usize| {
        let (x, y) = (i % w, i / w);
        (y - r..=y + r).flat_map(move |y| (x - r..=x + r).map(move |x| y * w + x))
    };
    let interior: Vec<usize> =
        (0..w * h).filter(|i| i % w > 1 && i % w + 2 < w && i / w > 1 && i / w + 2 < h).collect();
    let inside: Vec<usize> =
        interior.iter().copied().filter(|&i| neighbourhood(i, 1).all(|j| reference[j] >= 24)).collect();
    let outside: Vec<usize> =
        interior.iter().copied().filter(|&i| neighbourhood(i, 2).all(|j| reference[j] <= 1)).collect();
    assert!(inside.len() > 1000, "only {} pixels deep in deferred's shadows", inside.len());
    assert!(outside.len() > 1000, "only {} pixels untouched by deferred's shadows", outside.len());
    let mut failures = Vec::new();
    for path in [RenderPath::LightPrepass, RenderPath::Forward, RenderPath::ForwardMultipass] {
        let d = darkening(&s, path);
        let missed = inside.iter().filter(|&&i| d[i] < 12).count();
        let extra = outside.iter().filter(|&&i| d[i] > 1).count();
        let most = outside.iter().map(|&i| (d[i], i % w, i / w)).max().unwrap_or_default();
        eprintln!(
            "{path:?}: {missed} of {} shadowed pixels not darkened by >= 12 steps, {extra} of {} unshadowed ones \
             darkened (most: {} steps at {}, {})",
            inside.len(),
            outside.len(),
            most.0,
            most.1,
            most.2
        );
        if missed > 0 || extra > 0 {
            failures.push(format!("{path:?}: {missed} shadowed pixels missed, {extra} unshadowed darkened"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The viewer's atlas panel lists what is in the atlas: with `--shadow-cube unrolled` the
/// point light's six faces are atlas tiles, with `array` they are layers of the cube array and
/// not in the atlas (so the panel lists the light as shadowed outside it), while the sun's
/// cascades and the spot's tile stay; every listed tile lies inside the atlas.
#[test]
fn the_atlas_panel_lists_only_tiles_that_are_in_the_atlas() {
    use lampshade::renderer::inspect::TileOwner;
    let gpu = gpu();
    let s = scene("shadows");
    let point = s.lights.iter().position(|l| matches!(l, Light::Point(_))).expect("a point light");
    for cube in CUBES {
        let st = Settings { shadow_cube: cube, ..settings(ShadowMode::All) };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &st).expect("renderer");
        render_image(gpu, &mut r, &s, &st, W, H).expect("render");
        let (side, tiles) = r.last_frame().shadow_atlas_tiles();
        let faces = tiles.iter().filter(|t| t.owner == TileOwner::Cube(point)).count();
        let expected = if cube == ShadowCube::Unrolled { 6 } else { 0 };
        assert_eq!(faces, expected, "{}: the point light's faces listed in the atlas", cube_name(cube));
        assert!(tiles.iter().any(|t| t.owner == TileOwner::Sun), "{}: no cascade listed", cube_name(cube));
        assert!(tiles.iter().any(|t| matches!(t.owner, TileOwner::Spot(_))), "{}: no spot tile", cube_name(cube));
        for t in &tiles {
            assert!(
                t.size > 0 && t.x + t.size <= side && t.y + t.size <= side,
                "{}: {t:?} outside the atlas",
                cube_name(cube)
            );
        }
    }
}

/// The `shadow` view walks the casting lights, not every light: with 66,000 lights that reach
/// nothing and cast nothing put before the `shadows` scene's own (so its casters' indices pass
/// 65,535, after which lavapipe ends an invocation's loops), the view is the scene's own pixel
/// for pixel, with both cube layouts. Walking every light, it left the casters past the limit
/// out.
#[test]
fn the_shadow_view_shows_casters_past_the_loop_limit() {
    use lampshade::renderer::DebugView;
    use lampshade::scene::PointLight;
    let gpu = gpu();
    let (w, h) = (160, 90);
    let base = scene("shadows");
    let mut crowded = base.clone();
    let idle = Light::Point(PointLight {
        position: DVec3::new(0.0, -1.0e4, 0.0),
        color: Vec3::ONE,
        intensity: 0.0,
        radius: 0.01,
        cookie: None,
        mask: lampshade::scene::ALL_LAYERS,
        cast_shadows: false,
    });
    crowded.set_lights(std::iter::repeat_n(idle, 66_000).chain(base.lights.iter().cloned()).collect());
    for cube in CUBES {
        let s = Settings {
            shadows: ShadowMode::All,
            shadow_cube: cube,
            debug_view: DebugView::Shadow,
            count_fragments: false,
            ..Settings::default()
        };
        let mut r = Renderer::new(gpu, OUTPUT_FORMAT, &s).expect("renderer");
        let (own, _) = render_image(gpu, &mut r, &base, &s, w, h).expect("render");
        let casters = r.last_frame().shadow_plan().casters.clone();
        assert!(casters.len() >= 2, "{cube:?}: {} casters", casters.len());
        // The view shows shadow somewhere (not all lit).
        let dark = own.pixels().filter(|p| p[0] < 128).count();
        assert!(dark > 50, "{cube:?}: {dark} shadowed pixels in the shadow view");
        let (many, _) = render_image(gpu, &mut r, &crowded, &s, w, h).expect("render");
        assert_eq!(
            r.last_frame().shadow_plan().casters,
            casters.iter().map(|c| c + 66_000).collect::<Vec<_>>(),
            "{cube:?}"
        );
        let diff = max_channel_difference(&own, &many);
        assert_eq!(diff, 0, "{cube:?}: the shadow view changed by {diff} with the casters past index 65,535");
    }
}

/// The ledger's shadow times: a counted frame with timestamps draws each casting light's tiles
/// (and the sun's cascades) in render passes of their own, each timed. The maps they leave are
/// the uncounted frame's (the `shadow` view is the same, byte for byte); every light that holds
/// tiles has a time and no other light has one; the sun's cascades have theirs; and the times
/// add up to no more than the shadow pass's span, whose two stamps the timed passes run between
/// one after another. With every light casting, on both cube layouts that draw into the atlas
/// and into the cube array.
#[test]
fn the_ledger_times_each_lights_shadow_maps() {
    use lampshade::renderer::{DebugView, ShadowCube, ShadowMode};
    let s = scene("shadows");
    for cube in [ShadowCube::Unrolled, ShadowCube::Array] {
        let base = Settings { shadows: ShadowMode::All, shadow_cube: cube, timestamps: true, ..Settings::default() };
        let counted = Settings { count_fragments: true, ..base.clone() };
        let plain = Settings { count_fragments: false, ..base.clone() };
        let view = |st: &Settings| render(&s, &Settings { debug_view: DebugView::Shadow, ..st.clone() }, 160, 90).image;
        assert!(view(&counted) == view(&plain), "{cube:?}: the timed shadow passes drew other maps");
        let stats = render(&s, &counted, 160, 90).stats;
        let sh = stats.shadow.as_ref().expect("shadow stats");
        let mut sum = 0.0;
        for l in &stats.per_light {
            assert_eq!(l.shadow_ms.is_some(), l.shadow_tiles > 0, "{cube:?}: light {}: {:?}", l.index, l.shadow_ms);
            sum += l.shadow_ms.unwrap_or(0.0);
        }
        assert!(stats.per_light.iter().any(|l| l.shadow_ms.is_some()), "{cube:?}: no light timed");
        assert_eq!(sh.sun_ms.is_some(), sh.sun_cascades > 0, "{cube:?}");
        sum += sh.sun_ms.unwrap_or(0.0);
        let span = stats.gpu_ms.shadows.expect("the shadow pass timed");
        assert!(sum <= span + 1e-6, "{cube:?}: the owners' {sum} ms over the pass's {span} ms");
        let plain = render(&s, &Settings { per_light_stats: true, ..plain }, 160, 90).stats;
        assert!(!plain.per_light.is_empty() && plain.per_light.iter().all(|l| l.shadow_ms.is_none()));
    }
}
