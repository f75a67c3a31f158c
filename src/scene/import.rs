//! glTF 2.0 import (`.gltf`, `.glb`) with the `gltf` crate: the default scene's node hierarchy,
//! triangle primitives, materials with their textures, KHR_lights_punctual lights and cameras.
//!
//! Every value the file controls is checked before it is used: a bad file is an error that names
//! the problem (the caller adds the file name), never a panic or a hang. Where the scene can
//! still be shown (a texture that does not decode, a point or line primitive, a degenerate
//! triangle) the loader warns and goes on, with a visible fallback for missing textures.
//!
//! Light units: glTF gives point and spot intensities in candela with an inverse-square falloff,
//! ours fall off with the window (1 - (d/r)^2)^2 and no inverse square. The mapping matches the
//! two at half the radius: intensity = 4 I / (0.5625 r^2) = 7.11 I / r^2. The radius is the
//! light's `range`, or, without one, where I / d^2 falls to [`RANGE_CUTOFF`]. Directional lights
//! become the sun with their lux value as its intensity (the first one; others are dropped with a
//! warning). Exposure is the viewer's to adjust.

use super::{
    AlphaMode, Camera, Light, Material, MaterialTextures, Mesh, Object, PointLight, Scene, SpotLight, Sun, Texture,
    Vertex, DIELECTRIC_F0,
};
use anyhow::{anyhow, bail, Context, Result};
use glam::{DMat4, DVec3, Vec3};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// Extensions the importer understands; a file that requires any other is rejected.
pub const SUPPORTED_EXTENSIONS: &[&str] =
    &["KHR_lights_punctual", "KHR_materials_specular", "KHR_materials_ior", "KHR_materials_emissive_strength"];

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
    /// Point lights per side of the grid added when the file has no lights (0: none).
    pub light_grid: u32,
    /// Textures with a side longer than this are downscaled.
    pub max_texture_size: u32,
    /// Most vertices plus indices the primitives of one file may decode in all: a budget that
    /// keeps a small file that reuses a big accessor many times from running for minutes.
    pub max_elements: usize,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self { light_grid: 8, max_texture_size: 4096, max_elements: 1 << 25 }
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
    pub cameras: usize,
    /// Zero-area triangles removed.
    pub dropped_triangles: usize,
    /// Point and line primitives, which a deferred renderer of surfaces does not draw.
    pub skipped_primitives: usize,
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
    let gltf::Gltf { document: doc, blob } = gltf::Gltf::from_slice(bytes).map_err(|e| match e {
        gltf::Error::Validation(list) => {
            let shown: Vec<String> = list.iter().take(4).map(|(path, err)| format!("{path}: {err}")).collect();
            let more = if list.len() > 4 { format!(" (and {} more)", list.len() - 4) } else { String::new() };
            anyhow!("the glTF is invalid: {}{more}", shown.join("; "))
        }
        other => anyhow!("not a valid glTF file: {other}"),
    })?;
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
    let buffers = load_buffers(&doc, base, blob, progress)?;
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

fn load_buffers(
    doc: &gltf::Document,
    base: Option<&Path>,
    mut blob: Option<Vec<u8>>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<gltf::buffer::Data>> {
    let total = doc.buffers().len();
    let mut out = Vec::with_capacity(total);
    for (i, buffer) in doc.buffers().enumerate() {
        progress(Progress { stage: "buffers", done: i, total });
        let what = match buffer.name() {
            Some(n) => format!("buffer {i} ('{n}')"),
            None => format!("buffer {i}"),
        };
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => match blob.take() {
                Some(b) => b,
                None => bail!("{what} refers to the binary chunk, which the file does not have"),
            },
            gltf::buffer::Source::Uri(uri) => {
                check_external(base, uri).with_context(|| what.clone())?;
                gltf::buffer::Data::from_source(gltf::buffer::Source::Uri(uri), base)
                    .map_err(|e| anyhow!("{what}: cannot load '{}': {e}", short_uri(uri)))?
                    .0
            }
        };
        if data.len() < buffer.length() {
            bail!("{what} has {} bytes, the file declares {}", data.len(), buffer.length());
        }
        out.push(gltf::buffer::Data(data));
    }
    progress(Progress { stage: "buffers", done: total, total });
    Ok(out)
}

/// A data URI shortened for messages.
fn short_uri(uri: &str) -> String {
    if uri.len() > 48 {
        format!("{}...", &uri[..uri.char_indices().nth(40).map_or(uri.len(), |(i, _)| i)])
    } else {
        uri.to_string()
    }
}

/// An external reference must be a regular file of a sane size (not a device, not a folder).
fn check_external(base: Option<&Path>, uri: &str) -> Result<()> {
    if uri.starts_with("data:") {
        return Ok(());
    }
    let Some(base) = base else { bail!("'{}' is an external file, which cannot be read here", short_uri(uri)) };
    let path = base.join(uri);
    if let Ok(meta) = std::fs::metadata(&path) {
        if !meta.is_file() {
            bail!("'{uri}' is not a regular file");
        }
        if meta.len() > MAX_FILE_BYTES {
            bail!("'{uri}' is {} bytes, more than the {} this loader accepts", meta.len(), MAX_FILE_BYTES);
        }
    }
    Ok(())
}

/// A .glb header whose total length is shorter than the header itself makes the `gltf` crate
/// subtract past zero (a panic in debug builds; found by the fuzzer).
fn check_glb_header(bytes: &[u8]) -> Result<()> {
    if !bytes.starts_with(b"glTF") {
        return Ok(());
    }
    let Some(len) = bytes.get(8..12) else { bail!("not a valid glTF file: the .glb header is cut short") };
    let length = u32::from_le_bytes([len[0], len[1], len[2], len[3]]) as usize;
    if length < 20 {
        bail!("not a valid glTF file: the .glb header declares {length} bytes, less than a header and a chunk");
    }
    Ok(())
}

/// What `gltf-json`'s own validation indexes without checking (a panic otherwise; found by the
/// fuzzer): the POSITION accessor of every primitive.
fn check_before_validation(root: &gltf::json::Root) -> Result<()> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (semantic, index) in &prim.attributes {
                if index.value() >= root.accessors.len() {
                    bail!(
                        "the glTF is invalid: meshes[{m}].primitives[{p}].attributes[{:?}] refers to accessor {}, but there are {}",
                        semantic,
                        index.value(),
                        root.accessors.len()
                    );
                }
            }
        }
    }
    Ok(())
}

/// What the `gltf` crate's accessors assume without validating (they would panic otherwise):
/// an image has a source, an image in a buffer view has a MIME type, a camera has the
/// projection its type names.
fn check_json(doc: &gltf::Document) -> Result<()> {
    let root = doc.as_json();
    for (i, image) in root.images.iter().enumerate() {
        match (&image.buffer_view, &image.uri) {
            (Some(_), _) if image.mime_type.is_none() => bail!("image {i} is in a buffer view but has no mimeType"),
            (None, None) => bail!("image {i} has neither a uri nor a bufferView"),
            _ => {}
        }
    }
    for (i, camera) in root.cameras.iter().enumerate() {
        use gltf::json::camera::Type;
        let ok = match camera.type_ {
            gltf::json::validation::Checked::Valid(Type::Perspective) => camera.perspective.is_some(),
            gltf::json::validation::Checked::Valid(Type::Orthographic) => camera.orthographic.is_some(),
            _ => false,
        };
        if !ok {
            bail!("camera {i} lacks the projection its type names");
        }
    }
    Ok(())
}

/// Every buffer view inside its buffer and every accessor inside its view, with a stride no
/// shorter than its element: the `gltf` crate's readers slice with these numbers.
fn check_views(doc: &gltf::Document, buffers: &[gltf::buffer::Data]) -> Result<()> {
    let view_ok = |view: &gltf::buffer::View<'_>| -> Result<()> {
        let len = buffers.get(view.buffer().index()).map_or(0, |b| b.0.len());
        let end = view.offset().checked_add(view.length());
        if end.is_none_or(|e| e > len) {
            bail!(
                "buffer view {} (offset {}, length {}) reaches past the end of buffer {} ({len} bytes)",
                view.index(),
                view.offset(),
                view.length(),
                view.buffer().index()
            );
        }
        Ok(())
    };
    for view in doc.views() {
        view_ok(&view)?;
    }
    let span = |what: String, view: &gltf::buffer::View<'_>, offset: usize, count: usize, elem: usize| -> Result<()> {
        if count == 0 {
            bail!("{what} has count 0");
        }
        let stride = view.stride().unwrap_or(elem);
        if stride < elem {
            bail!("{what}: buffer view {} has a stride of {stride} bytes for {elem}-byte elements", view.index());
        }
        let end = stride.checked_mul(count - 1).and_then(|s| s.checked_add(offset)).and_then(|s| s.checked_add(elem));
        if end.is_none_or(|e| e > view.length()) {
            bail!(
                "{what} ({count} elements of {elem} bytes from offset {offset}) reads past the end of buffer view {} ({} bytes)",
                view.index(),
                view.length()
            );
        }
        Ok(())
    };
    for acc in doc.accessors() {
        let what = format!("accessor {}", acc.index());
        // A sparse accessor without a view is zeros plus a few values: its count is not
        // bounded by the file's size, so it is bounded here.
        if acc.count() > MAX_ACCESSOR_COUNT {
            bail!("{what} has {} elements, more than the {MAX_ACCESSOR_COUNT} this loader accepts", acc.count());
        }
        if acc.view().is_none() && acc.count() > MAX_SPARSE_ONLY_COUNT {
            bail!(
                "{what} is a sparse accessor without a buffer view of {} elements (at most {MAX_SPARSE_ONLY_COUNT})",
                acc.count()
            );
        }
        if let Some(view) = acc.view() {
            span(what.clone(), &view, acc.offset(), acc.count(), acc.size())?;
        } else if acc.sparse().is_none() && acc.count() > 0 {
            // No data: the gltf readers return nothing; the mesh code reports it where used.
        }
        if let Some(sparse) = acc.sparse() {
            let n = sparse.count();
            let idx = sparse.indices();
            span(format!("{what} sparse indices"), &idx.view(), idx.offset(), n, idx.index_type().size())?;
            let values = sparse.values();
            span(format!("{what} sparse values"), &values.view(), values.offset(), n, acc.size())?;
        }
    }
    Ok(())
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
    /// Decodes every image a material uses, in the roles it is used in, on all cores.
    fn textures(&mut self, progress: &mut dyn FnMut(Progress<'_>)) -> Result<()> {
        let mut wanted: Vec<(usize, Role)> = Vec::new();
        for m in self.doc.materials() {
            let pbr = m.pbr_metallic_roughness();
            let mut want = |t: Option<gltf::Texture<'_>>, role| {
                if let Some(t) = t {
                    let key = (t.source().index(), role);
                    if !wanted.contains(&key) {
                        wanted.push(key);
                    }
                }
            };
            want(pbr.base_color_texture().map(|i| i.texture()), Role::Color);
            want(m.emissive_texture().map(|i| i.texture()), Role::Color);
            want(m.normal_texture().map(|i| i.texture()), Role::Data);
            want(pbr.metallic_roughness_texture().map(|i| i.texture()), Role::Data);
        }
        let total = wanted.len();
        progress(Progress { stage: "textures", done: 0, total });
        // Encoded bytes first (sequential: they may come from the buffers or from files).
        let mut encoded: Vec<Result<Vec<u8>>> = Vec::with_capacity(total);
        for &(image, _) in &wanted {
            encoded.push(self.image_bytes(image));
        }
        let max = self.options.max_texture_size.max(1);
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).clamp(1, 8);
        let mut decoded: Vec<Option<Result<Texture>>> = (0..total).map(|_| None).collect();
        let done = std::sync::atomic::AtomicUsize::new(0);
        std::thread::scope(|s| {
            let chunks: Vec<_> = decoded.chunks_mut(total.div_ceil(threads).max(1)).collect();
            let mut start = 0;
            let mut handles = Vec::new();
            for chunk in chunks {
                let first = start;
                start += chunk.len();
                let (wanted, encoded, done) = (&wanted, &encoded, &done);
                handles.push(s.spawn(move || {
                    for (k, slot) in chunk.iter_mut().enumerate() {
                        let i = first + k;
                        let (image, role) = wanted[i];
                        *slot = Some(match &encoded[i] {
                            Ok(bytes) => decode_image(bytes, max).map(|mut t| {
                                t.srgb = role == Role::Color;
                                t.name = format!("image {image}");
                                t
                            }),
                            Err(e) => Err(anyhow!("{e:#}")),
                        });
                        done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    }
                }));
            }
            // Report progress from this thread while the workers run.
            loop {
                let n = done.load(std::sync::atomic::Ordering::Relaxed);
                progress(Progress { stage: "textures", done: n, total });
                if handles.iter().all(|h| h.is_finished()) {
                    break;
                }
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
        });
        for (i, ((image, role), result)) in wanted.iter().zip(decoded).enumerate() {
            let name = self.doc.images().nth(*image).and_then(|im| im.name().map(String::from));
            let label = name.unwrap_or_else(|| format!("image {image}"));
            let texture = match result {
                Some(Ok(mut t)) => {
                    t.name = label;
                    t
                }
                Some(Err(e)) => {
                    self.warnings.push(format!("{label}: {e:#}; shown as a magenta checker"));
                    Texture::missing(&label, *role == Role::Color)
                }
                None => Texture::missing(&label, *role == Role::Color),
            };
            self.texture_slots.insert((*image, *role), i);
            self.scene.textures.push(Arc::new(texture));
        }
        progress(Progress { stage: "textures", done: total, total });
        self.stats.textures = total;
        Ok(())
    }

    /// The encoded bytes of an image (from a buffer view, a data URI or a file).
    fn image_bytes(&self, index: usize) -> Result<Vec<u8>> {
        let Some(image) = self.doc.images().nth(index) else { bail!("image {index} does not exist") };
        match image.source() {
            gltf::image::Source::View { view, .. } => {
                let data = &self.buffers[view.buffer().index()].0;
                // `check_views` has already put the view inside its buffer.
                Ok(data[view.offset()..view.offset() + view.length()].to_vec())
            }
            gltf::image::Source::Uri { uri, .. } => {
                check_external(self.base, uri)?;
                gltf::buffer::Data::from_source(gltf::buffer::Source::Uri(uri), self.base)
                    .map(|d| d.0)
                    .map_err(|e| anyhow!("cannot load '{}': {e}", short_uri(uri)))
            }
        }
    }

    /// The scene material for a glTF material (None: glTF's default material). `normal_ok` is
    /// false for primitives without UVs, which cannot use a normal map.
    fn material(&mut self, m: &gltf::Material<'_>, normal_ok: bool) -> usize {
        let key = (m.index(), normal_ok);
        if let Some(&k) = self.material_slots.get(&key) {
            return k;
        }
        let label = m.name().map_or_else(|| format!("material {:?}", m.index()), |n| format!("material '{n}'"));
        let pbr = m.pbr_metallic_roughness();
        let [r, g, bl, a] = pbr.base_color_factor();
        let base = Vec3::new(r, g, bl);
        let mut textures = MaterialTextures::default();
        let tex = |info: Option<(gltf::Texture<'_>, u32)>, role: Role, what: &str, warnings: &mut Vec<String>| {
            let (t, set) = info?;
            if set != 0 {
                warnings.push(format!("{label}: {what} uses TEXCOORD_{set}; only TEXCOORD_0 is read"));
            }
            self.texture_slots.get(&(t.source().index(), role)).copied()
        };
        let w = &mut self.warnings;
        textures.base_color =
            tex(pbr.base_color_texture().map(|i| (i.texture(), i.tex_coord())), Role::Color, "base colour", w);
        textures.emissive = tex(m.emissive_texture().map(|i| (i.texture(), i.tex_coord())), Role::Color, "emissive", w);
        textures.metallic_roughness = tex(
            pbr.metallic_roughness_texture().map(|i| (i.texture(), i.tex_coord())),
            Role::Data,
            "metallic-roughness",
            w,
        );
        let normal = m.normal_texture();
        if normal_ok {
            textures.normal = tex(normal.as_ref().map(|n| (n.texture(), n.tex_coord())), Role::Data, "normal map", w);
        }
        for info in [pbr.base_color_texture(), m.emissive_texture(), pbr.metallic_roughness_texture()].iter().flatten()
        {
            if info.texture_transform().is_some() {
                w.push(format!("{label}: KHR_texture_transform is not supported; the texture is drawn untransformed"));
            }
        }
        // KHR_materials_specular / KHR_materials_ior: the dielectric reflectance.
        let ior = m.ior().unwrap_or(1.5).max(1.0);
        let mut f0 = ((ior - 1.0) / (ior + 1.0)).powi(2);
        if let Some(spec) = m.specular() {
            let c = Vec3::from(spec.specular_color_factor());
            f0 = (f0 * c.max_element()).min(1.0) * spec.specular_factor();
        }
        if !f0.is_finite() {
            f0 = DIELECTRIC_F0;
        }
        let metallic = pbr.metallic_factor();
        let roughness = pbr.roughness_factor();
        let (diffuse, level, exponent) = if textures.metallic_roughness.is_some() {
            // Derived per pixel by the shader; keep the factors.
            (base, f0, 1.0)
        } else {
            Material::blinn_phong_from_pbr(base, metallic, roughness, f0)
        };
        let emissive = Vec3::from(m.emissive_factor()) * m.emissive_strength().unwrap_or(1.0);
        let alpha_mode = match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: m.alpha_cutoff().unwrap_or(0.5) },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        };
        let mut material = Material {
            diffuse,
            specular_level: level,
            specular_exponent: exponent,
            emissive,
            alpha: a,
            alpha_mode,
            double_sided: m.double_sided(),
            textures,
            normal_scale: normal.as_ref().map_or(1.0, |n| n.scale()),
            metallic,
            roughness,
        };
        // Values the file controls: keep them finite and in range.
        let fix = |v: f32, lo: f32, hi: f32, default: f32| if v.is_finite() { v.clamp(lo, hi) } else { default };
        material.diffuse =
            Vec3::new(fix(diffuse.x, 0.0, 1.0, 0.8), fix(diffuse.y, 0.0, 1.0, 0.8), fix(diffuse.z, 0.0, 1.0, 0.8));
        material.emissive =
            Vec3::new(fix(emissive.x, 0.0, 1e4, 0.0), fix(emissive.y, 0.0, 1e4, 0.0), fix(emissive.z, 0.0, 1e4, 0.0));
        material.alpha = fix(a, 0.0, 1.0, 1.0);
        material.specular_level = fix(level, 0.0, 1.0, DIELECTRIC_F0);
        material.specular_exponent = fix(exponent, 1.0, 2048.0, 32.0);
        material.normal_scale = fix(material.normal_scale, -16.0, 16.0, 1.0);
        material.metallic = fix(metallic, 0.0, 1.0, 0.0);
        material.roughness = fix(roughness, 0.0, 1.0, 1.0);
        if let AlphaMode::Mask { cutoff } = material.alpha_mode {
            material.alpha_mode = AlphaMode::Mask { cutoff: fix(cutoff, 0.0, 1.0, 0.5) };
        }
        self.scene.materials.push(material);
        let k = self.scene.materials.len() - 1;
        self.material_slots.insert(key, k);
        k
    }

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
            if let Some(mesh) = node.mesh() {
                self.mesh(&mesh, world).with_context(|| match mesh.name() {
                    Some(n) => format!("mesh {} ('{n}')", mesh.index()),
                    None => format!("mesh {}", mesh.index()),
                })?;
            }
            if let Some(light) = node.light() {
                self.light(&light, world);
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
                    self.stats.triangles += built.0.indices.len() / 3;
                    self.stats.vertices += built.0.vertices.len();
                    self.scene.meshes.push(built.0);
                    let v = (self.scene.meshes.len() - 1, normal_ok);
                    self.mesh_slots.insert(key, v);
                    v
                }
            };
            let material = self.material(&prim.material(), normal_ok);
            self.scene.objects.push(Object { mesh: mesh_index, material, transform: world });
        }
        Ok(())
    }

    /// One primitive as an indexed triangle list, or `None` when it is not drawable (points,
    /// lines, nothing left after removing degenerate triangles). The bool: it has UVs, so a
    /// normal map can be used.
    fn primitive(&mut self, prim: &gltf::Primitive<'_>, mirrored: bool) -> Result<Option<(Mesh, bool)>> {
        use gltf::accessor::{DataType, Dimensions};
        use gltf::mesh::Mode;
        let mode = prim.mode();
        if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            self.stats.skipped_primitives += 1;
            self.warnings.push(format!("a primitive of mode {mode:?} is skipped: only triangles are drawn"));
            return Ok(None);
        }
        let check =
            |sem: &gltf::Semantic, what: &str, dims: &[Dimensions], types: &[DataType]| -> Result<Option<usize>> {
                let Some(acc) = prim.get(sem) else { return Ok(None) };
                if !dims.contains(&acc.dimensions()) || !types.contains(&acc.data_type()) {
                    bail!(
                        "{what} accessor {} is {:?} {:?}, which glTF does not allow",
                        acc.index(),
                        acc.dimensions(),
                        acc.data_type()
                    );
                }
                if acc.view().is_none() && acc.sparse().is_none() {
                    bail!("{what} accessor {} has no data (no buffer view)", acc.index());
                }
                Ok(Some(acc.count()))
            };
        let f32_only = [DataType::F32];
        let Some(n) = check(&gltf::Semantic::Positions, "POSITION", &[Dimensions::Vec3], &f32_only)? else {
            bail!("it has no POSITION attribute");
        };
        self.decoded = self.decoded.saturating_add(n).saturating_add(prim.indices().map_or(0, |a| a.count()));
        if self.decoded > self.options.max_elements {
            bail!("the primitives add up to more than {} vertices and indices", self.options.max_elements);
        }
        let n_normals = check(&gltf::Semantic::Normals, "NORMAL", &[Dimensions::Vec3], &f32_only)?;
        let n_tangents = check(&gltf::Semantic::Tangents, "TANGENT", &[Dimensions::Vec4], &f32_only)?;
        let n_uv = check(
            &gltf::Semantic::TexCoords(0),
            "TEXCOORD_0",
            &[Dimensions::Vec2],
            &[DataType::F32, DataType::U8, DataType::U16],
        )?;
        for (what, count) in [("NORMAL", n_normals), ("TANGENT", n_tangents), ("TEXCOORD_0", n_uv)] {
            if let Some(c) = count {
                if c != n {
                    bail!("{what} has {c} elements but POSITION has {n}: the accessor counts disagree");
                }
            }
        }
        let reader = prim.reader(|b| self.buffers.get(b.index()).map(|d| d.0.as_slice()));
        let positions: Vec<[f32; 3]> =
            reader.read_positions().ok_or_else(|| anyhow!("POSITION cannot be read"))?.collect();
        if positions.len() != n {
            bail!("POSITION yields {} of its {n} elements", positions.len());
        }
        if let Some(i) = positions.iter().position(|p| !p.iter().all(|v| v.is_finite())) {
            bail!("vertex {i} has a non-finite position {:?}", positions[i]);
        }
        let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|it| it.collect());
        let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|it| it.collect());
        let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|it| it.into_f32().collect());
        for (what, len) in [
            ("NORMAL", normals.as_ref().map(|v| v.len())),
            ("TANGENT", tangents.as_ref().map(|v| v.len())),
            ("TEXCOORD_0", uvs.as_ref().map(|v| v.len())),
        ] {
            if len.is_some_and(|l| l != n) {
                bail!("{what} cannot be read in full");
            }
        }
        if n_normals.is_some() && normals.is_none() || n_uv.is_some() && uvs.is_none() {
            bail!("an attribute's data cannot be read");
        }
        let raw_indices: Vec<u32> = match prim.indices() {
            Some(acc) => {
                if acc.dimensions() != Dimensions::Scalar
                    || !matches!(acc.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
                {
                    bail!(
                        "index accessor {} is {:?} {:?}; indices must be unsigned scalars",
                        acc.index(),
                        acc.dimensions(),
                        acc.data_type()
                    );
                }
                let idx: Vec<u32> = reader
                    .read_indices()
                    .ok_or_else(|| anyhow!("index accessor {} cannot be read", acc.index()))?
                    .into_u32()
                    .collect();
                if idx.len() != acc.count() {
                    bail!("index accessor {} yields {} of its {} elements", acc.index(), idx.len(), acc.count());
                }
                if let Some((k, &bad)) = idx.iter().enumerate().find(|(_, &i)| i as usize >= n) {
                    bail!("index {k} is {bad}, out of range for {n} vertices");
                }
                idx
            }
            None => (0..n as u32).collect(),
        };
        let mut tris: Vec<[u32; 3]> = match mode {
            Mode::Triangles => raw_indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
            Mode::TriangleStrip => (2..raw_indices.len())
                .map(|i| {
                    let (a, b, c) = (raw_indices[i - 2], raw_indices[i - 1], raw_indices[i]);
                    if i % 2 == 0 {
                        [a, b, c]
                    } else {
                        [b, a, c]
                    }
                })
                .collect(),
            _ => (2..raw_indices.len()).map(|i| [raw_indices[0], raw_indices[i - 1], raw_indices[i]]).collect(),
        };
        if mode == Mode::Triangles && !raw_indices.len().is_multiple_of(3) {
            self.warnings
                .push(format!("{} trailing indices do not make a triangle and are ignored", raw_indices.len() % 3));
        }
        // Zero-area triangles draw nothing and break normal and tangent generation.
        let before = tris.len();
        tris.retain(|t| {
            let p = t.map(|i| glam::Vec3::from(positions[i as usize]).as_dvec3());
            let c = (p[1] - p[0]).cross(p[2] - p[0]);
            let scale = (p[1] - p[0]).length_squared().max((p[2] - p[0]).length_squared());
            c.length_squared() > 1e-24 * scale * scale && c.is_finite()
        });
        let dropped = before - tris.len();
        if dropped > 0 {
            self.stats.dropped_triangles += dropped;
        }
        if tris.is_empty() {
            self.warnings.push("a primitive has no triangles with area and is skipped".into());
            return Ok(None);
        }
        if mirrored {
            // A mirroring transform turns counter-clockwise into clockwise: swap to keep the
            // front faces in front for back-face culling.
            for t in &mut tris {
                t.swap(1, 2);
            }
        }
        let material = prim.material();
        let wants_normal_map = material.normal_texture().is_some();
        let has_uv = uvs.is_some();
        if wants_normal_map && !has_uv {
            self.warnings.push(format!("{}: a normal map without TEXCOORD_0 is ignored", prim_label(prim)));
        }

        let mut mesh = Mesh { name: prim_label(prim), ..Default::default() };
        let uv_at = |i: usize| {
            uvs.as_ref().map_or([0.0, 0.0], |u| if u[i].iter().all(|v| v.is_finite()) { u[i] } else { [0.0, 0.0] })
        };
        match &normals {
            None => {
                // glTF: without normals, flat shading. Each triangle gets its own vertices.
                for t in &tris {
                    let p = t.map(|i| glam::Vec3::from(positions[i as usize]));
                    let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                    let n = if mirrored { -n } else { n };
                    let base = mesh.vertices.len() as u32;
                    for &i in t {
                        mesh.vertices.push(Vertex::new(positions[i as usize], n.into(), uv_at(i as usize)));
                    }
                    mesh.indices.extend([base, base + 1, base + 2]);
                }
            }
            Some(normals) => {
                let mut bad = 0;
                let mut fixed: Vec<Vec3> = normals.iter().map(|n| Vec3::from(*n)).collect();
                let broken: Vec<bool> = fixed.iter().map(|n| !n.is_finite() || n.length_squared() < 1e-12).collect();
                if broken.iter().any(|&b| b) {
                    // Replace unusable normals with the area-weighted normal of their faces.
                    let mut acc = vec![Vec3::ZERO; n];
                    for t in &tris {
                        let p = t.map(|i| glam::Vec3::from(positions[i as usize]));
                        let fnorm = (p[1] - p[0]).cross(p[2] - p[0]);
                        let fnorm = if mirrored { -fnorm } else { fnorm };
                        for &i in t {
                            acc[i as usize] += fnorm;
                        }
                    }
                    for i in 0..n {
                        if broken[i] {
                            fixed[i] = acc[i].normalize_or(Vec3::Y);
                            bad += 1;
                        }
                    }
                    self.warnings.push(format!(
                        "{}: {bad} normal(s) are zero or not finite; replaced by the faces' normal",
                        prim_label(prim)
                    ));
                }
                for i in 0..n {
                    let mut v = Vertex::new(positions[i], fixed[i].normalize().into(), uv_at(i));
                    if let Some(t) = &tangents {
                        let t = glam::Vec4::from(t[i]);
                        if t.is_finite() && t.truncate().length_squared() > 1e-12 {
                            v.tangent = [t.x, t.y, t.z, if t.w < 0.0 { -1.0 } else { 1.0 }];
                        }
                    }
                    mesh.vertices.push(v);
                }
                mesh.indices = tris.iter().flatten().copied().collect();
            }
        }
        let usable_normal_map = wants_normal_map && has_uv;
        let tangents_missing = mesh.vertices.iter().any(|v| v.tangent[3] == 0.0);
        if usable_normal_map && tangents_missing {
            generate_tangents(&mut mesh);
        }
        Ok(Some((mesh, has_uv)))
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
            Kind::Point => Light::Point(PointLight { position, color, intensity: ours, radius }),
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
                })
            }
        };
        match l.validate() {
            Ok(()) => {
                self.scene.lights.push(l);
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
            let skipped = self.stats.skipped_primitives;
            bail!(
                "nothing to draw: the scene has no triangles{}",
                if skipped > 0 {
                    format!(" ({skipped} point or line primitive(s), which are not drawn)")
                } else {
                    String::new()
                }
            );
        }
        let bounds = self.scene.bounds();
        let (lo, hi) = bounds.unwrap_or((DVec3::splat(-1.0), DVec3::splat(1.0)));
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-3);
        // A framing viewpoint: front, above, whole scene in view.
        let fov: f64 = 50f64.to_radians();
        let distance = radius / (fov * 0.5).sin() * 1.05;
        let eye = centre + DVec3::new(0.45, 0.35, 1.0).normalize() * distance;
        let mut framing = Camera::looking_at(eye, centre);
        framing.fov_y = fov;
        framing.near = (distance - radius).max(radius * 1e-3) * 0.5;
        framing.far = (distance + radius) * 3.0;
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
            self.scene.sun = Some(Sun::fill_sun());
            self.add_light_grid(lo, hi);
        }
        self.stats.meshes = self.scene.meshes.len();
        self.stats.objects = self.scene.objects.len();
        self.stats.materials = self.scene.materials.len();
        Ok(())
    }

    /// The default lights of a scene without any: an n x n grid of coloured point lights over
    /// the bounds' footprint, a little above the lowest quarter of its height.
    fn add_light_grid(&mut self, lo: DVec3, hi: DVec3) {
        let n = self.options.light_grid;
        if n == 0 {
            return;
        }
        let extent = hi - lo;
        let spacing = (extent.x.max(extent.z) / n as f64).max(1e-3);
        let y = lo.y + extent.y * 0.25 + spacing * 0.2;
        for i in 0..n {
            for j in 0..n {
                let x = lo.x + (i as f64 + 0.5) * extent.x / n as f64;
                let z = lo.z + (j as f64 + 0.5) * extent.z / n as f64;
                let h = ((i * n + j) as f32 * 0.618_034).fract();
                self.scene.lights.push(Light::Point(PointLight {
                    position: DVec3::new(x, y, z),
                    color: super::builtin::hue(h) * 0.7 + Vec3::splat(0.3),
                    intensity: 1.5,
                    radius: (spacing * 1.5) as f32,
                }));
                self.stats.lights_added += 1;
            }
        }
    }
}

fn prim_label(prim: &gltf::Primitive<'_>) -> String {
    format!("primitive {}", prim.index())
}

/// Decodes an image to RGBA8 with allocation limits, downscaled to at most `max` a side.
fn decode_image(bytes: &[u8], max: u32) -> Result<Texture> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format()?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(16384);
    limits.max_image_height = Some(16384);
    limits.max_alloc = Some(1 << 30);
    reader.limits(limits);
    if reader.format().is_none() {
        bail!("not a PNG or JPEG image");
    }
    let mut img = reader.decode().context("cannot decode the image")?.to_rgba8();
    let (w, h) = img.dimensions();
    if w == 0 || h == 0 {
        bail!("the image is empty");
    }
    if w > max || h > max {
        let s = max as f64 / w.max(h) as f64;
        let (nw, nh) = (((w as f64 * s) as u32).max(1), ((h as f64 * s) as u32).max(1));
        img = image::imageops::resize(&img, nw, nh, image::imageops::FilterType::Triangle);
    }
    let (width, height) = img.dimensions();
    Ok(Texture { name: String::new(), width, height, srgb: true, rgba: img.into_raw() })
}

/// MikkTSpace tangents (what glTF's normal maps are baked against), written per vertex.
fn generate_tangents(mesh: &mut Mesh) {
    struct Geo<'a>(&'a mut Mesh);
    impl bevy_mikktspace::Geometry for Geo<'_> {
        fn num_faces(&self) -> usize {
            self.0.indices.len() / 3
        }
        fn num_vertices_of_face(&self, _face: usize) -> usize {
            3
        }
        fn position(&self, face: usize, vert: usize) -> [f32; 3] {
            self.0.vertices[self.0.indices[face * 3 + vert] as usize].position
        }
        fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
            self.0.vertices[self.0.indices[face * 3 + vert] as usize].normal
        }
        fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
            self.0.vertices[self.0.indices[face * 3 + vert] as usize].uv
        }
        fn set_tangent(&mut self, t: Option<bevy_mikktspace::TangentSpace>, face: usize, vert: usize) {
            let i = self.0.indices[face * 3 + vert] as usize;
            let t = t.unwrap_or_default().tangent_encoded();
            if t.iter().all(|v| v.is_finite()) {
                self.0.vertices[i].tangent = t;
            }
        }
    }
    if bevy_mikktspace::generate_tangents(&mut Geo(mesh)).is_err() {
        log::warn!("tangent generation failed for {}", mesh.name);
    }
    // Anything still without a tangent gets one perpendicular to its normal.
    for v in &mut mesh.vertices {
        if v.tangent[3] == 0.0 {
            let n = Vec3::from(v.normal);
            let t = n.any_orthonormal_vector();
            v.tangent = [t.x, t.y, t.z, 1.0];
        }
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
        // Polished metal: no diffuse, the exponent at its clamp, level 1.
        let (d, level, exp) = Material::blinn_phong_from_pbr(Vec3::splat(0.9), 1.0, 0.0, DIELECTRIC_F0);
        assert_eq!(d, Vec3::ZERO);
        assert_eq!(exp, 2048.0);
        assert_eq!(level, 1.0);
        // Roughness 0.5: alpha 0.25, exponent 2/0.0625 - 2 = 30.
        let (_, _, exp) = Material::blinn_phong_from_pbr(Vec3::ONE, 0.0, 0.5, DIELECTRIC_F0);
        assert!((exp - 30.0).abs() < 1e-4);
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
