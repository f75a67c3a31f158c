//! What the adapter can do, read once when the device is made: its optional features, its
//! downlevel flags, its limits, which formats it renders and blends, and the driver quirks the
//! shaders work around. Every path, layout, culling mode and knob asks this table, never the
//! adapter: a choice the adapter cannot give either takes another way (said once, in the log and
//! in the frame's stats) or is refused with the adapter's name and the capability it lacks.
//!
//! A [`Profile`] masks a real adapter's table down to another adapter class's (the GL backend's),
//! so that the fallbacks and refusals are tested on the machine at hand. The device is then made
//! with the masked features only, so wgpu's own validation catches a use of a masked feature;
//! the masked formats and downlevel flags are masked in the table only (wgpu still allows them).

use serde::{Deserialize, Serialize};
use wgpu::{DownlevelFlags as D, Features as F, TextureFormat as Tf};

/// The formats the renderer may ask for, whose renderability and blending the table records.
pub const FORMATS: &[Tf] = &[
    Tf::Rgba8Unorm,
    Tf::Bgra8Unorm,
    Tf::Rgba16Float,
    Tf::Rg16Float,
    Tf::R16Float,
    Tf::Rgba32Float,
    Tf::R32Float,
    Tf::R32Uint,
    Tf::Rg11b10Ufloat,
    Tf::Rg16Unorm,
    Tf::Rgb10a2Unorm,
];

/// A masked adapter class (tests and `--restrict`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum Profile {
    /// wgpu's GL backend on Mesa's llvmpipe (GL 4.5 through EGL), as measured on this project's
    /// machines: no pipeline statistics, no 32-bit float or Rg11b10 render targets, no read-only
    /// depth-stencil attachments, no depth copies to buffers, occlusion queries that only say
    /// 0 or 1.
    Gl,
}

impl Profile {
    /// The features this class lacks.
    pub fn missing_features(self) -> F {
        match self {
            Profile::Gl => {
                F::PIPELINE_STATISTICS_QUERY
                    | F::FLOAT32_BLENDABLE
                    | F::RG11B10UFLOAT_RENDERABLE
                    | F::SHADER_F16
                    | F::FLOAT32_FILTERABLE
            }
        }
    }

    /// The downlevel flags this class lacks.
    fn missing_downlevel(self) -> D {
        match self {
            Profile::Gl => {
                D::READ_ONLY_DEPTH_STENCIL
                    | D::DEPTH_TEXTURE_AND_BUFFER_COPIES
                    | D::WEBGPU_TEXTURE_FORMAT_SUPPORT
                    | D::FULL_DRAW_INDEX_UINT32
                    | D::DEPTH_BIAS_CLAMP
                    | D::VIEW_FORMATS
                    | D::SURFACE_VIEW_FORMATS
            }
        }
    }

    /// The formats this class cannot render to.
    fn unrenderable(self) -> &'static [Tf] {
        match self {
            Profile::Gl => &[Tf::R32Float, Tf::Rg32Float, Tf::Rgba32Float, Tf::Rg11b10Ufloat],
        }
    }
}

/// How exact the adapter's occlusion queries are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Occlusion {
    /// Sample counts (Vulkan, Metal, DX12).
    Exact,
    /// Only whether any sample passed (wgpu's GL backend: `GL_ANY_SAMPLES_PASSED`).
    Binary,
}

/// Driver quirks the shaders and the planner work around, each only where it is needed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Quirks {
    /// A shader invocation's loops end, silently, once they have run this many iterations
    /// between them: gallivm's loop limiter (Mesa's llvmpipe, under Vulkan as lavapipe and under
    /// GL). Lists longer than a loop may walk are split, paired or built on the CPU.
    pub loop_limit: Option<u64>,
    /// A storage-buffer load at a per-pixel index costs a loop over the SIMD lanes while a
    /// uniform load is one gather (gallivm), so the per-light loops read small scenes' lights
    /// from uniform arrays (the light planes).
    pub uniform_gathers: bool,
    /// `vkCmdBeginDebugUtilsLabelEXT` outside a pass crashes (lavapipe, Mesa 22.3.6): the
    /// frame's steps are not pushed as debug groups.
    pub no_encoder_debug_groups: bool,
    /// wgpu's GL backend guesses a texture's view dimension from its layer count, and takes a
    /// 6-layer texture for one cube: a cube array then holds at least two cubes (12 layers).
    pub cube_guess_by_layers: bool,
    /// gallivm compiles a pipeline's shaders to machine code at its first draw under each
    /// state, not when the pipeline is created (llvmpipe, under Vulkan and GL): 0.3-0.6 s for
    /// a configuration's first frame on `demo` against 50-110 ms to create its pipelines.
    /// Mesa's shader cache keeps that code on disk, so one draw on another device makes the
    /// first draw here a cache read (the viewer's background compiles).
    #[serde(default)]
    pub jit_on_first_draw: bool,
}

/// gallivm's loop limit: 65,535 iterations an invocation.
pub const GALLIVM_LOOP_LIMIT: u64 = 65_535;

impl Quirks {
    /// The quirks of the driver `info` names.
    pub fn of(info: &wgpu::AdapterInfo) -> Self {
        // lavapipe names its driver "llvmpipe"; GL names none, only the renderer string.
        let llvmpipe = info.driver == "llvmpipe" || info.name.starts_with("llvmpipe");
        let lavapipe = llvmpipe && info.backend == wgpu::Backend::Vulkan;
        Self {
            loop_limit: llvmpipe.then_some(GALLIVM_LOOP_LIMIT),
            uniform_gathers: llvmpipe,
            no_encoder_debug_groups: lavapipe,
            cube_guess_by_layers: info.backend == wgpu::Backend::Gl,
            jit_on_first_draw: llvmpipe,
        }
    }

    /// Host memory a compiled pipeline holds, an estimate for the pass pool's budget
    /// (`kit::pool`). gallivm JIT-compiles each pipeline's shaders to machine code on the host:
    /// the culling oracle's runner, 23 pipelines a pass set, peaked at 0.75 GB keeping 8 sets
    /// and 2.3 GB keeping 32, 2.8 MiB a pipeline (taken as 3 MiB). Other drivers keep their
    /// compiled code on the GPU or in small host allocations: 256 KiB.
    pub fn pipeline_bytes(&self) -> u64 {
        if self.uniform_gathers {
            3 << 20
        } else {
            256 << 10
        }
    }

    /// The fewest layers a cube array is made with.
    pub fn min_cube_layers(&self) -> u32 {
        if self.cube_guess_by_layers {
            12
        } else {
            6
        }
    }

    /// No workaround: what a hardware GPU's table says.
    pub const NONE: Quirks = Quirks {
        loop_limit: None,
        uniform_gathers: false,
        no_encoder_debug_groups: false,
        cube_guess_by_layers: false,
        jit_on_first_draw: false,
    };
}

/// One format's row of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FormatCaps {
    pub format: Tf,
    pub renderable: bool,
    pub blendable: bool,
    pub multisample_x4: bool,
}

impl FormatCaps {
    /// The row of `format` whose features are `f`, where the device has what rendering to it
    /// needs (`enabled`).
    fn of(format: Tf, f: &wgpu::TextureFormatFeatures, enabled: bool) -> Self {
        use wgpu::TextureFormatFeatureFlags as Fl;
        let renderable = enabled && f.allowed_usages.contains(wgpu::TextureUsages::RENDER_ATTACHMENT);
        FormatCaps {
            format,
            renderable,
            blendable: renderable && f.flags.contains(Fl::BLENDABLE),
            multisample_x4: renderable && f.flags.contains(Fl::MULTISAMPLE_X4),
        }
    }
}

/// The adapter a table was read from.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AdapterName {
    pub name: String,
    pub backend: String,
    pub device_type: String,
    pub driver: String,
    pub driver_info: String,
}

impl AdapterName {
    pub fn of(info: &wgpu::AdapterInfo) -> Self {
        Self {
            name: info.name.clone(),
            backend: backend_name(info.backend).to_string(),
            device_type: format!("{:?}", info.device_type),
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
        }
    }
}

impl std::fmt::Display for AdapterName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({})", self.name, self.backend)
    }
}

/// The backend's name as `--backend` takes it.
pub fn backend_name(b: wgpu::Backend) -> &'static str {
    match b {
        wgpu::Backend::Vulkan => "vulkan",
        wgpu::Backend::Gl => "gl",
        wgpu::Backend::Metal => "metal",
        wgpu::Backend::Dx12 => "dx12",
        wgpu::Backend::BrowserWebGpu => "webgpu",
        _ => "noop",
    }
}

/// The capability table.
#[derive(Clone, Debug)]
pub struct AdapterCaps {
    pub adapter: AdapterName,
    /// The adapter class the table was masked to, if any.
    pub profile: Option<Profile>,
    /// The optional features the device was made with.
    pub features: F,
    pub downlevel: D,
    /// The device's limits.
    pub limits: wgpu::Limits,
    pub formats: Vec<FormatCaps>,
    pub occlusion: Occlusion,
    pub quirks: Quirks,
}

/// What a row without which nothing renders says (`gpu::REQUIRED_DOWNLEVEL`).
const REQUIRED: &str = "required: the one shader module every pass is compiled from uses it; Lampshade does not start";

/// A named capability: a row of `lampshade adapters` and of the stats' `capabilities`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Row {
    pub name: &'static str,
    pub has: bool,
    /// What is done, or lost, without it.
    pub without: &'static str,
}

impl AdapterCaps {
    /// The table of `adapter`, whose device was made with `features`, masked to `profile`.
    pub fn read(adapter: &wgpu::Adapter, features: F, limits: wgpu::Limits, profile: Option<Profile>) -> Self {
        let info = adapter.get_info();
        let mut downlevel = adapter.get_downlevel_capabilities().flags;
        // Without TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES the device allows only what WebGPU
        // guarantees for its features, whatever the adapter could do.
        let specific = features.contains(F::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);
        let mut formats: Vec<FormatCaps> = FORMATS
            .iter()
            .map(|&format| {
                let f = if specific {
                    adapter.get_texture_format_features(format)
                } else {
                    format.guaranteed_format_features(features)
                };
                let mut needs = format.required_features();
                if format == Tf::Rg11b10Ufloat {
                    needs |= F::RG11B10UFLOAT_RENDERABLE;
                }
                FormatCaps::of(format, &f, features.contains(needs))
            })
            .collect();
        let mut occlusion = if info.backend == wgpu::Backend::Gl { Occlusion::Binary } else { Occlusion::Exact };
        if let Some(p) = profile {
            downlevel -= p.missing_downlevel();
            for f in formats.iter_mut().filter(|f| p.unrenderable().contains(&f.format)) {
                (f.renderable, f.blendable, f.multisample_x4) = (false, false, false);
            }
            occlusion = Occlusion::Binary;
        }
        let mut caps = Self {
            adapter: AdapterName::of(&info),
            profile,
            features: features - profile.map_or(F::empty(), Profile::missing_features),
            downlevel,
            limits,
            formats,
            occlusion,
            quirks: Quirks::of(&info),
        };
        // Blending a float32 target needs the feature as well as the format's flag.
        if !caps.features.contains(F::FLOAT32_BLENDABLE) {
            for f in caps.formats.iter_mut().filter(|f| matches!(f.format, Tf::R32Float | Tf::Rgba32Float)) {
                f.blendable = false;
            }
        }
        caps
    }

    /// `format`'s row: the table's, or for formats outside [`FORMATS`] what WebGPU guarantees.
    fn format(&self, format: Tf) -> FormatCaps {
        match self.formats.iter().find(|f| f.format == format) {
            Some(f) => *f,
            None => FormatCaps::of(format, &format.guaranteed_format_features(self.features), true),
        }
    }

    /// The adapter can render to `format`.
    pub fn renderable(&self, format: Tf) -> bool {
        self.format(format).renderable
    }

    /// The adapter can blend into `format`.
    pub fn blendable(&self, format: Tf) -> bool {
        self.format(format).blendable
    }

    /// The adapter renders `format` with 4 samples.
    pub fn multisample_x4(&self, format: Tf) -> bool {
        self.format(format).multisample_x4
    }

    pub fn has(&self, feature: F) -> bool {
        self.features.contains(feature)
    }

    pub fn has_downlevel(&self, flag: D) -> bool {
        self.downlevel.contains(flag)
    }

    /// `--shadow-cube array` can be given.
    pub fn cube_arrays(&self) -> bool {
        self.has_downlevel(D::CUBE_ARRAY_TEXTURES)
    }

    /// An error naming the adapter and what it lacks, for a choice that cannot be given.
    pub fn refuse(&self, choice: &str, lacks: &str, instead: &str) -> anyhow::Error {
        let profile = self.profile.map(|p| format!(" masked to the {p:?} profile")).unwrap_or_default();
        anyhow::anyhow!("{choice} needs {lacks}, which {}{profile} lacks; {instead}", self.adapter)
    }

    /// The named rows, in the order `lampshade adapters` prints them.
    pub fn rows(&self) -> Vec<Row> {
        let r = |name, has, without| Row { name, has, without };
        vec![
            r(
                "storage buffers in vertex and fragment shaders",
                self.has_downlevel(D::VERTEX_STORAGE | D::FRAGMENT_STORAGE),
                REQUIRED,
            ),
            r("writable storage in fragment shaders", self.has_downlevel(D::FRAGMENT_WRITABLE_STORAGE), REQUIRED),
            r("compute shaders", self.has_downlevel(D::COMPUTE_SHADERS), REQUIRED),
            r("cube-array textures", self.cube_arrays(), REQUIRED),
            r(
                "indirect draws",
                self.has_downlevel(D::INDIRECT_EXECUTION),
                "not used: every draw's count is known on the CPU",
            ),
            r(
                "depth clamp",
                self.has(F::DEPTH_CLIP_CONTROL),
                "light volumes crossing the far plane are drawn full-screen",
            ),
            r(
                "read-only depth-stencil attachments",
                self.has_downlevel(D::READ_ONLY_DEPTH_STENCIL),
                "--depth-read buffer keeps the G-buffer's depth copy",
            ),
            r(
                "depth copies to buffers",
                self.has_downlevel(D::DEPTH_TEXTURE_AND_BUFFER_COPIES),
                "not used: depth is read back from the depth copy",
            ),
            r("Depth32FloatStencil8", self.has(F::DEPTH32FLOAT_STENCIL8), "depth is Depth24PlusStencil8"),
            r(
                "R32Float render targets",
                self.renderable(Tf::R32Float),
                "the depth copy is R32Uint holding depth's bits (exact)",
            ),
            r(
                "Rgba32Float render targets",
                self.renderable(Tf::Rgba32Float),
                "the post chain runs in Rgba16Float; the reference layout is refused",
            ),
            r("Rgba32Float blending", self.blendable(Tf::Rgba32Float), "--accumulation rgba32-float is refused"),
            r(
                "Rg11b10Ufloat render targets",
                self.renderable(Tf::Rg11b10Ufloat),
                "--accumulation rg11b10-ufloat is refused",
            ),
            r("Rg16Unorm render targets", self.renderable(Tf::Rg16Unorm), "the oct16 layout is refused"),
            r("timestamp queries", self.has(F::TIMESTAMP_QUERY), "per-pass GPU times are not reported"),
            r("timestamps inside passes", self.has(F::TIMESTAMP_QUERY_INSIDE_PASSES), "no per-light-batch times"),
            r(
                "exact occlusion queries",
                self.occlusion == Occlusion::Exact,
                "pixels shaded per light are not counted (only 0 or 1)",
            ),
            r(
                "pipeline-statistics queries",
                self.has(F::PIPELINE_STATISTICS_QUERY),
                "rasterised light-volume coverage is not reported",
            ),
        ]
    }

    /// The table as the stats JSON carries it, with the fallbacks a configuration took.
    pub fn report(&self, fallbacks: Vec<String>) -> CapsReport {
        let names = |keep: fn(&FormatCaps) -> bool| {
            self.formats.iter().filter(|f| keep(f)).map(|f| format!("{:?}", f.format)).collect()
        };
        CapsReport {
            adapter: self.adapter.clone(),
            profile: self.profile,
            capabilities: self.rows().into_iter().map(|r| (r.name.to_string(), r.has)).collect(),
            renderable: names(|f| f.renderable),
            blendable: names(|f| f.blendable),
            quirks: self.quirks,
            max_sampled_textures_per_stage: self.limits.max_sampled_textures_per_shader_stage,
            max_storage_buffers_per_stage: self.limits.max_storage_buffers_per_shader_stage,
            max_color_attachments: self.limits.max_color_attachments,
            max_color_attachment_bytes_per_sample: self.limits.max_color_attachment_bytes_per_sample,
            fallbacks,
        }
    }
}

/// [`AdapterCaps`] as the stats JSON (`adapter`) and `lampshade adapters --json` write it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CapsReport {
    /// Its fields (`name`, `backend`, …) at the report's top level.
    #[serde(flatten)]
    pub adapter: AdapterName,
    pub profile: Option<Profile>,
    /// [`AdapterCaps::rows`] by name.
    pub capabilities: std::collections::BTreeMap<String, bool>,
    /// Of [`FORMATS`], those the adapter renders to and blends into.
    pub renderable: Vec<String>,
    pub blendable: Vec<String>,
    pub quirks: Quirks,
    pub max_sampled_textures_per_stage: u32,
    pub max_storage_buffers_per_stage: u32,
    pub max_color_attachments: u32,
    pub max_color_attachment_bytes_per_sample: u32,
    /// The other ways this configuration took for what the adapter lacks.
    pub fallbacks: Vec<String>,
}

/// A feature's name as wgpu's flags print it (`PIPELINE_STATISTICS_QUERY`), not its debug struct.
pub fn feature_name(feature: F) -> String {
    format!("{feature}")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn info(name: &str, driver: &str, backend: wgpu::Backend) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: name.into(),
            vendor: 0,
            device: 0,
            device_type: wgpu::DeviceType::DiscreteGpu,
            device_pci_bus_id: String::new(),
            driver: driver.into(),
            driver_info: String::new(),
            backend,
            subgroup_min_size: 4,
            subgroup_max_size: 128,
            transient_saves_memory: None,
            limit_bucket: None,
        }
    }

    /// Each workaround is keyed to the driver that needs it: gallivm's loop limit and gathers
    /// to llvmpipe under either backend, the debug-group crash to lavapipe, the cube guess to
    /// wgpu's GL backend; a hardware GPU gets none.
    #[test]
    fn quirks_follow_the_driver_that_needs_them() {
        use wgpu::Backend::{Gl, Vulkan};
        let lavapipe = Quirks::of(&info("llvmpipe (LLVM 15.0.6, 256 bits)", "llvmpipe", Vulkan));
        let gl = Quirks::of(&info("llvmpipe (LLVM 15.0.6, 256 bits)", "", Gl));
        let nvidia = Quirks::of(&info("NVIDIA H100 80GB HBM3", "NVIDIA", Vulkan));
        let nvidia_gl = Quirks::of(&info("NVIDIA H100 80GB HBM3/PCIe/SSE2", "", Gl));
        assert_eq!(lavapipe.loop_limit, Some(GALLIVM_LOOP_LIMIT));
        assert!(lavapipe.uniform_gathers && lavapipe.no_encoder_debug_groups && !lavapipe.cube_guess_by_layers);
        assert!(gl.loop_limit.is_some() && gl.uniform_gathers && !gl.no_encoder_debug_groups);
        assert_eq!((gl.min_cube_layers(), lavapipe.min_cube_layers()), (12, 6));
        assert_eq!(nvidia, Quirks::NONE);
        assert_eq!(nvidia_gl, Quirks { cube_guess_by_layers: true, ..Quirks::NONE });
    }
}
