//! What the last frame kept, and the view of it the renderer hands out ([`Last`]): the
//! diagnostic tools (`tools/`: the probe, the explanation, brute force, the read-backs) take
//! this, never the renderer's internals.

use super::passes::Passes;
use crate::renderer::culling::plan::FramePlan;
use crate::renderer::culling::volumes::Volumes;
use crate::renderer::inputs::scratch::Scratch;
use crate::renderer::kit::adapter::AdapterCaps;
use crate::renderer::options::culling::CullingMode;
use crate::renderer::options::RenderPath;
use crate::renderer::records::{FrameBuffers, LightRecord};
use crate::renderer::settings::Settings;
use crate::renderer::shadows::ShadowPlan;
use crate::renderer::targets::Targets;
use crate::scene::Scene;
use anyhow::{bail, Result};
use glam::DMat4;
use std::sync::Arc;

/// What the last frame left for the probe, the wireframes and the viewer's panels.
#[derive(Default)]
pub struct LastFrame {
    /// The lights (view space) as the shaders saw them.
    pub lights: Vec<LightRecord>,
    /// The most ambient + sun could add to a channel (`overlap::clamps`).
    pub ambient_clamp: f32,
    /// World to view rotation (world-space G-buffer layouts are turned back with it).
    pub view_rotation: glam::DMat3,
    pub plan: FramePlan,
    /// The shadow tiles and who casts.
    pub shadows: ShadowPlan,
    /// The path it was drawn with: the forward paths leave no G-buffer to read (what the
    /// targets hold is an older frame's).
    pub path: RenderPath,
    /// The culling mode it was drawn with.
    pub mode: CullingMode,
    /// The projection it was drawn with (the probe unprojects depth with its inverse).
    pub proj: DMat4,
    /// World to view of that frame.
    pub view: DMat4,
    /// What the next frame may take as it is when its inputs are the same (`prepare`).
    pub reusable: Option<super::Reusable>,
}

impl LastFrame {
    /// What the probe, the wireframes and the panels read of a frame just drawn.
    pub fn new(scene: &Scene, settings: &Settings, prepared: super::Prepared) -> Self {
        let super::Prepared { records, plan, path_lists, shadows, key, .. } = prepared;
        LastFrame {
            view_rotation: scene.camera.rotation(),
            lights: records.lights,
            ambient_clamp: records.camera.light_clamp,
            plan,
            shadows,
            path: settings.path,
            mode: settings.culling,
            proj: records.proj,
            view: records.view,
            reusable: Some(super::Reusable { key, camera: records.camera, objects: records.objects, path_lists }),
        }
    }

    /// An error when the last frame left no G-buffer (`what` is what was asked for).
    pub fn gbuffer(&self, what: &str) -> Result<()> {
        if !self.path.keeps_gbuffer() {
            bail!("the {} path keeps no G-buffer: no {what} (use --path deferred or light-prepass)", self.path.name());
        }
        Ok(())
    }
}

/// The last frame as the renderer hands it out: its device, its pass
/// set, its targets and buffers, and what it kept. Read-only: a tool records and submits its
/// own work, and never changes what the next frame draws.
pub struct Last<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub caps: &'a AdapterCaps,
    /// The pass set the last frame drew with.
    pub passes: &'a Passes,
    /// Pass sets of recent other configurations this renderer keeps.
    pub pass_cache: &'a [Arc<Passes>],
    pub targets: &'a Option<Targets>,
    pub frame: &'a FrameBuffers,
    pub volumes: &'a Volumes,
    pub scratch: &'a Scratch,
    pub last: &'a LastFrame,
}
