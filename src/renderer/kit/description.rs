//! What a pipeline is, as its descriptor says, kept beside the pipeline so a frame's declared
//! set can be shown and checked without compiling it: its stages, colour targets and blending,
//! its primitive state, its depth and stencil state and its sample count.

/// One declared pipeline's descriptor, owned (the wgpu types as the pipeline was created with).
#[derive(Clone, Debug, PartialEq)]
pub enum PipelineDescription {
    Render(RenderDescription),
    Compute { label: String, entry: String },
}

#[derive(Clone, Debug, PartialEq)]
pub struct RenderDescription {
    pub label: String,
    pub vertex: String,
    /// The fragment entry point; `None`: depth only.
    pub fragment: Option<String>,
    /// The colour targets, each slot as bound (`None`: an empty slot).
    pub targets: Vec<Option<wgpu::ColorTargetState>>,
    pub primitive: wgpu::PrimitiveState,
    pub depth_stencil: Option<wgpu::DepthStencilState>,
    pub samples: u32,
}

impl PipelineDescription {
    pub fn label(&self) -> &str {
        match self {
            PipelineDescription::Render(r) => &r.label,
            PipelineDescription::Compute { label, .. } => label,
        }
    }

    /// The render pipeline's description (`None` for a compute pipeline).
    pub fn render(&self) -> Option<&RenderDescription> {
        match self {
            PipelineDescription::Render(r) => Some(r),
            PipelineDescription::Compute { .. } => None,
        }
    }
}

impl RenderDescription {
    /// The colour targets bound (empty slots left out).
    pub fn colour_targets(&self) -> impl Iterator<Item = &wgpu::ColorTargetState> {
        self.targets.iter().flatten()
    }

    /// Whether the pipeline writes colour: a target with a write mask.
    pub fn writes_colour(&self) -> bool {
        self.fragment.is_some() && self.colour_targets().any(|t| !t.write_mask.is_empty())
    }

    /// Whether the depth test can fail (a depth-stencil state whose compare is not `Always`).
    pub fn depth_tested(&self) -> bool {
        self.depth_stencil.as_ref().is_some_and(|d| d.depth_compare != Some(wgpu::CompareFunction::Always))
    }

    /// Whether the pipeline writes or tests the stencil.
    pub fn uses_stencil(&self) -> bool {
        self.depth_stencil.as_ref().is_some_and(|d| d.stencil.is_enabled())
    }

    /// One line: label, stages, targets, cull, depth and stencil (the viewer's and `lampshade
    /// pipelines`' row).
    pub fn line(&self) -> String {
        let targets: Vec<String> = self
            .targets
            .iter()
            .map(|t| match t {
                Some(t) if t.write_mask.is_empty() => format!("{:?} (no writes)", t.format),
                Some(t) if t.blend.is_some() => format!("{:?} blended", t.format),
                Some(t) => format!("{:?}", t.format),
                None => "-".into(),
            })
            .collect();
        let depth = match &self.depth_stencil {
            None => "no depth".into(),
            Some(d) => {
                let write = if d.depth_write_enabled == Some(true) { ", written" } else { "" };
                let stencil = if d.stencil.is_enabled() {
                    let f = |s: &wgpu::StencilFaceState| {
                        format!(
                            "{:?} fail {:?} depth-fail {:?} pass {:?}",
                            s.compare, s.fail_op, s.depth_fail_op, s.pass_op
                        )
                    };
                    format!("; stencil front {}, back {}", f(&d.stencil.front), f(&d.stencil.back))
                } else {
                    String::new()
                };
                format!("depth {:?}{write}{stencil}", d.depth_compare.unwrap_or(wgpu::CompareFunction::Always))
            }
        };
        format!(
            "{}: {} / {}; targets [{}]; cull {:?}; {depth}; {} sample(s)",
            self.label,
            self.vertex,
            self.fragment.as_deref().unwrap_or("depth only"),
            targets.join(", "),
            self.primitive.cull_mode,
            self.samples
        )
    }
}
