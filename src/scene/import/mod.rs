//! glTF 2.0 import (`.gltf`, `.glb`) with the `gltf` crate: the default scene's node hierarchy,
//! triangle, line and point primitives, materials with their textures, KHR_lights_punctual lights and cameras.
//!
//! Every value the file controls is checked before it is used: a bad file is an error that names
//! the problem (the caller adds the file name), never a panic or a hang. Where the scene can
//! still be shown (a texture that does not decode, a blended line, a degenerate triangle) the
//! loader warns and goes on, with a visible fallback for missing textures.
//!
//! Light units: glTF gives point and spot intensities in candela with an inverse-square falloff,
//! ours fall off with the window (1 - (d/r)^2)^2 and no inverse square. The mapping matches the
//! two at half the radius: intensity = 4 I / (0.5625 r^2) = 7.11 I / r^2. The radius is the
//! light's `range`, or, without one, where I / d^2 falls to [`RANGE_CUTOFF`]. Directional lights
//! become the sun with their lux value as its intensity (the first one; others are dropped with a
//! warning). Exposure is the viewer's to adjust.

use super::{
    AlphaMode, Camera, Light, Material, MaterialTextures, MaterialUvs, Mesh, Object, PointLight, Scene, SpotLight, Sun,
    Texture, Topology, UvTransform, Vertex, DIELECTRIC_F0,
};
use anyhow::{anyhow, bail, Context, Result};
use glam::{DMat4, DVec3, Vec3};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

mod checks;
mod draco;
mod geometry;
pub mod lighting;
mod materials;
pub use materials::METAL_THRESHOLD;
mod meshopt;

use checks::{
    check_before_validation, check_external, check_glb_header, check_json, check_views, load_buffers, short_uri,
};

/// Extensions the importer understands; a file that requires any other is rejected.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_materials_unlit",
    "EXT_meshopt_compression",
    "KHR_texture_transform",
    "KHR_draco_mesh_compression",
    geometry::QUANTIZATION,
];

/// Point lights a file without lights gets by default (`--lights N` for another count).
pub const DEFAULT_ADDED_LIGHTS: usize = 64;

/// Without a `range`, a light reaches as far as its inverse-square intensity exceeds this.
pub const RANGE_CUTOFF: f32 = 0.05;

/// Largest element count of one accessor.
pub const MAX_ACCESSOR_COUNT: usize = 1 << 26;
/// Largest count of a sparse accessor without a buffer view (zeros plus a few values: its
/// size is not bounded by the file's, so a 1 KB file could ask for gigabytes; found by the
/// fuzzer).
pub const MAX_SPARSE_ONLY_COUNT: usize = 1 << 22;

/// Files larger than this are refused before they are read (a guard against reading a device or
/// an enormous file by mistake).
pub const MAX_FILE_BYTES: u64 = 2 << 30;

#[derive(Clone, Debug)]
pub struct ImportOptions {
    /// Point lights added when the file has no lights (0: none; see [`lighting`]).
    pub lights: usize,
    /// Textures with a side longer than this are downscaled.
    pub max_texture_size: u32,
    /// Most vertices plus indices the primitives of one file may decode in all: a budget that
    /// keeps a small file that reuses a big accessor many times from running for minutes.
    pub max_elements: usize,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self { lights: DEFAULT_ADDED_LIGHTS, max_texture_size: 4096, max_elements: 1 << 25 }
    }
}

/// Where a load has got to: `done` of `total` in `stage`.
#[derive(Clone, Copy, Debug)]
pub struct Progress<'a> {
    pub stage: &'a str,
    pub done: usize,
    pub total: usize,
}

#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ImportStats {
    pub triangles: usize,
    pub vertices: usize,
    pub meshes: usize,
    pub objects: usize,
    pub materials: usize,
    pub textures: usize,
    pub lights_from_file: usize,
    pub lights_added: usize,
    /// The file has neither lights nor a sun: the sun, ambient and `ImportOptions::lights`
    /// point lights were added (`lighting::add_surface_lights` adds another count to a copy).
    pub default_lights: bool,
    pub cameras: usize,
    /// Zero-area triangles removed.
    pub dropped_triangles: usize,
    /// Line segments (strips and loops counted as their segments) and points drawn.
    pub lines: usize,
    pub points: usize,
    pub load_ms: f64,
}

pub struct Imported {
    pub scene: Scene,
    pub warnings: Vec<String>,
    pub stats: ImportStats,
}

/// Whether `name` names a glTF file rather than a built-in scene.
pub fn is_gltf_path(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".gltf") || lower.ends_with(".glb")
}

/// Loads a `.gltf` or `.glb` file. Errors name the file and the problem.
pub fn load(path: &Path, options: &ImportOptions, progress: &mut dyn FnMut(Progress<'_>)) -> Result<Imported> {
    let shown = path.display().to_string();
    let mut inner = || -> Result<Imported> {
        let meta = std::fs::metadata(path).context("cannot open the file")?;
        if !meta.is_file() {
            bail!("not a regular file");
        }
        if meta.len() > MAX_FILE_BYTES {
            bail!("the file is {} bytes, more than the {} this loader accepts", meta.len(), MAX_FILE_BYTES);
        }
        let bytes = std::fs::read(path).context("cannot read the file")?;
        let name = path.file_stem().map_or("gltf".into(), |s| s.to_string_lossy().to_string());
        load_bytes(&bytes, Some(path.parent().unwrap_or(Path::new("."))), &name, options, progress)
    };
    inner().with_context(|| shown)
}

/// Loads glTF from memory. `base` resolves relative URIs; without it only embedded data
/// (data URIs, a .glb's binary chunk) can be read.
pub fn load_bytes(
    bytes: &[u8],
    base: Option<&Path>,
    name: &str,
    options: &ImportOptions,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Imported> {
    let start = std::time::Instant::now();
    if options.lights > crate::scene::builtin::MAX_LIGHTS {
        bail!("--lights {} is more than the {} Lampshade supports", options.lights, crate::scene::builtin::MAX_LIGHTS);
    }
    progress(Progress { stage: "parsing", done: 0, total: 1 });
    check_glb_header(bytes)?;
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(|e| anyhow!("not a valid glTF file: {e}"))?;
    check_before_validation(gltf.document.as_json())?;
    for ext in gltf.document.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            bail!(
                "the file requires the extension {ext}, which Lampshade does not support (it reads {})",
                SUPPORTED_EXTENSIONS.join(", ")
            );
        }
    }
    // Validation proper (indices in range, required fields): parse again with the checks on.
    let draco_used = gltf.document.extensions_used().any(|e| e == draco::NAME);
    let gltf::Gltf { document: doc, blob } = match gltf::Gltf::from_slice(bytes) {
        Ok(checked) => checked,
        // The `gltf` crate refuses the extensions it does not know (EXT_meshopt_compression)
        // in extensionsRequired; those were held against SUPPORTED_EXTENSIONS above. It also
        // wants a buffer view for every accessor, which Draco-compressed primitives' accessors
        // do not have (an accessor without data used elsewhere is an error when it is read).
        // Only its other findings count.
        Err(gltf::Error::Validation(list))
            if list.iter().all(|(path, err)| {
                let path = path.as_str();
                path.starts_with("extensionsRequired")
                    || draco_used
                        && path.starts_with("accessors[")
                        && path.ends_with("].bufferView")
                        && matches!(err, gltf::json::validation::Error::Missing)
            }) =>
        {
            gltf
        }
        Err(e) => return Err(validation_error(e)),
    };
    progress(Progress { stage: "parsing", done: 1, total: 1 });

    let mut warnings = Vec::new();
    for ext in doc.extensions_used() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            warnings.push(format!("extension {ext} is used but not supported; its data is ignored"));
        }
    }
    if doc.skins().len() > 0 {
        warnings.push("skins are not applied: skinned meshes are drawn in their bind pose".into());
    }
    if doc.animations().len() > 0 {
        warnings.push("animations are not played: the scene is drawn as posed in the file".into());
    }
    if doc.meshes().any(|m| m.primitives().any(|p| p.morph_targets().len() > 0)) {
        warnings.push("morph targets are not applied: meshes are drawn with their base shape".into());
    }
    check_json(&doc)?;
    let compressed = meshopt::Meshopt::read(bytes, &doc)?;
    let mut buffers = load_buffers(&doc, base, blob, &compressed.fallback, progress)?;
    if !compressed.is_empty() {
        compressed.decode(&doc, &mut buffers)?;
    }
    check_views(&doc, &buffers)?;

    let mut b = Importer {
        doc: &doc,
        buffers: &buffers,
        base,
        options,
        warnings,
        scene: Scene::new(name, Camera::looking_at(DVec3::new(0.0, 1.0, 5.0), DVec3::ZERO)),
        stats: ImportStats::default(),
        texture_slots: HashMap::new(),
        material_slots: HashMap::new(),
        mesh_slots: HashMap::new(),
        first_sun: true,
        decoded: 0,
    };
    b.textures(progress)?;
    b.nodes(progress)?;
    b.finish()?;
    let mut stats = b.stats;
    stats.load_ms = start.elapsed().as_secs_f64() * 1e3;
    let scene = b.scene;
    scene.validate().map_err(|e| anyhow!("the imported scene is inconsistent: {e}"))?;
    Ok(Imported { scene, warnings: b.warnings, stats })
}

/// The `gltf` crate's parse or validation error as a message.
fn validation_error(e: gltf::Error) -> anyhow::Error {
    match e {
        gltf::Error::Validation(list) => {
            let shown: Vec<String> = list.iter().take(4).map(|(path, err)| format!("{path}: {err}")).collect();
            let more = if list.len() > 4 { format!(" (and {} more)", list.len() - 4) } else { String::new() };
            anyhow!("the glTF is invalid: {}{more}", shown.join("; "))
        }
        other => anyhow!("not a valid glTF file: {other}"),
    }
}

/// Which way a texture is read: colour (sRGB) or data (linear).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Role {
    Color,
    Data,
}

struct Importer<'a> {
    doc: &'a gltf::Document,
    buffers: &'a [gltf::buffer::Data],
    base: Option<&'a Path>,
    options: &'a ImportOptions,
    warnings: Vec<String>,
    scene: Scene,
    stats: ImportStats,
    /// (image index, role) -> scene texture.
    texture_slots: HashMap<(usize, Role), usize>,
    /// (glTF material or None, normal map usable) -> scene material.
    material_slots: HashMap<(Option<usize>, bool), usize>,
    /// (mesh, primitive, mirrored) -> scene mesh and whether its material may use a normal map.
    mesh_slots: HashMap<(usize, usize, bool), (usize, bool)>,
    first_sun: bool,
    /// Vertices and indices decoded so far (against `options.max_elements`).
    decoded: usize,
}

impl Importer<'_> {
    /// Walks the default scene (or the first; or, without scenes, every root node).
    fn nodes(&mut self, progress: &mut dyn FnMut(Progress<'_>)) -> Result<()> {
        let roots: Vec<gltf::Node<'_>> = match self.doc.default_scene().or_else(|| self.doc.scenes().next()) {
            Some(s) => s.nodes().collect(),
            None => {
                let mut is_child = vec![false; self.doc.nodes().len()];
                for n in self.doc.nodes() {
                    for c in n.children() {
                        is_child[c.index()] = true;
                    }
                }
                self.warnings.push("the file has no scene; drawing every root node".into());
                self.doc.nodes().filter(|n| !is_child[n.index()]).collect()
            }
        };
        let total = self.doc.nodes().len();
        let mut visited = vec![false; total];
        // Iterative walk: no recursion depth to overflow, and each node is visited once, so a
        // cycle in the hierarchy cannot hang the loader.
        let mut stack: Vec<(gltf::Node<'_>, DMat4)> = roots.into_iter().rev().map(|n| (n, DMat4::IDENTITY)).collect();
        let mut done = 0;
        let mut repeated = 0;
        while let Some((node, parent)) = stack.pop() {
            if std::mem::replace(&mut visited[node.index()], true) {
                repeated += 1;
                continue;
            }
            done += 1;
            if done % 64 == 0 {
                progress(Progress { stage: "meshes", done, total });
            }
            let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(|v| v as f64)));
            let world = parent * local;
            if !world.is_finite() {
                bail!("node {} has a non-finite transform", node.index());
            }
            let extras = NodeExtras::of(&node)?;
            if let Some(mesh) = node.mesh() {
                let first = self.scene.objects.len();
                self.mesh(&mesh, world).with_context(|| match mesh.name() {
                    Some(n) => format!("mesh {} ('{n}')", mesh.index()),
                    None => format!("mesh {}", mesh.index()),
                })?;
                if let Some(layer) = extras.layer {
                    self.scene.objects[first..].iter_mut().for_each(|o| o.layer = layer);
                }
            }
            if let Some(light) = node.light() {
                let before = self.scene.lights.len();
                self.light(&light, world);
                if self.scene.lights.len() > before {
                    if let Some(mask) = extras.mask {
                        self.scene.lights_mut()[before].set_mask(mask);
                    }
                    if let Some(cookie) = &extras.cookie {
                        // Relative paths from the file's directory; built-in names as they are.
                        let spec = match self.base {
                            Some(base) if cookie.to_ascii_lowercase().ends_with(".png") => {
                                base.join(cookie).to_string_lossy().into_owned()
                            }
                            _ => cookie.clone(),
                        };
                        self.scene
                            .set_light_cookie(before, Some(&spec))
                            .map_err(|e| anyhow::anyhow!("node {} extras: {e}", node.index()))?;
                    }
                }
            }
            if let Some(camera) = node.camera() {
                self.camera(&camera, world, node.name());
            }
            for child in node.children().collect::<Vec<_>>().into_iter().rev() {
                stack.push((child, world));
            }
        }
        if repeated > 0 {
            self.warnings.push(format!(
                "{repeated} node reference(s) reach an already visited node (a cycle or a shared child); each node is drawn once"
            ));
        }
        progress(Progress { stage: "meshes", done: total, total });
        Ok(())
    }

    fn mesh(&mut self, mesh: &gltf::Mesh<'_>, world: DMat4) -> Result<()> {
        let mirrored = world.determinant() < 0.0;
        for prim in mesh.primitives() {
            let key = (mesh.index(), prim.index(), mirrored);
            let (mesh_index, normal_ok) = match self.mesh_slots.get(&key) {
                Some(&v) => v,
                None => {
                    let Some(built) =
                        self.primitive(&prim, mirrored).with_context(|| format!("primitive {}", prim.index()))?
                    else {
                        continue;
                    };
                    let normal_ok = built.1;
                    if built.0.topology == Topology::Triangles {
                        self.stats.triangles += built.0.indices.len() / 3;
                    }
                    self.stats.vertices += built.0.vertices.len();
                    self.scene.meshes.push(built.0);
                    let v = (self.scene.meshes.len() - 1, normal_ok);
                    self.mesh_slots.insert(key, v);
                    v
                }
            };
            let material = self.material(&prim.material(), normal_ok);
            self.scene.objects.push(Object { mesh: mesh_index, material, transform: world, layer: 0 });
        }
        Ok(())
    }

    fn light(&mut self, light: &gltf::khr_lights_punctual::Light<'_>, world: DMat4) {
        use gltf::khr_lights_punctual::Kind;
        let color = Vec3::from(light.color());
        let intensity = light.intensity();
        let position = world.transform_point3(DVec3::ZERO);
        let direction = world.transform_vector3(DVec3::NEG_Z).normalize_or(DVec3::NEG_Z).as_vec3();
        let label = light.name().map_or_else(|| format!("light {}", light.index()), |n| format!("light '{n}'"));
        if !(color.is_finite() && intensity.is_finite() && intensity >= 0.0 && color.min_element() >= 0.0) {
            self.warnings.push(format!("{label}: colour or intensity out of range; skipped"));
            return;
        }
        let radius = match light.range() {
            Some(r) if r.is_finite() && r > 0.0 => r,
            _ => (intensity * color.max_element() / RANGE_CUTOFF).sqrt().max(1e-3),
        };
        let ours = 4.0 * intensity / (0.5625 * radius * radius);
        // `"extras": {"cast_shadows": false}` on the light turns its shadow off; any
        // other value of the key is a warning and the default (on).
        let cast_shadows = match light.extras().as_ref().map(|raw| serde_json::from_str::<serde_json::Value>(raw.get()))
        {
            Some(Ok(v)) => match v.get("cast_shadows") {
                None => true,
                Some(serde_json::Value::Bool(b)) => *b,
                Some(other) => {
                    self.warnings.push(format!("{label}: extras.cast_shadows {other} is not true or false; casting"));
                    true
                }
            },
            _ => true,
        };
        let l = match light.kind() {
            Kind::Directional => {
                if self.first_sun {
                    self.first_sun = false;
                    self.scene.sun = Some(Sun { direction, color, intensity });
                    self.stats.lights_from_file += 1;
                } else {
                    self.warnings.push(format!("{label}: only the first directional light is used"));
                }
                return;
            }
            Kind::Point => Light::Point(PointLight {
                position,
                color,
                intensity: ours,
                radius,
                cast_shadows,
                cookie: None,
                mask: crate::scene::ALL_LAYERS,
            }),
            Kind::Spot { inner_cone_angle, outer_cone_angle } => {
                let outer = outer_cone_angle.clamp(0.0, std::f32::consts::FRAC_PI_2);
                let inner = inner_cone_angle.clamp(0.0, outer);
                Light::Spot(SpotLight {
                    position,
                    direction,
                    color,
                    intensity: ours,
                    radius,
                    inner_angle: inner,
                    outer_angle: outer,
                    cast_shadows,
                    cookie: None,
                    mask: crate::scene::ALL_LAYERS,
                })
            }
        };
        match l.validate() {
            Ok(()) => {
                self.scene.lights_mut().push(l);
                self.stats.lights_from_file += 1;
            }
            Err(e) => self.warnings.push(format!("{label}: {e}; skipped")),
        }
    }

    fn camera(&mut self, camera: &gltf::Camera<'_>, world: DMat4, node_name: Option<&str>) {
        let name = camera.name().or(node_name).map_or_else(|| format!("camera {}", camera.index()), String::from);
        let gltf::camera::Projection::Perspective(p) = camera.projection() else {
            self.warnings.push(format!("{name}: orthographic cameras are not supported; skipped"));
            return;
        };
        let position = world.transform_point3(DVec3::ZERO);
        let forward = world.transform_vector3(DVec3::NEG_Z).normalize_or(DVec3::NEG_Z);
        let mut c = Camera::looking_at(position, position + forward);
        c.fov_y = p.yfov() as f64;
        c.near = p.znear() as f64;
        c.far = p.zfar().map_or(0.0, |f| f as f64);
        self.stats.cameras += 1;
        // `far` is completed from the scene's bounds in `finish` when the file gives none.
        self.scene.viewpoints.push((name, c));
    }

    /// Camera, viewpoints and default lights once the geometry is known.
    fn finish(&mut self) -> Result<()> {
        if self.scene.objects.is_empty() {
            bail!("nothing to draw: the scene has no triangles, lines or points");
        }
        let bounds = self.scene.bounds();
        let (lo, hi) = bounds.unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)));
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-3);
        let points: Vec<DVec3> =
            lighting::sample_vertices(&self.scene, lighting::FRAMING_SAMPLES).into_iter().map(|(p, _)| p).collect();
        let framing = lighting::framing(lo, hi, &points);
        let mut views = std::mem::take(&mut self.scene.viewpoints);
        for (name, c) in &mut views {
            if c.far.partial_cmp(&c.near) != Some(std::cmp::Ordering::Greater) {
                c.far = (c.position - centre).length() + radius * 3.0;
                c.far = c.far.max(c.near * 10.0);
            }
            if let Err(e) = c.validate() {
                self.warnings.push(format!("{name}: {e}; not offered"));
                c.fov_y = f64::NAN;
            }
        }
        views.retain(|(_, c)| !c.fov_y.is_nan());
        views.push(("framing".into(), framing));
        self.scene.camera = views[0].1;
        self.scene.viewpoints = views;

        if self.scene.lights.is_empty() && self.scene.sun.is_none() {
            self.add_default_lights();
            self.stats.default_lights = true;
        }
        self.stats.meshes = self.scene.meshes.len();
        self.stats.objects = self.scene.objects.len();
        self.stats.materials = self.scene.materials.len();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbr_mapping_covers_the_ends() {
        // Rough dielectric: wide, dim lobe; full diffuse.
        let (d, level, exp) = Material::blinn_phong_from_pbr(Vec3::ONE, 0.0, 1.0, DIELECTRIC_F0);
        assert_eq!(d, Vec3::ONE);
        assert_eq!(exp, 1.0);
        assert!((level - DIELECTRIC_F0 * 9.0 / 8.0).abs() < 1e-6);
        // Polished metal: no diffuse, the exponent at its clamp, the level unclamped: f0 = 0.9
        // (the base's luminance) times the normalisation (2048 + 8) / 8.
        let (d, level, exp) = Material::blinn_phong_from_pbr(Vec3::splat(0.9), 1.0, 0.0, DIELECTRIC_F0);
        assert_eq!(d, Vec3::ZERO);
        assert_eq!(exp, 2048.0);
        assert!((level - 0.9 * 2056.0 / 8.0).abs() < 1e-3, "level {level}");
        // Roughness 0.5: alpha 0.25, exponent 2/0.0625 - 2 = 30.
        let (_, _, exp) = Material::blinn_phong_from_pbr(Vec3::ONE, 0.0, 0.5, DIELECTRIC_F0);
        assert!((exp - 30.0).abs() < 1e-4);
    }

    #[test]
    fn texture_transforms_rotate_as_the_khronos_sample_expects() {
        // With the opposite sign, TextureTransformTest.gltf (assimp-testmodels) shows its
        // arrow pointing at the red "rotated the wrong way" marker (looked at).
        let quarter = UvTransform { rotation: std::f32::consts::FRAC_PI_2, ..Default::default() };
        assert!((quarter.apply(glam::Vec2::X) - glam::Vec2::new(0.0, -1.0)).length() < 1e-6);
        // Translation x rotation x scale: scale first, offset last.
        let t = UvTransform {
            set: 0,
            offset: glam::Vec2::new(0.5, 0.25),
            rotation: quarter.rotation,
            scale: glam::Vec2::new(2.0, 3.0),
        };
        assert!((t.apply(glam::Vec2::ONE) - glam::Vec2::new(3.5, -1.75)).length() < 1e-6);
        assert!(UvTransform::default().is_identity() && !t.is_identity());
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        let mut quiet = |_: Progress<'_>| {};
        for bytes in
            [&b""[..], b"{", b"glTF\x02\x00\x00\x00", b"{\"asset\":{\"version\":\"2.0\"},\"nodes\":[{\"mesh\":5}]}"]
        {
            let r = load_bytes(bytes, None, "x", &ImportOptions::default(), &mut quiet);
            assert!(r.is_err(), "{bytes:?} loaded");
        }
    }
}

/// Seed 004's keys in a node's `extras`: `{"layer": 0..=31}` on a mesh node (its objects'
/// culling layer); `{"cookie": "window" | "flashlight" | "file.png", "mask": u32}` on a
/// light node (a PNG path is relative to the glTF file). Other keys are left alone; a key of
/// the wrong type or range is an error naming the node.
#[derive(Default)]
struct NodeExtras {
    layer: Option<u8>,
    cookie: Option<String>,
    mask: Option<u32>,
}

impl NodeExtras {
    fn of(node: &gltf::Node<'_>) -> Result<Self> {
        let Some(raw) = node.extras() else { return Ok(Self::default()) };
        let Ok(serde_json::Value::Object(map)) = serde_json::from_str::<serde_json::Value>(raw.get()) else {
            return Ok(Self::default());
        };
        let bad = |key: &str, want: &str| anyhow::anyhow!("node {} extras: \"{key}\" must be {want}", node.index());
        let mut out = Self::default();
        if let Some(v) = map.get("layer") {
            out.layer = Some(v.as_u64().filter(|&l| l <= 31).ok_or_else(|| bad("layer", "a layer 0..=31"))? as u8);
        }
        if let Some(v) = map.get("mask") {
            out.mask =
                Some(v.as_u64().and_then(|m| u32::try_from(m).ok()).ok_or_else(|| bad("mask", "a 32-bit layer mask"))?);
        }
        if let Some(v) = map.get("cookie") {
            out.cookie =
                Some(v.as_str().ok_or_else(|| bad("cookie", "a built-in cookie's name or a .png path"))?.into());
        }
        Ok(out)
    }
}
