//! The scene on the GPU: every mesh in one vertex and one index buffer, the material textures
//! and their bind groups, and each mesh's bounding sphere. Uploaded once per scene; `render`
//! notices a different scene by its fingerprint.

use super::materials::{self, DefaultTextures};
use super::plan::Draw;
use crate::scene::Scene;
use anyhow::{bail, Result};
use glam::{DVec3, Vec3};

pub struct SceneGpu {
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    /// Per object: index range and base vertex of its mesh.
    pub draws: Vec<(std::ops::Range<u32>, i32)>,
    /// Per mesh: bounding sphere (centre, radius) in model space.
    pub bounds: Vec<(DVec3, f64)>,
    /// Per material: its textures and sampler.
    pub materials: Vec<wgpu::BindGroup>,
    /// What was loaded, to notice a different scene.
    pub fingerprint: SceneFingerprint,
    /// The material textures' views, to rebuild the bind groups when the pipelines change.
    views: Vec<wgpu::TextureView>,
    _textures: Vec<wgpu::Texture>,
}

/// Enough of a scene to tell that `render` was handed a different one than was loaded.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFingerprint {
    name: String,
    meshes: usize,
    vertices: usize,
    objects: usize,
    materials: usize,
    textures: Vec<usize>,
}

impl SceneFingerprint {
    pub fn of(scene: &Scene) -> Self {
        Self {
            name: scene.name.clone(),
            meshes: scene.meshes.len(),
            vertices: scene.meshes.iter().map(|m| m.vertices.len()).sum(),
            objects: scene.objects.len(),
            materials: scene.materials.len(),
            textures: scene.textures.iter().map(|t| std::sync::Arc::as_ptr(t) as usize).collect(),
        }
    }
}

/// The material sampler and the 1x1 textures that stand in for absent maps.
pub struct MaterialDefaults {
    pub sampler: wgpu::Sampler,
    /// The sampler's anisotropy clamp (`Settings::anisotropy`).
    pub anisotropy: u16,
    pub textures: DefaultTextures,
}

impl MaterialDefaults {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        Self { sampler: Self::sampler(device, 1), anisotropy: 1, textures: DefaultTextures::new(device, queue) }
    }

    /// Trilinear, repeating, with up to `anisotropy` samples along a footprint's long axis
    /// (seed 002: "use aniso filtering during G-buffer pass"; 1 is plain trilinear).
    fn sampler(device: &wgpu::Device, anisotropy: u16) -> wgpu::Sampler {
        device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("material"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            anisotropy_clamp: anisotropy.clamp(1, 16),
            ..Default::default()
        })
    }

    /// Makes the sampler `anisotropy`'s; true when it changed (the material bind groups that
    /// hold the old one must be made again).
    pub fn set_anisotropy(&mut self, device: &wgpu::Device, anisotropy: u16) -> bool {
        if anisotropy == self.anisotropy {
            return false;
        }
        self.sampler = Self::sampler(device, anisotropy);
        self.anisotropy = anisotropy;
        true
    }
}

/// Each mesh's bounding sphere (model space), as the plans and the shadow plan read them.
pub fn mesh_bounds(scene: &crate::scene::Scene) -> Vec<(DVec3, f64)> {
    scene.meshes.iter().map(|m| bounding_sphere(&m.vertices)).collect()
}

/// Bounding sphere of a mesh's vertices: the box centre and the farthest vertex from it.
fn bounding_sphere(vertices: &[crate::scene::Vertex]) -> (DVec3, f64) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for v in vertices {
        let p = Vec3::from(v.position).as_dvec3();
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let centre = if lo.x <= hi.x { (lo + hi) * 0.5 } else { DVec3::ZERO };
    let radius = vertices.iter().map(|v| (Vec3::from(v.position).as_dvec3() - centre).length()).fold(0.0, f64::max);
    (centre, radius)
}

impl SceneGpu {
    /// Uploads the scene's meshes and textures, with material bind groups for `material_bgl`.
    pub fn upload(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &Scene,
        material_bgl: &wgpu::BindGroupLayout,
        (defaults, uploads): (&MaterialDefaults, &crate::renderer::kit::uploads::Uploads),
    ) -> Result<Self> {
        scene.validate().map_err(anyhow::Error::msg)?;
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        let mut ranges = Vec::new();
        for m in &scene.meshes {
            let base = vertices.len() as i32;
            let start = indices.len() as u32;
            vertices.extend_from_slice(&m.vertices);
            indices.extend_from_slice(&m.indices);
            ranges.push((start..indices.len() as u32, base));
        }
        if vertices.is_empty() {
            vertices.push(Default::default());
            indices.extend([0, 0, 0]);
        }
        let (vb, ib) = crate::renderer::kit::mesh_buffers(device, "scene", &vertices, &indices);
        let limit = device.limits().max_texture_dimension_2d;
        if let Some(t) = scene.textures.iter().find(|t| t.width > limit || t.height > limit) {
            bail!("texture {} is {}x{}, larger than this GPU's limit of {limit}", t.name, t.width, t.height);
        }
        let textures: Vec<wgpu::Texture> =
            scene.textures.iter().map(|t| uploads.texture(t, || materials::upload(device, queue, t))).collect();
        let views: Vec<wgpu::TextureView> = textures.iter().map(|t| t.create_view(&Default::default())).collect();
        let material_groups =
            materials::bind_groups(device, material_bgl, scene, &views, &defaults.textures, &defaults.sampler);
        Ok(Self {
            vertices: vb,
            indices: ib,
            draws: scene.objects.iter().map(|o| ranges[o.mesh].clone()).collect(),
            bounds: mesh_bounds(scene),
            materials: material_groups,
            fingerprint: SceneFingerprint::of(scene),
            views,
            _textures: textures,
        })
    }

    /// Material bind groups belong to a pipeline configuration's layout: rebuilds them for
    /// another one (the textures stay uploaded).
    pub fn rebind_materials(
        &mut self,
        device: &wgpu::Device,
        scene: &Scene,
        material_bgl: &wgpu::BindGroupLayout,
        defaults: &MaterialDefaults,
    ) {
        self.materials =
            materials::bind_groups(device, material_bgl, scene, &self.views, &defaults.textures, &defaults.sampler);
    }

    /// Draws `list`'s objects with their material bind groups (group 1), switching among
    /// `pipelines` as the list asks.
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, list: &[Draw], pipelines: &[crate::renderer::kit::RenderPipe]) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        let (mut pipe, mut mat) = (usize::MAX, usize::MAX);
        for &(i, p, m) in list {
            if p != pipe {
                pass.set_pipeline(&pipelines[p]);
                pipe = p;
            }
            if m != mat {
                if let Some(g) = self.materials.get(m) {
                    pass.set_bind_group(1, g, &[]);
                }
                mat = m;
            }
            let (range, base) = &self.draws[i];
            pass.draw_indexed(range.clone(), *base, i as u32..i as u32 + 1);
        }
    }
}
