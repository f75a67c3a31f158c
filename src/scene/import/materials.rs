//! Materials and their textures: images decoded once per role (colour or data) on all cores,
//! with size limits and a visible fallback; glTF's metallic-roughness materials mapped to the
//! renderer's Blinn-Phong (`Material::blinn_phong_from_pbr`), or to its metal model
//! (`Material::metal_from_pbr`) when mostly metallic; `KHR_materials_unlit` to `unlit`.

use super::*;
use crate::scene::Brdf;

/// A glTF material whose metallic factor is at least this is imported as `metal` (specular
/// colour F0 = mix(dielectric f0, base, metallic), no diffuse term); below, as `blinn-phong`
/// (diffuse base x (1 - metallic), white specular of the base's luminance).
pub const METAL_THRESHOLD: f32 = 0.5;

impl Importer<'_> {
    /// Decodes every image a material uses, in the roles it is used in, on all cores.
    pub(super) fn textures(&mut self, progress: &mut dyn FnMut(Progress<'_>)) -> Result<()> {
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
            if let Some(Some((t, _))) = lightmap_extras(&m) {
                want(self.doc.textures().nth(t), Role::Data);
            }
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
        for ((image, role), result) in wanted.iter().zip(decoded) {
            let label = self.image_label(*image);
            let texture = match (result, role) {
                (Some(Ok(mut t)), _) => {
                    t.name = label;
                    t
                }
                // A colour map that cannot be read shows as the magenta checker, so the user
                // sees which surface lacks it.
                (Some(Err(e)), Role::Color) => {
                    self.warnings.push(format!("{label}: {e:#}; shown as a magenta checker"));
                    Texture::missing(&label, true)
                }
                (None, Role::Color) => Texture::missing(&label, true),
                // A data map that cannot be read is left out: a missing normal map means a flat
                // surface, a missing metallic-roughness map the material's factors alone. A
                // checker there would bend the normals and make the surface metallic.
                (Some(Err(e)), Role::Data) => {
                    self.warnings.push(format!(
                        "{label}: {e:#}; not used: as a normal map the surface is flat, as a metallic-roughness map the material's factors apply"
                    ));
                    continue;
                }
                (None, Role::Data) => continue,
            };
            self.texture_slots.insert((*image, *role), self.scene.textures.len());
            self.scene.textures.push(Arc::new(texture));
        }
        progress(Progress { stage: "textures", done: total, total });
        self.stats.textures = self.scene.textures.len();
        Ok(())
    }

    /// An image as messages and the viewer name it: its index, its name and, for an external
    /// file, the file's URI in full.
    pub(super) fn image_label(&self, index: usize) -> String {
        let Some(image) = self.doc.images().nth(index) else { return format!("image {index}") };
        let source = match image.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => format!(" ({uri})"),
            _ => String::new(),
        };
        match image.name() {
            Some(n) => format!("image {index} '{n}'{source}"),
            None => format!("image {index}{source}"),
        }
    }

    /// The encoded bytes of an image (from a buffer view, a data URI or a file).
    pub(super) fn image_bytes(&self, index: usize) -> Result<Vec<u8>> {
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
    pub(super) fn material(&mut self, m: &gltf::Material<'_>, normal_ok: bool) -> usize {
        let key = (m.index(), normal_ok);
        if let Some(&k) = self.material_slots.get(&key) {
            return k;
        }
        let label = m.name().map_or_else(|| format!("material {:?}", m.index()), |n| format!("material '{n}'"));
        self.warn_unused_maps(m, &label);
        let pbr = m.pbr_metallic_roughness();
        let [r, g, bl, a] = pbr.base_color_factor();
        let base = Vec3::new(r, g, bl);
        let mut textures = MaterialTextures::default();
        // Texture coordinate sets and transforms: `material_uvs`.
        let tex = |t: Option<gltf::Texture<'_>>, role: Role| {
            t.and_then(|t| self.texture_slots.get(&(t.source().index(), role)).copied())
        };
        textures.base_color = tex(pbr.base_color_texture().map(|i| i.texture()), Role::Color);
        textures.emissive = tex(m.emissive_texture().map(|i| i.texture()), Role::Color);
        textures.metallic_roughness = tex(pbr.metallic_roughness_texture().map(|i| i.texture()), Role::Data);
        let normal = m.normal_texture();
        if normal_ok {
            textures.normal = tex(normal.as_ref().map(|n| n.texture()), Role::Data);
        }
        let uvs = material_uvs(m, &label, &mut self.warnings);
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
        // The reflectance model: KHR_materials_unlit is `unlit` (the base colour as it is); a
        // mostly metallic material (metallic factor >= 0.5) is `metal`, whose highlight takes
        // the base colour; the rest `blinn-phong`.
        let brdf = if m.unlit() {
            Brdf::Unlit
        } else if metallic >= METAL_THRESHOLD {
            Brdf::Metal
        } else {
            Brdf::BlinnPhong
        };
        if brdf == Brdf::Unlit {
            // Unlit is the base colour as it is: a metallic-roughness map has nothing to say.
            textures.metallic_roughness = None;
        }
        let (diffuse, level, exponent) = if brdf == Brdf::Unlit {
            (base, 0.0, 1.0)
        } else if textures.metallic_roughness.is_some() {
            // Derived per pixel by the shader; keep the factors.
            (base, f0, 1.0)
        } else if brdf == Brdf::Metal {
            Material::metal_from_pbr(base, metallic, roughness, f0)
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
            uvs,
            brdf,
            distortion: self.distortion_of(m, &label),
            lightmap: self.lightmap_of(m, &label),
        };
        // Values the file controls: keep them finite and in range.
        let fix = |v: f32, lo: f32, hi: f32, default: f32| if v.is_finite() { v.clamp(lo, hi) } else { default };
        material.diffuse =
            Vec3::new(fix(diffuse.x, 0.0, 1.0, 0.8), fix(diffuse.y, 0.0, 1.0, 0.8), fix(diffuse.z, 0.0, 1.0, 0.8));
        material.emissive =
            Vec3::new(fix(emissive.x, 0.0, 1e4, 0.0), fix(emissive.y, 0.0, 1e4, 0.0), fix(emissive.z, 0.0, 1e4, 0.0));
        material.alpha = fix(a, 0.0, 1.0, 1.0);
        material.specular_exponent = fix(exponent, 1.0, 2048.0, 32.0);
        let most = crate::scene::max_specular_level(material.specular_exponent);
        material.specular_level = fix(level, 0.0, most, DIELECTRIC_F0);
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
}

/// The material's `extras` `{"lightmap": {"texture": i, "scale": s}}` as given: `None` without
/// a `lightmap` entry; `Some(None)` for a malformed one; else the texture's index in the file
/// and the scale (1 when absent).
fn lightmap_extras(m: &gltf::Material<'_>) -> Option<Option<(usize, f64)>> {
    let v: serde_json::Value = serde_json::from_str(m.extras().as_ref()?.get()).ok()?;
    let l = v.get("lightmap")?;
    let texture = l.get("texture").and_then(|t| t.as_u64());
    let scale = l.get("scale").map_or(Some(1.0), |s| s.as_f64());
    Some(texture.zip(scale).map(|(t, s)| (t as usize, s)))
}

impl Importer<'_> {
    /// Seed 004's lightmap from the material's `extras` (see [`lightmap_extras`]): read at
    /// TEXCOORD_1, linear. A malformed entry, a missing texture or a scale that is not a positive
    /// number is a warning and no lightmap.
    fn lightmap_of(&mut self, m: &gltf::Material<'_>, label: &str) -> Option<crate::scene::Lightmap> {
        let found = lightmap_extras(m)?.and_then(|(t, scale)| {
            let image = self.doc.textures().nth(t)?.source().index();
            let texture = *self.texture_slots.get(&(image, Role::Data))?;
            (scale.is_finite() && scale > 0.0 && scale < 1e6)
                .then_some(crate::scene::Lightmap { texture, scale: scale as f32 })
        });
        if found.is_none() {
            self.warnings.push(format!(
                "{label}: extras \"lightmap\" must be {{\"texture\": a readable texture's index, \"scale\": a positive number}}; no lightmap"
            ));
        }
        found
    }

    /// Seed 002's distortion strength from the material's `extras` (`{"distortion": k}`, k in
    /// [0, `MAX_DISTORTION`]); anything else there is a warning and no distortion.
    fn distortion_of(&mut self, m: &gltf::Material<'_>, label: &str) -> f32 {
        let Some(raw) = m.extras() else { return 0.0 };
        let Ok(serde_json::Value::Object(map)) = serde_json::from_str::<serde_json::Value>(raw.get()) else {
            return 0.0;
        };
        let Some(v) = map.get("distortion") else { return 0.0 };
        match v.as_f64().filter(|k| (0.0..=crate::scene::MAX_DISTORTION as f64).contains(k)) {
            Some(k) => k as f32,
            None => {
                self.warnings.push(format!(
                    "{label}: extras \"distortion\" must be a number from 0 to {}; no distortion",
                    crate::scene::MAX_DISTORTION
                ));
                0.0
            }
        }
    }

    /// Maps the renderer has no input for, said once per material rather than dropped.
    fn warn_unused_maps(&mut self, m: &gltf::Material<'_>, label: &str) {
        if m.occlusion_texture().is_some() {
            self.warnings.push(format!(
                "{label}: its occlusion map is not used (Lampshade has no ambient-occlusion input; ambient light is unoccluded)"
            ));
        }
        if let Some(spec) = m.specular() {
            if spec.specular_texture().is_some() || spec.specular_color_texture().is_some() {
                self.warnings.push(format!(
                    "{label}: its KHR_materials_specular textures are not used (the specular factors are)"
                ));
            }
        }
    }
}

/// A map's `KHR_texture_transform` as the file gives it: offset, rotation, scale, `texCoord`.
type FileTransform = ([f32; 2], f32, [f32; 2], Option<u32>);

/// Each map's texture coordinate set and `KHR_texture_transform`, with a warning for what
/// cannot be honoured (sets above 1, non-finite transforms).
pub(super) fn material_uvs(m: &gltf::Material<'_>, label: &str, warnings: &mut Vec<String>) -> MaterialUvs {
    let pbr = m.pbr_metallic_roughness();
    let from_info = |info: Option<gltf::texture::Info<'_>>| {
        info.map(|i| {
            let t = i.texture_transform();
            (i.tex_coord(), t.map(|t| (t.offset(), t.rotation(), t.scale(), t.tex_coord())))
        })
    };
    // The `gltf` crate keeps a normal texture's extensions as JSON.
    let normal = m.normal_texture().map(|n| {
        let t = n.extension_value("KHR_texture_transform").map(|v| {
            let pair = |key: &str, default: f32| -> [f32; 2] {
                let a = v.get(key).and_then(|a| a.as_array());
                let at = |k: usize| a.and_then(|a| a.get(k)).and_then(|x| x.as_f64()).map_or(default, |x| x as f32);
                [at(0), at(1)]
            };
            let rotation = v.get("rotation").and_then(|r| r.as_f64()).map_or(0.0, |r| r as f32);
            let set = v.get("texCoord").and_then(|c| c.as_u64()).map(|c| c.min(u32::MAX as u64) as u32);
            (pair("offset", 0.0), rotation, pair("scale", 1.0), set)
        });
        (n.tex_coord(), t)
    });
    let mut one = |what: &str, slot: Option<(u32, Option<FileTransform>)>| {
        let Some((tex_coord, transform)) = slot else { return UvTransform::default() };
        let mut t = UvTransform::default();
        let mut set = tex_coord;
        if let Some((offset, rotation, scale, over)) = transform {
            let candidate = UvTransform { set: 0, offset: offset.into(), rotation, scale: scale.into() };
            if candidate.rows().iter().flatten().all(|v| v.is_finite()) {
                t = candidate;
            } else {
                warnings.push(format!("{label}: the {what} map's KHR_texture_transform is not finite; ignored"));
            }
            set = over.unwrap_or(set);
        }
        if set > 1 {
            warnings
                .push(format!("{label}: the {what} map uses TEXCOORD_{set}; only sets 0 and 1 are read, it reads 0"));
            set = 0;
        }
        t.set = set;
        t
    };
    MaterialUvs {
        base_color: one("base colour", from_info(pbr.base_color_texture())),
        normal: one("normal", normal),
        emissive: one("emissive", from_info(m.emissive_texture())),
        metallic_roughness: one("metallic-roughness", from_info(pbr.metallic_roughness_texture())),
    }
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
