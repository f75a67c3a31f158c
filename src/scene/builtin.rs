//! Built-in deterministic scenes: seed 000's demo, seed 001's spot light, and the camera cases
//! the culling modes must survive. Every value derives from an index hash, so a scene is the
//! same on every machine and the first `k` lights do not change when more are asked for.

use super::*;
use glam::{DVec3, Vec3};

/// The names `lampshade render SCENE` accepts.
pub const NAMES: &[(&str, &str)] = &[
    ("demo", "seed 000: floor, pillars and boxes, sun + ambient, 1024 animated point lights, a few spots"),
    ("spot", "seed 001: one spot light over a floor and boxes"),
    ("inside", "the camera stands inside a point light's volume"),
    ("near", "a light volume crosses the near plane"),
    ("far", "a light volume crosses the far plane"),
    ("occluded", "a light hidden behind a wall"),
    ("floating", "a light in front of all geometry, touching nothing"),
    ("classify", "one light, one wall, one box: seed 000's stencil diagram"),
    ("on-surface", "hard case: point lights exactly on the floor and on a wall"),
    ("grazing", "hard case: the camera skims the floor at 1 degree"),
    ("far-origin", "hard case: `classify` moved 100,000 units from the origin"),
    ("tiny-radius", "hard case: lights of radius 0.001 beside lights of radius 10,000"),
    ("overflow", "hard case: 10,000 bright overlapping lights (fp16 overflow)"),
    ("normals", "hard case: normals at the encoding's singularities, facing away, and zero-length"),
    ("spot-extremes", "hard case: spot cones of 0 and 89 degrees"),
    ("coincident", "hard case: a light volume touching a wall; a light inside a box"),
    ("glass", "the demo's 1024 lights through rows of glass walls and boxes: the forward pass's stress case; the glass distorts (--distortion on)"),
    ("street", "hard case: a street-level camera among 64 point lights, many crossing the near plane"),
    ("sphere-wall", "the camera at the centre of an inward-facing sphere lit by 4096 evenly spread point lights"),
    ("railings", "a depth discontinuity in every tile: thin railings 4 units from the camera before a wall 42 away, half the lights at each"),
    ("many-lights", "Bevy's many_lights layout: 100,000 point lights of range 0.3 on an inward-facing sphere of radius 50, the camera at its centre"),
    (
        "materials",
        "the six reflectance models side by side: blinn-phong, lambert, metal, toon, unlit, phong spheres and boxes",
    ),
    ("shadows", "boxes and a thin wall on a floor under the sun, a spot and a point light (--shadows all)"),
    (
        "courtyard",
        "seed 004: a long courtyard of boxes under the sun, lightmapped (baked on first use): realtime light near the camera crossfading to baked far away (--lightmap-distance)",
    ),
    (
        "cookies",
        "seed 004: a spot throwing the window cookie on a wall, a point light's cube cookie, two objects on layers 1 and 2 under lights whose masks leave one of them out",
    ),
];

/// Options the CLI and the viewer pass to a built-in scene.
#[derive(Clone, Copy, Debug)]
pub struct BuiltinOptions {
    /// Number of point lights in `demo` (default 1024).
    pub lights: Option<usize>,
    /// Animation time in seconds.
    pub time: f64,
}

impl Default for BuiltinOptions {
    fn default() -> Self {
        Self { lights: None, time: 0.0 }
    }
}

/// The built-in scenes whose light count `--lights` sets.
pub const TAKES_LIGHT_COUNT: &[&str] =
    &["demo", "overflow", "glass", "street", "sphere-wall", "many-lights", "railings"];

/// The most lights `--lights` gives a built-in scene. Past
/// [`crate::renderer::settings::MAX_LIGHTS_EVERY_MODE`] only the list modes (`zbin`,
/// `clustered`, `tiled`) take them (the others refuse with a message).
pub const MAX_LIGHTS: usize = 1_000_000;

/// Builds a built-in scene by name, or says which names exist.
pub fn build(name: &str, opts: BuiltinOptions) -> Result<Scene, String> {
    if let Some(n) = opts.lights.filter(|&n| n > MAX_LIGHTS) {
        return Err(format!("--lights {n} is more than the {MAX_LIGHTS} Lampshade supports"));
    }
    let scene = match name {
        "demo" => demo(opts.lights.unwrap_or(1024), opts.time),
        "spot" => spot(),
        "inside" => single_light_case(name, DVec3::new(0.0, 1.5, 4.0), DVec3::new(0.5, 1.2, 3.0), 5.0, 0.1, 200.0),
        "near" => single_light_case(name, DVec3::new(0.0, 1.5, 8.0), DVec3::new(0.0, 1.2, 5.5), 3.0, 0.1, 200.0),
        // The camera's far plane cuts through the volume of a light that still reaches the floor.
        "far" => single_light_case(name, DVec3::new(0.0, 3.0, 14.0), DVec3::new(0.0, 1.0, -8.0), 9.0, 0.1, 23.0),
        "occluded" => occluded(),
        "floating" => floating(),
        "classify" => classify(),
        "on-surface" => on_surface(),
        "grazing" => grazing(),
        "far-origin" => translated(classify(), DVec3::new(1e5, 0.0, -1e5), "far-origin"),
        "tiny-radius" => tiny_radius(),
        "overflow" => overflow(opts.lights.unwrap_or(10_000)),
        "normals" => normals(),
        "spot-extremes" => spot_extremes(),
        "coincident" => coincident(),
        "glass" => glass(opts.lights.unwrap_or(1024), opts.time),
        "street" => street(opts.lights.unwrap_or(64)),
        "sphere-wall" => sphere_wall(opts.lights.unwrap_or(4096)),
        "many-lights" => many_lights(opts.lights.unwrap_or(100_000)),
        "railings" => railings(opts.lights.unwrap_or(1024)),
        "materials" => materials(),
        "shadows" => shadows(),
        "cookies" => cookies(),
        "courtyard" => courtyard(),
        _ => {
            let names: Vec<&str> = NAMES.iter().map(|(n, _)| *n).collect();
            return Err(format!("unknown scene '{name}'; built-in scenes are: {}", names.join(", ")));
        }
    };
    Ok(scene)
}

fn hash(seed: u64, i: u64) -> u64 {
    // splitmix64
    let mut z = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ i.wrapping_add(0x632B_E59B_D9B4_E019);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A deterministic number in [0, 1).
fn unit(seed: u64, i: u64) -> f64 {
    (hash(seed, i) >> 11) as f64 / (1u64 << 53) as f64
}

pub(crate) fn hue(h: f32) -> Vec3 {
    let c = |o: f32| ((h * 6.0 + o).rem_euclid(6.0) - 3.0).abs().clamp(1.0, 2.0) - 1.0;
    Vec3::new(1.0 - c(0.0), 1.0 - c(4.0), 1.0 - c(2.0)).max(Vec3::ZERO)
}

struct Builder {
    scene: Scene,
}

impl Builder {
    fn new(name: &str, camera: Camera) -> Self {
        Self { scene: Scene { meshes: vec![Mesh::cube()], ..Scene::new(name, camera) } }
    }

    fn material(&mut self, m: Material) -> usize {
        self.scene.materials.push(m);
        self.scene.materials.len() - 1
    }

    /// An axis-aligned box from its minimum corner to its maximum corner.
    fn boxed(&mut self, min: DVec3, max: DVec3, material: usize) {
        let t = DMat4::from_translation((min + max) * 0.5) * DMat4::from_scale(max - min);
        self.scene.objects.push(Object { mesh: 0, material, transform: t, layer: 0 });
    }

    fn point(&mut self, position: DVec3, color: Vec3, intensity: f32, radius: f32) {
        self.scene.lights_mut().push(Light::Point(PointLight {
            position,
            color,
            intensity,
            radius,
            cast_shadows: true,
            cookie: None,
            mask: crate::scene::ALL_LAYERS,
        }));
    }
}

/// Seed 000's demo: a large floor with pillars and boxes, a sun, ambient, `n` coloured point
/// lights circling above the floor at time `t`, and four spot lights.
pub fn demo(n: usize, t: f64) -> Scene {
    let camera = Camera { far: 300.0, ..Camera::looking_at(DVec3::new(0.0, 14.0, 46.0), DVec3::new(0.0, 0.0, 4.0)) };
    let mut b = Builder::new("demo", camera);
    b.scene.sun = Some(Sun::default_sun());
    b.scene.ambient = Vec3::new(0.025, 0.028, 0.035);
    let floor = b.material(Material {
        diffuse: Vec3::splat(0.55),
        specular_level: 0.5,
        specular_exponent: 48.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-80.0, -1.0, -80.0), DVec3::new(80.0, 0.0, 80.0), floor);
    // Pillars on a grid.
    let pillar = b.material(Material {
        diffuse: Vec3::new(0.7, 0.68, 0.62),
        specular_level: 0.2,
        specular_exponent: 16.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    for gx in -4..=4 {
        for gz in -4..=4 {
            let (x, z) = (gx as f64 * 16.0, gz as f64 * 16.0);
            b.boxed(DVec3::new(x - 0.8, 0.0, z - 0.8), DVec3::new(x + 0.8, 9.0, z + 0.8), pillar);
        }
    }
    // Boxes of varied size and colour.
    for i in 0..120u64 {
        let c = hue(unit(7, i) as f32) * 0.6 + Vec3::splat(0.25);
        let m = b.material(Material {
            diffuse: c,
            specular_level: unit(8, i) as f32 * 0.8,
            specular_exponent: 8.0 + unit(9, i) as f32 * 120.0,
            emissive: if i % 29 == 0 { c * 0.6 } else { Vec3::ZERO },
            ..Material::default()
        });
        let x = (unit(1, i) - 0.5) * 140.0;
        let z = (unit(2, i) - 0.5) * 140.0;
        let sx = 0.6 + unit(3, i) * 3.0;
        let sz = 0.6 + unit(4, i) * 3.0;
        let sy = 0.4 + unit(5, i) * 3.5;
        b.boxed(DVec3::new(x - sx, 0.0, z - sz), DVec3::new(x + sx, sy, z + sz), m);
    }
    // Point lights: each circles its own centre.
    for i in 0..n as u64 {
        let cx = (unit(11, i) - 0.5) * 150.0;
        let cz = (unit(12, i) - 0.5) * 150.0;
        let orbit = 1.0 + unit(13, i) * 4.0;
        let speed = 0.3 + unit(14, i) * 0.9;
        let phase = unit(15, i) * std::f64::consts::TAU;
        let a = phase + t * speed;
        let y = 0.6 + unit(16, i) * 2.5 + 0.4 * (t * 1.3 + phase).sin();
        let pos = DVec3::new(cx + orbit * a.cos(), y, cz + orbit * a.sin());
        let color = hue(unit(17, i) as f32);
        b.point(pos, color, 0.5 + unit(18, i) as f32 * 0.7, 2.5 + unit(19, i) as f32 * 3.0);
    }
    // A few spot lights sweeping the floor.
    for k in 0..4u64 {
        let a = k as f64 * std::f64::consts::FRAC_PI_2 + t * 0.2;
        let pos = DVec3::new(20.0 * a.cos(), 10.0, 20.0 * a.sin());
        let dir = (DVec3::new(12.0 * a.cos(), 0.0, 12.0 * a.sin()) - pos).normalize().as_vec3();
        b.scene.lights_mut().push(Light::Spot(SpotLight {
            position: pos,
            direction: dir,
            color: hue(0.1 + k as f32 * 0.25) * 0.5 + Vec3::splat(0.5),
            intensity: 4.0,
            radius: 22.0,
            inner_angle: 14f32.to_radians(),
            outer_angle: 22f32.to_radians(),
            cast_shadows: true,
            cookie: None,
            mask: crate::scene::ALL_LAYERS,
        }));
    }
    b.scene
}

/// The forward pass's stress case: the demo (its lights, floor, pillars and boxes) with five
/// 120-unit glass walls across the view and a dozen glass boxes, all blended. Each wall's
/// bounding sphere reaches most of the lights, so per-object light lists hold hundreds.
pub fn glass(n: usize, t: f64) -> Scene {
    let mut scene = demo(n, t);
    scene.name = "glass".into();
    let mut b = Builder { scene };
    let pane = b.material(Material {
        diffuse: Vec3::new(0.55, 0.75, 0.8),
        specular_level: 0.9,
        specular_exponent: 256.0,
        emissive: Vec3::ZERO,
        alpha: 0.3,
        alpha_mode: AlphaMode::Blend,
        // Seed 002's distortion (`--distortion on`): the panes bend what is behind them.
        distortion: 0.02,
        ..Material::default()
    });
    for z in [24.0, 8.0, -8.0, -24.0, -40.0] {
        b.boxed(DVec3::new(-60.0, 0.0, z - 0.1), DVec3::new(60.0, 6.0, z + 0.1), pane);
    }
    for i in 0..12u64 {
        let tint = b.material(Material {
            diffuse: hue(unit(21, i) as f32) * 0.5 + Vec3::splat(0.4),
            specular_level: 0.8,
            specular_exponent: 128.0,
            emissive: Vec3::ZERO,
            alpha: 0.25 + unit(22, i) as f32 * 0.4,
            alpha_mode: AlphaMode::Blend,
            distortion: 0.04,
            ..Material::default()
        });
        let x = (unit(23, i) - 0.5) * 100.0;
        let z = (unit(24, i) - 0.5) * 100.0;
        let s = 1.0 + unit(25, i) * 2.5;
        b.boxed(DVec3::new(x - s, 0.0, z - s), DVec3::new(x + s, 2.0 * s, z + s), tint);
    }
    b.scene
}

/// Seed 001's case: one spot light over a floor and a few boxes.
pub fn spot() -> Scene {
    let camera = Camera::looking_at(DVec3::new(7.0, 7.0, 11.0), DVec3::new(0.0, 0.5, 0.0));
    let mut b = Builder::new("spot", camera);
    b.scene.ambient = Vec3::splat(0.02);
    let floor = b.material(Material {
        diffuse: Vec3::new(0.6, 0.58, 0.55),
        specular_level: 0.4,
        specular_exponent: 40.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-12.0, -1.0, -12.0), DVec3::new(12.0, 0.0, 12.0), floor);
    let wall = b.material(Material::diffuse(Vec3::new(0.5, 0.55, 0.7)));
    b.boxed(DVec3::new(-12.0, 0.0, -12.0), DVec3::new(12.0, 6.0, -11.0), wall);
    for (i, (x, z, s, h)) in [(-1.5, 0.5, 1.0, 2.0), (2.0, -1.5, 0.7, 1.2), (0.5, 2.5, 0.5, 3.0)].iter().enumerate() {
        let m = b.material(Material {
            diffuse: hue(i as f32 * 0.3) * 0.6 + Vec3::splat(0.2),
            specular_level: 0.6,
            specular_exponent: 64.0,
            emissive: Vec3::ZERO,
            ..Material::default()
        });
        b.boxed(DVec3::new(x - s, 0.0, z - s), DVec3::new(x + s, *h, z + s), m);
    }
    b.scene.lights_mut().push(Light::Spot(SpotLight {
        position: DVec3::new(-2.0, 7.0, 1.0),
        direction: Vec3::new(0.25, -1.0, -0.1).normalize(),
        color: Vec3::new(1.0, 0.92, 0.8),
        intensity: 6.0,
        radius: 13.0,
        inner_angle: 20f32.to_radians(),
        outer_angle: 32f32.to_radians(),
        cast_shadows: true,
        cookie: None,
        mask: crate::scene::ALL_LAYERS,
    }));
    b.scene
}

/// A floor, a back wall and one point light, seen from `eye`.
fn single_light_case(name: &str, eye: DVec3, light: DVec3, radius: f32, near: f64, far: f64) -> Scene {
    let camera = Camera { near, far, ..Camera::looking_at(eye, DVec3::new(0.0, 0.5, -4.0)) };
    let mut b = Builder::new(name, camera);
    let floor = b.material(Material {
        diffuse: Vec3::splat(0.6),
        specular_level: 0.5,
        specular_exponent: 32.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-30.0, -1.0, -40.0), DVec3::new(30.0, 0.0, 30.0), floor);
    let wall = b.material(Material::diffuse(Vec3::new(0.6, 0.5, 0.4)));
    b.boxed(DVec3::new(-3.0, 0.0, -2.0), DVec3::new(-1.0, 2.5, -1.0), wall);
    b.point(light, Vec3::new(1.0, 0.85, 0.6), 3.0, radius);
    b.scene
}

/// A light behind a wall: no pixel it could light is visible.
fn occluded() -> Scene {
    let mut b = Builder::new("occluded", Camera::looking_at(DVec3::new(0.0, 2.0, 10.0), DVec3::new(0.0, 2.0, 0.0)));
    let floor = b.material(Material::diffuse(Vec3::splat(0.5)));
    b.boxed(DVec3::new(-20.0, -1.0, -20.0), DVec3::new(20.0, 0.0, 20.0), floor);
    let wall = b.material(Material::diffuse(Vec3::new(0.5, 0.6, 0.5)));
    b.boxed(DVec3::new(-30.0, 0.0, 0.0), DVec3::new(30.0, 30.0, 1.0), wall);
    // Radius 2 at 2 units behind the wall (which is 1 unit thick): it reaches nothing visible.
    b.point(DVec3::new(0.0, 3.0, -2.5), Vec3::new(1.0, 0.3, 0.2), 4.0, 2.0);
    // A visible light so the frame is not only ambient.
    b.point(DVec3::new(3.0, 1.0, 3.0), Vec3::new(0.3, 0.6, 1.0), 3.0, 3.0);
    b.scene
}

/// A light floating between the camera and the geometry, touching nothing.
fn floating() -> Scene {
    let mut b = Builder::new("floating", Camera::looking_at(DVec3::new(0.0, 3.0, 12.0), DVec3::new(0.0, 0.0, 0.0)));
    let floor = b.material(Material::diffuse(Vec3::splat(0.5)));
    b.boxed(DVec3::new(-20.0, -1.0, -20.0), DVec3::new(20.0, 0.0, 20.0), floor);
    b.point(DVec3::new(0.0, 3.2, 8.0), Vec3::new(1.0, 0.8, 0.3), 5.0, 1.5);
    b.point(DVec3::new(-3.0, 0.8, 0.0), Vec3::new(0.3, 1.0, 0.5), 3.0, 3.0);
    b.scene
}

/// Seed 000's diagram: one light, one wall, one box. From the camera the wall hides the left
/// part of the light's volume, the box stands inside it, and the floor behind is out of reach.
pub fn classify() -> Scene {
    let mut b = Builder::new("classify", Camera::looking_at(DVec3::new(0.0, 2.5, 9.0), DVec3::new(0.0, 1.0, 0.0)));
    b.scene.ambient = Vec3::splat(0.05);
    let floor = b.material(Material::diffuse(Vec3::splat(0.5)));
    b.boxed(DVec3::new(-20.0, -1.0, -20.0), DVec3::new(20.0, 0.0, 20.0), floor);
    let wall = b.material(Material::diffuse(Vec3::new(0.5, 0.5, 0.6)));
    // The wall stands in front of the light's left half.
    b.boxed(DVec3::new(-6.0, 0.0, 4.0), DVec3::new(0.4, 5.0, 4.5), wall);
    let boxm = b.material(Material::diffuse(Vec3::new(0.7, 0.5, 0.3)));
    b.boxed(DVec3::new(0.5, 0.0, -0.5), DVec3::new(1.5, 1.0, 0.5), boxm);
    b.point(DVec3::new(1.0, 1.8, 0.0), Vec3::ONE, 4.0, 3.0);
    b.scene
}

/// A floor and a wall with a few lights, the base of several hard cases.
fn room(name: &str, camera: Camera) -> Builder {
    let mut b = Builder::new(name, camera);
    b.scene.ambient = Vec3::splat(0.04);
    let floor = b.material(Material {
        diffuse: Vec3::splat(0.6),
        specular_level: 0.5,
        specular_exponent: 64.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-20.0, -1.0, -20.0), DVec3::new(20.0, 0.0, 20.0), floor);
    let wall = b.material(Material::diffuse(Vec3::new(0.5, 0.55, 0.6)));
    b.boxed(DVec3::new(-20.0, 0.0, -6.0), DVec3::new(20.0, 8.0, -5.0), wall);
    b
}

fn on_surface() -> Scene {
    let mut b = room("on-surface", Camera::looking_at(DVec3::new(0.0, 4.0, 8.0), DVec3::new(0.0, 0.5, -2.0)));
    b.point(DVec3::new(-2.0, 0.0, 0.0), Vec3::new(1.0, 0.6, 0.3), 3.0, 3.0);
    b.point(DVec3::new(2.0, 2.0, -5.0), Vec3::new(0.3, 0.6, 1.0), 3.0, 3.0);
    b.point(DVec3::new(0.0, 0.0, -5.0), Vec3::ONE, 2.0, 2.0);
    b.scene
}

fn grazing() -> Scene {
    let mut cam = Camera::looking_at(DVec3::new(0.0, 0.05, 15.0), DVec3::new(0.0, 0.0, -5.0));
    cam.pitch = -1f64.to_radians();
    let mut b = room("grazing", cam);
    for i in 0..12 {
        let x = -11.0 + 2.0 * i as f64;
        b.point(DVec3::new(x, 0.3, 2.0 - i as f64), hue(i as f32 / 12.0), 3.0, 4.0);
    }
    b.scene
}

/// Moves a whole scene: positions far from the origin must render like the original,
/// because the renderer works camera-relative in f64 before converting to f32.
pub fn translated(mut scene: Scene, by: DVec3, name: &str) -> Scene {
    scene.name = name.into();
    scene.camera.position += by;
    for o in &mut scene.objects {
        o.transform = DMat4::from_translation(by) * o.transform;
    }
    for l in scene.lights_mut() {
        match l {
            Light::Point(p) => p.position += by,
            Light::Spot(s) => s.position += by,
        }
    }
    scene
}

fn tiny_radius() -> Scene {
    let mut b = room("tiny-radius", Camera::looking_at(DVec3::new(0.0, 3.0, 8.0), DVec3::new(0.0, 0.0, 0.0)));
    b.point(DVec3::new(0.0, 0.0005, 0.0), Vec3::new(1.0, 0.2, 0.2), 50.0, 1e-3);
    b.point(DVec3::new(1.0, 1.0, 1.0), Vec3::new(0.2, 1.0, 0.2), 50.0, 1e-3);
    b.point(DVec3::new(3.0, 20.0, -40.0), Vec3::new(0.3, 0.3, 0.6), 0.2, 1e4);
    b.scene
}

fn overflow(n: usize) -> Scene {
    let mut b = room("overflow", Camera::looking_at(DVec3::new(0.0, 4.0, 8.0), DVec3::new(0.0, 0.0, 0.0)));
    for i in 0..n as u64 {
        let p = DVec3::new((unit(21, i) - 0.5) * 6.0, 0.2 + unit(22, i) * 2.0, (unit(23, i) - 0.5) * 6.0);
        b.point(p, hue(unit(24, i) as f32), 1000.0, 6.0);
    }
    b.scene
}

fn normals() -> Scene {
    // Straight down: the floor's normal is exactly +z in view space.
    let mut cam = Camera::looking_at(DVec3::new(0.0, 10.0, 0.0), DVec3::new(0.0, 0.0, 0.0));
    cam.pitch = -std::f64::consts::FRAC_PI_2;
    cam.yaw = 0.0;
    let mut b = room("normals", cam);
    // A quad whose normals face away from the viewer (-z in view space) and one whose normals
    // are zero-length, as a broken file might have them.
    let quad = |normal: [f32; 3]| Mesh {
        name: "quad".into(),
        vertices: [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .iter()
            .map(|&(x, z)| Vertex::new([x, 0.0, z], normal, [x + 0.5, z + 0.5]))
            .collect(),
        indices: vec![0, 2, 1, 0, 3, 2],
        ..Default::default()
    };
    b.scene.meshes.push(quad([0.0, -1.0, 0.0]));
    b.scene.meshes.push(quad([0.0, 0.0, 0.0]));
    let m = b.material(Material::diffuse(Vec3::new(0.8, 0.7, 0.3)));
    for (mesh, x) in [(1usize, -2.0), (2, 2.0)] {
        let t = DMat4::from_translation(DVec3::new(x, 0.5, 0.0)) * DMat4::from_scale(DVec3::splat(3.0));
        b.scene.objects.push(Object { mesh, material: m, transform: t, layer: 0 });
    }
    b.point(DVec3::new(-2.0, 1.5, 0.0), Vec3::ONE, 3.0, 4.0);
    b.point(DVec3::new(2.0, 1.5, 0.0), Vec3::new(1.0, 0.5, 0.2), 3.0, 4.0);
    b.point(DVec3::new(0.0, 1.0, 3.0), Vec3::new(0.2, 0.5, 1.0), 3.0, 4.0);
    b.scene
}

fn spot_extremes() -> Scene {
    let mut b = room("spot-extremes", Camera::looking_at(DVec3::new(0.0, 5.0, 9.0), DVec3::new(0.0, 0.0, -1.0)));
    for (x, outer, inner) in [(-3.0, 0.0f32, 0.0f32), (3.0, 89.0, 80.0), (0.0, 0.5, 0.5)] {
        b.scene.lights_mut().push(Light::Spot(SpotLight {
            position: DVec3::new(x, 3.0, 0.0),
            direction: Vec3::new(0.0, -1.0, -0.2).normalize(),
            color: Vec3::new(1.0, 0.9, 0.7),
            intensity: 5.0,
            radius: 8.0,
            inner_angle: inner.to_radians(),
            outer_angle: outer.to_radians(),
            cast_shadows: true,
            cookie: None,
            mask: crate::scene::ALL_LAYERS,
        }));
    }
    b.scene
}

fn coincident() -> Scene {
    let mut b = room("coincident", Camera::looking_at(DVec3::new(0.0, 3.0, 7.0), DVec3::new(0.0, 1.0, -3.0)));
    // The wall's front face is the plane z = -5: this light's sphere just touches it.
    b.point(DVec3::new(-2.0, 2.0, -2.0), Vec3::new(1.0, 0.7, 0.4), 4.0, 3.0);
    // A light sitting on the floor's top face with a box around it.
    let m = b.material(Material::diffuse(Vec3::new(0.4, 0.6, 0.4)));
    b.boxed(DVec3::new(1.0, 0.0, -2.0), DVec3::new(3.0, 1.5, 0.0), m);
    b.point(DVec3::new(2.0, 0.75, -1.0), Vec3::new(0.4, 0.7, 1.0), 4.0, 2.0);
    b.point(DVec3::new(0.0, 1.0, 1.0), Vec3::ONE, 2.0, 5.0);
    b.scene
}

/// A street between two rows of buildings, seen from eye height, with the camera standing among
/// `n` point lights: the first quarter hang around the camera (many of their volumes hold it or
/// cross the near plane), the rest line the street ahead.
fn street(n: usize) -> Scene {
    let camera = Camera { far: 200.0, ..Camera::looking_at(DVec3::new(0.0, 1.7, 0.0), DVec3::new(0.3, 1.2, -40.0)) };
    let mut b = Builder::new("street", camera);
    b.scene.ambient = Vec3::splat(0.03);
    let road = b.material(Material {
        diffuse: Vec3::splat(0.35),
        specular_level: 0.4,
        specular_exponent: 24.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-40.0, -1.0, -130.0), DVec3::new(40.0, 0.0, 30.0), road);
    // Pavements, then blocks of buildings with alleys between them.
    let kerb = b.material(Material::diffuse(Vec3::new(0.55, 0.53, 0.5)));
    for side in [-1.0, 1.0] {
        let (x0, x1) = if side < 0.0 { (-9.0, -5.0) } else { (5.0, 9.0) };
        b.boxed(DVec3::new(x0, 0.0, -130.0), DVec3::new(x1, 0.15, 30.0), kerb);
    }
    for i in 0..28u64 {
        let side = if i % 2 == 0 { -1.0 } else { 1.0 };
        let z1 = 26.0 - (i / 2) as f64 * 11.0;
        let z0 = z1 - 8.0 - unit(31, i) * 2.0;
        let h = 6.0 + unit(32, i) * 18.0;
        let depth = 8.0 + unit(33, i) * 6.0;
        let (x0, x1) = if side < 0.0 { (-9.0 - depth, -9.0) } else { (9.0, 9.0 + depth) };
        let m = b.material(Material {
            diffuse: hue(unit(34, i) as f32) * 0.25 + Vec3::splat(0.45),
            specular_level: unit(35, i) as f32 * 0.5,
            specular_exponent: 8.0 + unit(36, i) as f32 * 60.0,
            emissive: Vec3::ZERO,
            ..Material::default()
        });
        b.boxed(DVec3::new(x0, 0.0, z0), DVec3::new(x1, h, z1), m);
    }
    // Parked cars and kiosks along the kerbs.
    for i in 0..16u64 {
        let x = if i % 2 == 0 { -4.0 } else { 3.0 } + unit(41, i) * 0.6;
        let z = 6.0 - unit(42, i) * 110.0;
        let m = b.material(Material {
            diffuse: hue(unit(43, i) as f32) * 0.6 + Vec3::splat(0.2),
            specular_level: 0.7,
            specular_exponent: 90.0,
            emissive: Vec3::ZERO,
            ..Material::default()
        });
        b.boxed(DVec3::new(x, 0.0, z - 2.0), DVec3::new(x + 1.0, 1.4, z + 2.0), m);
    }
    let eye = b.scene.camera.position;
    for i in 0..n as u64 {
        let color = hue(unit(51, i) as f32);
        let intensity = 0.6 + unit(52, i) as f32 * 0.8;
        if i < (n as u64).div_ceil(4) {
            // Around the camera, in every direction, 1 to 6 units away, radius 3 to 7.
            let a = unit(53, i) * std::f64::consts::TAU;
            let d = 1.0 + unit(54, i) * 5.0;
            let y = 0.4 + unit(55, i) * 4.0;
            let pos = DVec3::new(eye.x + d * a.cos(), y, eye.z + d * a.sin());
            b.point(pos, color, intensity, 3.0 + unit(56, i) as f32 * 4.0);
        } else {
            // Down the street ahead, over the road and the pavements.
            let x = (unit(57, i) - 0.5) * 16.0;
            let z = 4.0 - unit(58, i) * 100.0;
            let y = 0.4 + unit(59, i) * 5.0;
            b.point(DVec3::new(x, y, z), color, intensity, 2.5 + unit(60, i) as f32 * 4.5);
        }
    }
    b.scene
}

/// Railings in front of a far wall: the depth discontinuity inside a tile that per-tile lists
/// cannot separate (Olsson et al. 2012's case for clusters). Vertical bars 0.03 wide every
/// 0.12 units, 4 units from the camera and taller than the view there, are 5 pixels wide every
/// 19 at 1280x720 (60° vertical field of view: 156 pixels a unit at that distance), so nearly
/// every 16-pixel tile holds a bar and, behind it, the wall 42 units away or the floor. Lights at even indices hang among the bars (range
/// 0.5–0.9), those at odd ones before the wall (range 2–4): a tile's depth bounds span both
/// groups, while a cluster or z-bin at a pixel's depth holds only the lights near that depth.
fn railings(n: usize) -> Scene {
    let camera = Camera { far: 100.0, ..Camera::looking_at(DVec3::new(0.0, 1.4, 2.0), DVec3::new(0.0, 1.4, -40.0)) };
    let mut b = Builder::new("railings", camera);
    b.scene.ambient = Vec3::splat(0.03);
    let floor = b.material(Material::diffuse(Vec3::splat(0.45)));
    b.boxed(DVec3::new(-60.0, -1.0, -45.0), DVec3::new(60.0, 0.0, 4.0), floor);
    let wall = b.material(Material {
        diffuse: Vec3::new(0.6, 0.58, 0.55),
        specular_level: 0.3,
        specular_exponent: 24.0,
        ..Material::default()
    });
    b.boxed(DVec3::new(-60.0, 0.0, -41.0), DVec3::new(60.0, 40.0, -40.0), wall);
    let metal = b.material(Material {
        diffuse: Vec3::new(0.35, 0.36, 0.4),
        specular_level: 0.8,
        specular_exponent: 64.0,
        ..Material::default()
    });
    let (z0, z1) = (-2.015, -1.985);
    for k in -45..=45 {
        let x = k as f64 * 0.12;
        b.boxed(DVec3::new(x - 0.015, 0.0, z0), DVec3::new(x + 0.015, 4.2, z1), metal);
    }
    for y in [1.2, 2.6, 4.0] {
        b.boxed(DVec3::new(-5.5, y, z0 - 0.01), DVec3::new(5.5, y + 0.06, z1 + 0.01), metal);
    }
    for i in 0..n as u64 {
        let colour = hue(unit(81, i) as f32) * 0.8 + Vec3::splat(0.2);
        if i % 2 == 0 {
            let p = DVec3::new((unit(82, i) - 0.5) * 9.0, 0.2 + unit(83, i) * 3.8, -2.0 + (unit(84, i) - 0.5) * 1.2);
            b.point(p, colour, 0.6, 0.5 + 0.4 * unit(85, i) as f32);
        } else {
            let p = DVec3::new((unit(86, i) - 0.5) * 84.0, 0.5 + unit(87, i) * 24.0, -39.5 + unit(88, i) * 2.0);
            b.point(p, colour, 1.5, 2.0 + 2.0 * unit(89, i) as f32);
        }
    }
    b.scene
}

/// Radius of `sphere-wall`'s sphere, the radius its lights sit at and their range.
pub const SPHERE_WALL: (f64, f64, f32) = (50.0, 49.0, 5.0);

/// The camera at the centre of an inward-facing sphere of radius 50 (a UV sphere of 64 x 32
/// quads, 3,968 triangles, normals pointing inward), lit by `n` point lights of range 5 spread
/// evenly over the sphere of radius 49 (a Fibonacci sphere), each reaching a disc of the wall.
/// Every light is the same distance from the eye, about a third of them in the view.
pub fn sphere_wall(n: usize) -> Scene {
    let (wall, at, range) = SPHERE_WALL;
    lights_on_a_sphere("sphere-wall", n, (wall, at, range), (64, 32), |i| 0.25 + 0.25 * unit(72, i as u64) as f32)
}

/// Bevy's `many_lights` stress test as a scene: `n` (100,000 there) point lights of range 0.3
/// on a sphere of radius 50 seen from its centre, each lighting a disc of 0.28 to 0.3 of the
/// wall. They sit 0.1 inside the sphere, in front of the mesh's flat faces: a quad of 128 x 64
/// cuts at most 50 (1 - cos(pi/128) cos(pi/128)) = 0.03 inside it at its centre (with 64 x 32,
/// 0.12, and the lights at the quads' centres were behind the wall). Bevy's example opens a
/// 1920x1080 window (its scale factor held at 1) with a vertical field of view of 45 degrees,
/// as this camera has.
pub fn many_lights(n: usize) -> Scene {
    let mut s = lights_on_a_sphere("many-lights", n, (50.0, 49.9, 0.3), (128, 64), |_| 2.0);
    s.camera.fov_y = 45f64.to_radians();
    s
}

/// An inward-facing UV sphere of radius `wall` (`segments` x `rings` quads) around a camera at
/// its centre, lit by `n` point lights of range `range` on a Fibonacci sphere of radius `at`,
/// light i of intensity `intensity(i)`.
fn lights_on_a_sphere(
    name: &str,
    n: usize,
    (wall, at, range): (f64, f64, f32),
    (segments, rings): (u32, u32),
    intensity: impl Fn(usize) -> f32,
) -> Scene {
    let camera = Camera { far: 200.0, ..Camera::looking_at(DVec3::ZERO, DVec3::new(0.0, 0.0, -1.0)) };
    let mut b = Builder::new(name, camera);
    b.scene.ambient = Vec3::splat(0.02);
    let mut mesh = Mesh { name: "sphere wall".into(), ..Default::default() };
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let p = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            let uv = [s as f32 / segments as f32, r as f32 / rings as f32];
            mesh.vertices.push(Vertex::new(p.into(), (-p).into(), uv));
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b2, c, d) = (r * row + s, r * row + s + 1, (r + 1) * row + s, (r + 1) * row + s + 1);
            // Counter-clockwise seen from the centre (inward-facing); the poles' degenerate
            // triangles are left out.
            if r != 0 {
                mesh.indices.extend([a, c, b2]);
            }
            if r + 1 != rings {
                mesh.indices.extend([b2, c, d]);
            }
        }
    }
    b.scene.meshes.push(mesh);
    let m = b.material(Material {
        diffuse: Vec3::splat(0.6),
        specular_level: 0.3,
        specular_exponent: 32.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    let mesh = b.scene.meshes.len() - 1;
    b.scene.objects.push(Object { mesh, material: m, transform: DMat4::from_scale(DVec3::splat(wall)), layer: 0 });
    // Fibonacci sphere: evenly spread directions, the same for every count's first lights only
    // in distribution (the spiral depends on n).
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    for i in 0..n {
        let y = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
        let ring = (1.0 - y * y).max(0.0).sqrt();
        let a = golden * i as f64;
        let dir = DVec3::new(ring * a.cos(), y, ring * a.sin());
        b.point(dir * at, hue(unit(71, i as u64) as f32), intensity(i), range);
    }
    b.scene
}

/// A unit sphere facing outward (`segments` around, `rings` from pole to pole).
fn sphere_mesh(segments: u32, rings: u32) -> Mesh {
    let mut mesh = Mesh { name: "sphere".into(), ..Default::default() };
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let p = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            mesh.vertices.push(Vertex::new(p.into(), p.into(), [s as f32 / segments as f32, r as f32 / rings as f32]));
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let (a, b, c, d) = (r * row + s, r * row + s + 1, (r + 1) * row + s, (r + 1) * row + s + 1);
            // Counter-clockwise seen from outside; the poles' degenerate triangles left out.
            if r != 0 {
                mesh.indices.extend([a, b, c]);
            }
            if r + 1 != rings {
                mesh.indices.extend([b, d, c]);
            }
        }
    }
    mesh
}

/// Seed 002's material IDs side by side: six spheres, each on a box of the same model, in
/// `Brdf::ALL` order from left to right (blinn-phong, lambert, metal, toon, unlit, phong), on a
/// blinn-phong floor, lit by a sun, ambient, eight coloured point lights and a spot; a
/// translucent toon pane in front of the lambert and metal spheres (the forward pass).
pub fn materials() -> Scene {
    let camera = Camera { far: 120.0, ..Camera::looking_at(DVec3::new(0.0, 2.6, 9.5), DVec3::new(0.0, 0.9, 0.0)) };
    let mut b = Builder::new("materials", camera);
    b.scene.sun = Some(Sun { intensity: 0.6, ..Sun::fill_sun() });
    b.scene.ambient = Vec3::new(0.05, 0.05, 0.06);
    b.scene.meshes.push(sphere_mesh(48, 24));
    let sphere = b.scene.meshes.len() - 1;
    let floor = b.material(Material {
        diffuse: Vec3::splat(0.45),
        specular_level: 0.4,
        specular_exponent: 24.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-20.0, -1.0, -15.0), DVec3::new(20.0, 0.0, 15.0), floor);
    let (gold, _, _) = Material::metal_from_pbr(Vec3::new(1.0, 0.71, 0.29), 1.0, 0.35, DIELECTRIC_F0);
    let models = [
        (Brdf::BlinnPhong, Vec3::new(0.75, 0.18, 0.15), 1.2, 64.0),
        (Brdf::Lambert, Vec3::new(0.2, 0.45, 0.8), 0.0, 1.0),
        // Gold from glTF metallic-roughness (base (1, 0.71, 0.29), metallic 1, roughness 0.35).
        (Brdf::Metal, gold, max_specular_level(96.0), 96.0),
        (Brdf::Toon, Vec3::new(0.85, 0.5, 0.75), 1.0, 48.0),
        (Brdf::Unlit, Vec3::new(0.3, 0.75, 0.35), 0.0, 1.0),
        (Brdf::Phong, Vec3::new(0.55, 0.5, 0.8), 0.8, 32.0),
    ];
    for (k, (brdf, color, level, exponent)) in models.into_iter().enumerate() {
        let m = b.material(Material {
            diffuse: color,
            specular_level: level,
            specular_exponent: exponent,
            emissive: Vec3::ZERO,
            brdf,
            ..Material::default()
        });
        let x = (k as f64 - 2.5) * 2.9;
        b.boxed(DVec3::new(x - 1.1, 0.0, -2.6), DVec3::new(x + 1.1, 0.8, -1.4), m);
        let t = DMat4::from_translation(DVec3::new(x, 1.3, 0.0)) * DMat4::from_scale(DVec3::splat(1.3));
        b.scene.objects.push(Object { mesh: sphere, material: m, transform: t, layer: 0 });
    }
    let pane = b.material(Material {
        diffuse: Vec3::new(0.9, 0.85, 0.5),
        specular_level: 1.0,
        specular_exponent: 64.0,
        emissive: Vec3::ZERO,
        alpha: 0.35,
        alpha_mode: AlphaMode::Blend,
        brdf: Brdf::Toon,
        ..Material::default()
    });
    b.boxed(DVec3::new(-5.9, 0.0, 2.4), DVec3::new(0.0, 1.6, 2.5), pane);
    for i in 0..8u64 {
        let x = -9.0 + 18.0 * (i as f64 + 0.5) / 8.0;
        let z = if i % 2 == 0 { 3.0 } else { -3.5 };
        b.point(DVec3::new(x, 2.6 + unit(31, i) * 1.5, z), hue(i as f32 / 8.0) * 0.7 + Vec3::splat(0.3), 1.6, 6.0);
    }
    b.scene.lights_mut().push(Light::Spot(SpotLight {
        position: DVec3::new(0.0, 7.0, 3.0),
        direction: Vec3::new(0.0, -1.0, -0.4).normalize(),
        color: Vec3::new(1.0, 0.95, 0.85),
        intensity: 1.5,
        radius: 14.0,
        inner_angle: 25f32.to_radians(),
        outer_angle: 40f32.to_radians(),
        cast_shadows: true,
        cookie: None,
        mask: crate::scene::ALL_LAYERS,
    }));
    b.scene
}

/// Seed 004's cookies and light culling masks. A floor and a wall (layer 0); a red box on
/// layer 1 and a blue sphere on layer 2 with a blended pane on layer 2 in front of it (so the
/// forward pass reads layers from the object record); a spot throwing the `window` cookie on
/// the wall (every layer); a warm point light with the `flashlight` cube cookie lighting layers
/// 0 and 1 only (not the sphere) and a cool one lighting layers 0 and 2 only (not the box).
pub fn cookies() -> Scene {
    let camera = Camera { far: 80.0, ..Camera::looking_at(DVec3::new(0.5, 3.2, 9.0), DVec3::new(0.0, 1.4, -1.0)) };
    let mut b = Builder::new("cookies", camera);
    b.scene.ambient = Vec3::splat(0.04);
    b.scene.meshes.push(sphere_mesh(32, 16));
    let sphere = b.scene.meshes.len() - 1;
    let floor = b.material(Material {
        diffuse: Vec3::splat(0.55),
        specular_level: 0.3,
        specular_exponent: 24.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-10.0, -1.0, -6.0), DVec3::new(10.0, 0.0, 8.0), floor);
    let wall = b.material(Material::diffuse(Vec3::new(0.7, 0.68, 0.62)));
    b.boxed(DVec3::new(-10.0, 0.0, -6.0), DVec3::new(10.0, 7.0, -5.0), wall);
    let red = b.material(Material {
        diffuse: Vec3::new(0.8, 0.25, 0.2),
        specular_level: 0.5,
        specular_exponent: 48.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-3.2, 0.0, -0.8), DVec3::new(-1.4, 1.8, 1.0), red);
    b.scene.objects.last_mut().expect("the box").layer = 1;
    let blue = b.material(Material {
        diffuse: Vec3::new(0.2, 0.35, 0.85),
        specular_level: 0.6,
        specular_exponent: 64.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    let t = DMat4::from_translation(DVec3::new(2.3, 1.1, 0.0)) * DMat4::from_scale(DVec3::splat(1.1));
    b.scene.objects.push(Object { mesh: sphere, material: blue, transform: t, layer: 2 });
    let pane = b.material(Material {
        diffuse: Vec3::new(0.85, 0.9, 0.95),
        specular_level: 0.8,
        specular_exponent: 64.0,
        emissive: Vec3::ZERO,
        alpha: 0.3,
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    });
    b.boxed(DVec3::new(1.0, 0.0, 2.2), DVec3::new(3.6, 1.4, 2.3), pane);
    b.scene.objects.last_mut().expect("the pane").layer = 2;
    b.scene.lights_mut().push(Light::Spot(SpotLight {
        position: DVec3::new(0.0, 4.0, 3.0),
        direction: (DVec3::new(0.0, 3.5, -5.0) - DVec3::new(0.0, 4.0, 3.0)).normalize().as_vec3(),
        color: Vec3::new(1.0, 0.95, 0.85),
        intensity: 5.0,
        radius: 14.0,
        inner_angle: 20f32.to_radians(),
        outer_angle: 24f32.to_radians(),
        cast_shadows: true,
        cookie: None,
        mask: crate::scene::ALL_LAYERS,
    }));
    b.point(DVec3::new(-1.0, 3.0, 1.5), Vec3::new(1.0, 0.75, 0.45), 4.0, 7.0);
    b.scene.lights_mut().last_mut().expect("the warm light").set_mask(0b011);
    b.point(DVec3::new(1.5, 2.5, 2.5), Vec3::new(0.45, 0.7, 1.0), 3.0, 6.0);
    b.scene.lights_mut().last_mut().expect("the cool light").set_mask(0b101);
    // Built-in names always resolve.
    let _ = b.scene.set_light_cookie(0, Some("window"));
    let _ = b.scene.set_light_cookie(1, Some("flashlight"));
    b.scene
}

/// The shadows' scene: boxes, a pillar and a thin wall on a floor under the sun, a spot light and
/// a point light, so each kind's shadow shows (`--shadows all`).
pub fn shadows() -> Scene {
    let camera = Camera::looking_at(DVec3::new(6.0, 6.5, 11.0), DVec3::new(0.0, 0.5, 0.0));
    let mut b = Builder::new("shadows", camera);
    b.scene.ambient = Vec3::splat(0.03);
    b.scene.sun = Some(Sun {
        direction: Vec3::new(0.6, -0.55, 0.6).normalize(),
        color: Vec3::new(1.0, 0.95, 0.85),
        intensity: 0.35,
    });
    let floor = b.material(Material {
        diffuse: Vec3::new(0.6, 0.58, 0.55),
        specular_level: 0.3,
        specular_exponent: 32.0,
        emissive: Vec3::ZERO,
        ..Material::default()
    });
    b.boxed(DVec3::new(-10.0, -1.0, -10.0), DVec3::new(10.0, 0.0, 10.0), floor);
    for (i, (x, z, s, h)) in [(-2.0, 0.0, 0.8, 1.6), (1.0, -1.5, 0.5, 3.0), (2.0, 2.0, 0.6, 1.0)].iter().enumerate() {
        let m = b.material(Material::diffuse(hue(i as f32 * 0.3) * 0.6 + Vec3::splat(0.2)));
        b.boxed(DVec3::new(x - s, 0.0, z - s), DVec3::new(x + s, *h, z + s), m);
    }
    // A thin wall (5 cm) between the point light and the boxes on its far side.
    let wall = b.material(Material::diffuse(Vec3::new(0.55, 0.6, 0.7)));
    b.boxed(DVec3::new(-4.5, 0.0, -3.0), DVec3::new(-4.45, 2.0, 1.0), wall);
    b.boxed(DVec3::new(-6.0, 0.0, -0.5), DVec3::new(-5.4, 0.9, 0.1), wall);
    // Behind the objects as the camera sees them: their shadows fall towards it.
    let spot = DVec3::new(-1.0, 5.5, -5.0);
    b.scene.lights_mut().push(Light::Spot(SpotLight {
        position: spot,
        direction: (DVec3::new(0.5, 0.0, 0.5) - spot).normalize().as_vec3(),
        color: Vec3::new(1.0, 0.9, 0.75),
        intensity: 5.0,
        radius: 14.0,
        inner_angle: 30f32.to_radians(),
        outer_angle: 40f32.to_radians(),
        cast_shadows: true,
        cookie: None,
        mask: crate::scene::ALL_LAYERS,
    }));
    b.point(DVec3::new(-3.5, 1.2, -1.0), Vec3::new(0.5, 0.7, 1.0), 3.0, 6.0);
    b.scene
}

/// `courtyard` before its bake: a 60-unit floor receding from the camera, boxes and walls along
/// it, the sun low enough to cast long shadows, an ambient bright enough to show its occlusion,
/// and two point lights near the camera (realtime everywhere: a bake holds only ambient and sun).
pub fn courtyard_unbaked() -> Scene {
    let camera = Camera { far: 200.0, ..Camera::looking_at(DVec3::new(0.0, 4.0, 24.0), DVec3::new(0.0, 0.0, -10.0)) };
    let mut b = Builder::new("courtyard", camera);
    b.scene.ambient = Vec3::new(0.16, 0.17, 0.2);
    b.scene.sun = Some(Sun {
        direction: Vec3::new(0.5, -0.6, 0.35).normalize(),
        color: Vec3::new(1.0, 0.93, 0.8),
        intensity: 0.5,
    });
    let floor = b.material(Material::diffuse(Vec3::new(0.62, 0.6, 0.56)));
    b.boxed(DVec3::new(-12.0, -1.0, -36.0), DVec3::new(12.0, 0.0, 28.0), floor);
    let wall = b.material(Material::diffuse(Vec3::new(0.55, 0.5, 0.45)));
    b.boxed(DVec3::new(-12.0, 0.0, -36.0), DVec3::new(-11.0, 4.0, 28.0), wall);
    b.boxed(DVec3::new(11.0, 0.0, -36.0), DVec3::new(12.0, 4.0, 28.0), wall);
    for i in 0..8u64 {
        let m = b.material(Material::diffuse(hue(i as f32 * 0.13) * 0.5 + Vec3::splat(0.3)));
        let z = 16.0 - i as f64 * 7.0;
        let x = if i % 2 == 0 { -5.0 } else { 4.0 } + (unit(41, i) - 0.5) * 2.0;
        let s = 0.8 + unit(42, i);
        b.boxed(DVec3::new(x - s, 0.0, z - s), DVec3::new(x + s, 1.0 + 2.5 * unit(43, i), z + s), m);
    }
    b.point(DVec3::new(-2.0, 1.5, 16.0), Vec3::new(1.0, 0.6, 0.3), 4.0, 7.0);
    b.point(DVec3::new(3.0, 1.2, 10.0), Vec3::new(0.3, 0.6, 1.0), 4.0, 7.0);
    b.scene
}

/// The bake options `courtyard` is baked with.
pub const COURTYARD_BAKE: crate::scene::lightmap::BakeOptions =
    crate::scene::lightmap::BakeOptions { texels: 32, rays: 64, occlusion_distance: 4.0 };

/// Seed 004's lightmapped scene: [`courtyard_unbaked`] with every object's lightmap, baked once
/// per process ([`COURTYARD_BAKE`]; `lampshade bake courtyard` writes the same maps).
pub fn courtyard() -> Scene {
    static BAKED: std::sync::OnceLock<crate::scene::lightmap::Baked> = std::sync::OnceLock::new();
    let mut scene = courtyard_unbaked();
    let baked = BAKED.get_or_init(|| {
        crate::scene::lightmap::bake(&scene, &COURTYARD_BAKE, |_, _| {}).unwrap_or_else(|e| {
            // The scene is built in code and valid: a failure here is a bug, shown as an unbaked
            // scene rather than a crash.
            log::error!("courtyard: the bake failed ({e:#}); shown without lightmaps");
            crate::scene::lightmap::Baked {
                scene: "courtyard".into(),
                options: COURTYARD_BAKE,
                objects: Vec::new(),
                skipped: Vec::new(),
            }
        })
    });
    crate::scene::lightmap::apply(&mut scene, baked);
    scene
}
