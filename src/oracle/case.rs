//! The oracle's cases: a scene, a camera and the settings that change what the culling sees,
//! written down as plain data (so a failing case is a file the suite replays), and the seeded
//! generator that draws them from the space the culling bugs of the field live in.

use crate::renderer::{AccumFormat, DepthFormat, DepthRead, LayoutChoice, Settings, ShadowMode};
use crate::scene::{Camera, Light, Material, Mesh, Object, PointLight, Scene, SpotLight, ALL_LAYERS};
use glam::{DMat4, DQuat, DVec3, Vec3};
use serde::{Deserialize, Serialize};

/// One box of a case: a unit cube scaled, turned about +Y and moved. A zero size on an axis is
/// a degenerate box (zero-area faces), a tiny one a thin wall.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct BoxSpec {
    pub center: [f64; 3],
    pub size: [f64; 3],
    /// Radians about +Y.
    pub yaw: f64,
    /// Culling layer (seed 004's masks), 0..=31.
    #[serde(default)]
    pub layer: u8,
    pub color: [f32; 3],
    /// Blinn-Phong specular level (0: diffuse only).
    #[serde(default)]
    pub specular: f32,
}

/// The settings a case varies: what changes the culling's inputs (the G-buffer's layout and
/// precision, the depth buffer, the accumulation) and the lookups that zero light (shadows).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct CaseSettings {
    pub layout: LayoutChoice,
    pub depth_format: DepthFormat,
    pub reversed_z: bool,
    pub accumulation: AccumFormat,
    pub shadows: ShadowMode,
    /// The clustered grid, when not the default: (tile pixels, slices, first slice depth; 0 for
    /// exponential slices over the lights' depths). Engines' grids (`renderer::caps`) change
    /// the lists, never the light.
    #[serde(default)]
    pub grid: Option<(u32, u32, f32)>,
    /// Light volumes drawn with depth clamp (`Settings::depth_clamp`, where the adapter has
    /// it); off, as on an adapter without `DEPTH_CLIP_CONTROL`, volumes crossing the far plane
    /// are drawn full-screen and the near plane clips.
    #[serde(default = "depth_clamp_on")]
    pub depth_clamp: bool,
    /// Where the lights read depth: the G-buffer's copy, or the depth buffer itself (24-bit
    /// included), where the culling mode lets them (`key::depth_read_refusal`).
    #[serde(default)]
    pub depth_read: DepthRead,
}

fn depth_clamp_on() -> bool {
    true
}

impl CaseSettings {
    /// The frame's settings: the case's, nothing counted or timed.
    pub fn settings(&self) -> Settings {
        Settings {
            layout: self.layout,
            depth_format: self.depth_format,
            reversed_z: self.reversed_z,
            accumulation: self.accumulation,
            shadows: self.shadows,
            cluster_tile: self.grid.map_or(0, |g| g.0),
            cluster_slices: self.grid.map_or(0, |g| g.1),
            first_slice_depth: self.grid.map_or(0.0, |g| g.2),
            count_fragments: false,
            count_ideal: false,
            timestamps: false,
            depth_clamp: self.depth_clamp,
            depth_read: self.depth_read,
            ..Settings::default()
        }
    }
}

/// A case: everything the oracle renders, as data.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Case {
    /// Where it came from: the generator's seed and the case's index (a shrunk case keeps its
    /// origin's).
    pub seed: u64,
    pub index: u64,
    /// What the generator aimed at, in words ("camera inside 3 volumes", ...).
    #[serde(default)]
    pub aims: Vec<String>,
    pub width: u32,
    pub height: u32,
    pub camera: Camera,
    /// Added to every position (camera, boxes, lights): far-from-origin coordinates.
    #[serde(default)]
    pub offset: [f64; 3],
    pub boxes: Vec<BoxSpec>,
    /// The lights; a light's `cookie` indexes [`Case::cookies`].
    pub lights: Vec<Light>,
    /// Built-in cookie names (`window`, `flashlight`): a cube for a point light, 2D for a spot.
    #[serde(default)]
    pub cookies: Vec<String>,
    pub settings: CaseSettings,
}

impl Case {
    /// The scene the case describes; an error for a cookie name that is not built in.
    pub fn scene(&self) -> Result<Scene, String> {
        let offset = DVec3::from_array(self.offset);
        let mut camera = self.camera;
        camera.position += offset;
        let mut scene =
            Scene { meshes: vec![Mesh::cube()], ..Scene::new(&format!("oracle-{}-{}", self.seed, self.index), camera) };
        scene.sun = None;
        scene.ambient = Vec3::splat(0.02);
        for b in &self.boxes {
            scene.materials.push(Material {
                diffuse: Vec3::from_array(b.color),
                specular_level: b.specular,
                specular_exponent: 32.0,
                ..Material::diffuse(Vec3::from_array(b.color))
            });
            let transform = DMat4::from_scale_rotation_translation(
                DVec3::from_array(b.size),
                DQuat::from_rotation_y(b.yaw),
                DVec3::from_array(b.center) + offset,
            );
            let material = scene.materials.len() - 1;
            scene.objects.push(Object { mesh: 0, material, transform, layer: b.layer.min(31) });
        }
        scene.set_lights(self.lights.clone());
        for l in scene.lights_mut() {
            match l {
                Light::Point(p) => p.position += offset,
                Light::Spot(s) => s.position += offset,
            }
        }
        for i in 0..scene.lights.len() {
            let name = scene.lights[i].cookie().map(|k| self.cookies.get(k as usize).cloned());
            let name = match name {
                Some(Some(n)) => Some(n),
                Some(None) => {
                    return Err(format!("light {i}: no cookie {:?} among {:?}", scene.lights[i].cookie(), self.cookies))
                }
                None => None,
            };
            scene.set_light_cookie(i, name.as_deref())?;
        }
        Ok(scene)
    }
}

/// SplitMix64 (Steele, Lea and Flood, "Fast splittable pseudorandom number generators"): the
/// generator's stream, one per case, so case k of seed s is the same on every machine.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64, index: u64) -> Self {
        Self(seed ^ index.wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(17))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Log-uniform in [lo, hi] (both > 0).
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }

    pub fn below(&mut self, n: usize) -> usize {
        (self.unit() * n as f64) as usize % n.max(1)
    }

    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    pub fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len())]
    }

    /// A direction uniform on the sphere.
    pub fn direction(&mut self) -> DVec3 {
        let z = self.range(-1.0, 1.0);
        let a = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * a.cos(), z, r * a.sin())
    }
}

/// Consecutive cases that share their settings (see [`generate`]).
pub const SETTINGS_BLOCK: u64 = 50;

/// How large the generator draws cases.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    pub width: u32,
    pub height: u32,
    /// The most lights a case holds (the counts are log-distributed from `min_lights`).
    pub max_lights: usize,
    /// The fewest: 1 in the default stream; 65,537 in the family past the tiled pass's
    /// 65,536-light batch (`tiles::GPU_LIST_MAX_LIGHTS`).
    pub min_lights: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self { width: 64, height: 36, max_lights: 256, min_lights: 1 }
    }
}

/// Case `index` of stream `seed`. It draws, each with its own chance:
/// - the camera: pitch from -90 to 90 degrees (an eighth straight down or up), any yaw, fields
///   of view from 0.5 to 170 degrees, near planes from 1e-4 to 10 and far planes from 10 to
///   10^6 near planes away;
/// - boxes: a floor and walls (planes at the camera's depth ranges), blocks, thin walls (1e-3
///   thick) and degenerate boxes (one size 0), on up to 4 layers;
/// - lights: 1 to `max_lights` (log-distributed), some stacked at one point; ranges from 1e-4
///   to 10^4; points and spots with half-angles from 0 to 89.9 degrees; placed at random, on a
///   box's face, just in front of or behind it, at the camera (which then stands inside the
///   volume), behind the camera; masks that leave layers out; built-in cookies;
/// - far from the origin (everything moved 10^6);
/// - the G-buffer layout, the depth format, reversed Z, the accumulation format (all five; the
///   8-bit and 11-bit ones less often, their bounds being coarser than many lights) and shadows,
///   shared by [`SETTINGS_BLOCK`] cases in a row;
/// - half the cases, a clustered grid as an engine lays it out (tile, slices, a first slice
///   from the eye to a depth, as Bevy's);
/// - a quarter of the cases, lights reaching a few depth steps behind a surface ([`rim_lights`]).
pub fn generate(seed: u64, index: u64, limits: Limits) -> Case {
    let mut r = Rng::new(seed, index);
    let mut aims = Vec::new();
    let settings = case_settings(seed, index);
    // Masks that leave some layers out need a layout with a channel for the layer (the others
    // refuse such scenes, with a clear error, which a test covers).
    let masks = matches!(settings.layout, LayoutChoice::Compact | LayoutChoice::Fit | LayoutChoice::Reference);
    // The world: a scale so cases are not all room-sized.
    let scale = r.log(0.01, 100.0);
    let mut camera = random_camera(&mut r, scale, &mut aims);
    let (boxes, layers) = random_boxes(&mut r, &camera, scale, masks, &mut aims);
    // The 8-bit formats saturate at 1 (linear) and about 8 (log): their lights are dimmer, so
    // that most pixels stay inside the range where a missed light shows.
    let dim = match settings.accumulation {
        AccumFormat::Rgba8Unorm => 0.02,
        AccumFormat::Rgba8Log => 0.1,
        _ => 1.0,
    };
    let world = World { camera: &camera, boxes: &boxes, scale, layers };
    let (mut lights, cookies) = random_lights(&mut r, &world, dim, (limits.min_lights, limits.max_lights), &mut aims);
    // From a stream of its own, so the other draws are what they were before these were: such a
    // case differs only in its near plane and its last lights.
    let mut g = Rng::new(seed ^ 0x21A5_0DE9, index);
    if g.chance(0.25) {
        let most = limits.max_lights.clamp(1, 4);
        let rim = rim_lights(&mut g, &mut camera, &boxes, (&settings, dim, most), (limits.width, limits.height));
        if !rim.is_empty() {
            aims.push(format!("{} lights poking a few depth steps behind a surface", rim.len()));
            lights.truncate(limits.max_lights.max(1).saturating_sub(rim.len()));
            lights.extend(rim);
        }
    }
    let inside = lights.iter().filter(|l| l.position().distance(camera.position) < l.radius() as f64).count();
    if inside > 0 {
        aims.push(format!("camera inside {inside} volumes"));
    }
    let offset = if r.chance(0.1) {
        aims.push("far from the origin".into());
        [1e6, 0.0, -1e6]
    } else {
        [0.0; 3]
    };
    Case {
        seed,
        index,
        aims,
        width: limits.width,
        height: limits.height,
        camera,
        offset,
        boxes,
        lights,
        cookies,
        settings,
    }
}

/// Case `index`'s settings. They come from a stream of their own, the same for
/// [`SETTINGS_BLOCK`] cases in a row: each combination compiles its own pipelines (tens of ms
/// each on lavapipe), which a block then reuses.
fn case_settings(seed: u64, index: u64) -> CaseSettings {
    let mut r = Rng::new(seed ^ 0x5E77_1465, index / SETTINGS_BLOCK);
    CaseSettings {
        layout: r.pick(&LayoutChoice::ALL),
        depth_format: r.pick(&DepthFormat::ALL),
        reversed_z: r.chance(0.5),
        // Every format; the float ones twice as often, as the 8-bit and 11-bit formats'
        // bounds are coarser than many lights (a light below its bound cannot be told
        // missed).
        accumulation: r.pick(&[
            AccumFormat::Rgba16Float,
            AccumFormat::Rgba16Float,
            AccumFormat::Rgba32Float,
            AccumFormat::Rgba32Float,
            AccumFormat::Rg11b10Ufloat,
            AccumFormat::Rgba8Log,
            AccumFormat::Rgba8Unorm,
        ]),
        shadows: r.pick(&[ShadowMode::None, ShadowMode::Spots, ShadowMode::All]),
        // From a stream of its own, per case (a grid compiles nothing), so the rest of the
        // case is what it was before grids were drawn.
        grid: {
            let mut g = Rng::new(seed ^ 0x6121_D5EE, index);
            g.chance(0.5).then(|| {
                let first = if g.chance(0.5) { g.log(1e-3, 1e3) as f32 } else { 0.0 };
                (g.pick(&[8, 16, 32, 64, 80, 128]), g.pick(&[1, 3, 24, 64]), first)
            })
        },
        // Per settings block, from a stream of its own (the rest of the case as before):
        // a quarter of the blocks draw without depth clamp.
        depth_clamp: Rng::new(seed ^ 0xDC1A_3F07, index / SETTINGS_BLOCK).chance(0.75),
        // Per settings block, from a stream of its own: half the blocks read the depth buffer.
        depth_read: match Rng::new(seed ^ 0xDE97_4EAD, index / SETTINGS_BLOCK).chance(0.5) {
            true => DepthRead::Buffer,
            false => DepthRead::Copy,
        },
    }
}

/// The camera: straight down or up now and then, fields of view from 0.5 to 170 degrees, near
/// planes from 1e-4, far planes up to 10^6 times the near.
fn random_camera(r: &mut Rng, scale: f64, aims: &mut Vec<String>) -> Camera {
    let pitch = if r.chance(0.125) {
        aims.push("camera straight down or up".to_string());
        r.pick(&[-1.0, 1.0]) * std::f64::consts::FRAC_PI_2
    } else {
        r.range(-1.0, 1.0) * std::f64::consts::FRAC_PI_2
    };
    let fov_deg = if r.chance(0.2) { r.pick(&[0.5, 1.0, 150.0, 170.0]) } else { r.range(20.0, 120.0) };
    let near = if r.chance(0.3) { r.log(1e-4, 10.0) } else { scale * r.log(1e-3, 0.1) };
    let far = near * r.log(10.0, 1e6);
    let position = DVec3::new(r.range(-1.0, 1.0), r.range(0.1, 2.0), r.range(-1.0, 1.0)) * scale;
    Camera { position, yaw: r.range(-3.2, 3.2), pitch, fov_y: fov_deg.to_radians(), near, far }
}

/// The boxes: a floor below the camera, walls ahead, blocks, thin walls, degenerate boxes, on
/// up to 4 layers where `masks` (the layout has a channel for the layer); and the layer count.
fn random_boxes(
    r: &mut Rng,
    camera: &Camera,
    scale: f64,
    masks: bool,
    aims: &mut Vec<String>,
) -> (Vec<BoxSpec>, usize) {
    let forward = camera.forward();
    let mut boxes = Vec::new();
    let grey = |r: &mut Rng| [r.range(0.2, 0.9) as f32, r.range(0.2, 0.9) as f32, r.range(0.2, 0.9) as f32];
    let layers = if masks && r.chance(0.3) { 4 } else { 1 };
    boxes.push(BoxSpec {
        center: [camera.position.x, -0.5 * scale, camera.position.z],
        size: [40.0 * scale, scale, 40.0 * scale],
        yaw: 0.0,
        layer: 0,
        color: grey(r),
        specular: r.pick(&[0.0, 0.5]) as f32,
    });
    let blocks = 1 + r.below(8);
    for _ in 0..blocks {
        let depth = r.log(camera.near.max(1e-3 * scale), 20.0 * scale);
        let side = r.range(-0.6, 0.6) * depth;
        let center = camera.position + forward * depth + camera.right() * side + DVec3::Y * r.range(-0.5, 0.5) * depth;
        let mut size = [r.log(0.05, 4.0) * scale, r.log(0.05, 4.0) * scale, r.log(0.05, 4.0) * scale];
        let kind = r.below(6);
        if kind == 0 {
            size[r.below(3)] = 1e-3 * scale;
            aims.push("a thin wall".into());
        } else if kind == 1 {
            size[r.below(3)] = 0.0;
            aims.push("a degenerate box".into());
        }
        boxes.push(BoxSpec {
            center: center.to_array(),
            size,
            yaw: r.range(0.0, 3.2),
            layer: r.below(layers) as u8,
            color: grey(r),
            specular: r.pick(&[0.0, 0.3, 1.0]) as f32,
        });
    }
    (boxes, layers)
}

/// What a case's lights are placed among: the camera, the boxes, the world's scale and how
/// many layers the boxes are on.
struct World<'a> {
    camera: &'a Camera,
    boxes: &'a [BoxSpec],
    scale: f64,
    layers: usize,
}

/// The lights (`min` to `max`, log-distributed; a share of them spots, some stacked at one
/// point, masks leaving layers out where there are layers, intensities times `dim`, and past 256
/// lights times 256 / their count, so that a crowd's sum stays inside the accumulation's range
/// where a missed light shows) and the cookies they may use.
fn random_lights(
    r: &mut Rng,
    world: &World,
    dim: f32,
    (min, max): (usize, usize),
    aims: &mut Vec<String>,
) -> (Vec<Light>, Vec<String>) {
    let max = max.max(1);
    let min = min.clamp(1, max);
    let count = (r.log(min as f64, max as f64 + 1.0) as usize).clamp(min, max);
    let dim = dim * (256.0 / count as f32).min(1.0);
    let mut lights: Vec<Light> = Vec::with_capacity(count);
    let spots = r.pick(&[0.0, 0.5, 1.0]);
    let cookies: Vec<String> = if r.chance(0.2) {
        aims.push("cookies".into());
        vec!["window".into(), "flashlight".into()]
    } else {
        Vec::new()
    };
    let range_lo = if r.chance(0.2) { 1e-4 } else { 1e-2 * world.scale };
    let forward = world.camera.forward();
    while lights.len() < count {
        let radius = r.log(range_lo, 1e4_f64.min(100.0 * world.scale.max(1.0))) as f32;
        let position = light_position(r, world);
        let color = Vec3::new(r.range(0.2, 1.0) as f32, r.range(0.2, 1.0) as f32, r.range(0.2, 1.0) as f32);
        let intensity = r.log(0.1, 20.0) as f32 * dim;
        let layers = world.layers;
        let mask = if layers > 1 && r.chance(0.5) { (r.next_u64() as u32) | 1 << r.below(4) } else { ALL_LAYERS };
        let light = if r.chance(spots) {
            let outer = if r.chance(0.2) { r.pick(&[0.0, 89.9]) } else { r.range(0.5, 89.9) };
            let inner = outer * r.range(0.0, 1.0);
            let direction = if r.chance(0.3) { (-forward).as_vec3() } else { r.direction().as_vec3() };
            Light::Spot(SpotLight {
                position,
                direction,
                color,
                intensity,
                radius,
                inner_angle: (inner as f32).to_radians(),
                outer_angle: (outer as f32).to_radians(),
                cast_shadows: true,
                cookie: None,
                mask,
            })
        } else {
            Light::Point(PointLight { position, color, intensity, radius, cookie: None, mask, cast_shadows: true })
        };
        let mut light = light;
        if !cookies.is_empty() && r.chance(0.5) {
            light.set_cookie(Some(r.below(cookies.len()) as u32));
        }
        // Some lights stacked at one point.
        let copies = if r.chance(0.05) { 1 + r.below(16) } else { 1 };
        for _ in 0..copies.min(count - lights.len()) {
            lights.push(light);
        }
    }
    (lights, cookies)
}

/// Where a light goes: at the camera, behind it, on or just off a box's face, or anywhere
/// around the camera.
fn light_position(r: &mut Rng, world: &World) -> DVec3 {
    let (camera, scale) = (world.camera, world.scale);
    match r.below(6) {
        0 => {
            // At the camera, or within the near plane of it: the camera inside the volume.
            camera.position + r.direction() * camera.near * r.range(0.0, 2.0)
        }
        1 => camera.position - camera.forward() * r.log(1e-3, 10.0) * scale,
        2 | 3 => {
            // On, just in front of or just behind a box's face (its +Y or -Z face).
            let b = &world.boxes[r.below(world.boxes.len())];
            let c = DVec3::from_array(b.center);
            let face = if r.chance(0.5) { DVec3::Y * b.size[1] * 0.5 } else { DVec3::Z * b.size[2] * 0.5 };
            let dir = face.normalize_or(DVec3::Y);
            let eps = r.pick(&[0.0, 1e-4, -1e-4, 1e-2, -1e-2]) * scale;
            c + face + dir * eps + DVec3::new(r.range(-0.4, 0.4) * b.size[0], 0.0, 0.0)
        }
        _ => camera.position + r.direction() * r.log(1e-3, 30.0) * scale,
    }
}

/// Up to `most` point lights whose spheres reach 0.1 to 4 depth steps behind the surface seen
/// through a random pixel: a volume's back face there lies behind the surface by about the
/// rounding of the volume's depth, and the surface points near the ray are at 0.75 to 0.97 of
/// the radius from the light, where it still adds light. The depth step is the depth buffer's
/// resolution at the hit (2^-24 for 24-bit depth, 2^(e-23) for float depth of exponent e) over
/// the projection's depth slope there, n f / ((f - n) z^2), in view depth. For a step to span
/// a visible share of a light, the near plane moves in to between 1/3,000 and 1/100,000 of the
/// first surface hit's depth (where it was farther): 2CylinderEngine's is 1/34,000.
fn rim_lights(
    g: &mut Rng,
    camera: &mut Camera,
    boxes: &[BoxSpec],
    (settings, dim, most): (&CaseSettings, f32, usize),
    (width, height): (u32, u32),
) -> Vec<Light> {
    let (forward, right) = (camera.forward(), camera.right());
    let up = right.cross(forward);
    let tan_y = (camera.fov_y * 0.5).tan();
    let tan_x = tan_y * width as f64 / height.max(1) as f64;
    let mut out = Vec::new();
    let mut moved = false;
    for _ in 0..1 + g.below(most) {
        let dir = (forward + right * g.range(-0.9, 0.9) * tan_x + up * g.range(-0.9, 0.9) * tan_y).normalize();
        let hit = boxes.iter().filter_map(|b| ray_box(camera.position, dir, b)).fold(f64::INFINITY, f64::min);
        let z = hit * dir.dot(forward);
        if !hit.is_finite() || z <= 0.0 || z >= camera.far {
            continue;
        }
        if !moved {
            camera.near = camera.near.min(z / g.log(3e3, 1e5));
            moved = true;
        }
        let (n, f) = (camera.near, camera.far);
        if z <= n {
            continue;
        }
        let depth = if settings.reversed_z { n * (f - z) / ((f - n) * z) } else { f * (z - n) / ((f - n) * z) };
        let unit = match settings.depth_format {
            DepthFormat::Depth24PlusStencil8 => 2f64.powi(-24),
            DepthFormat::Depth32FloatStencil8 => 2f64.powi(depth.max(1e-30).log2().floor() as i32 - 23),
        };
        let step = unit * (f - n) * z * z / (n * f) / dir.dot(forward);
        let poke = step * g.log(0.1, 4.0);
        let radius = poke / g.range(0.03, 0.25);
        let color = Vec3::new(g.range(0.5, 1.0) as f32, g.range(0.5, 1.0) as f32, g.range(0.5, 1.0) as f32);
        out.push(Light::Point(PointLight {
            position: camera.position + dir * (hit + poke - radius),
            color,
            intensity: g.log(1.0, 20.0) as f32 * dim,
            radius: radius as f32,
            cookie: None,
            mask: ALL_LAYERS,
            cast_shadows: g.chance(0.5),
        }));
    }
    out
}

/// Where the ray `origin + t dir` (t > 0) enters box `b`, if it does.
fn ray_box(origin: DVec3, dir: DVec3, b: &BoxSpec) -> Option<f64> {
    let turn = DQuat::from_rotation_y(-b.yaw);
    let (o, d) = (turn * (origin - DVec3::from_array(b.center)), turn * dir);
    let half = DVec3::from_array(b.size) * 0.5;
    let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if d[k].abs() < 1e-300 {
            if o[k].abs() > half[k] {
                return None;
            }
            continue;
        }
        let (a, c) = ((-half[k] - o[k]) / d[k], (half[k] - o[k]) / d[k]);
        t0 = t0.max(a.min(c));
        t1 = t1.min(a.max(c));
    }
    (t0 <= t1 && t0 > 0.0).then_some(t0)
}
