//! The command line: every subcommand's arguments in one place. The renderer's knobs are not
//! listed here one by one: `RenderArgs` flattens [`KnobArgs`], which builds a flag per row of
//! the knob table.

use crate::renderer::knobs::KnobArgs;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Parses `WxH` with each side in `min ..= 8192`.
fn size_at_least(s: &str, min: u32, what: &str) -> Result<(u32, u32), String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("size '{s}' is not WxH"))?;
    let w: u32 = w.trim().parse().map_err(|_| format!("width '{w}' is not a number"))?;
    let h: u32 = h.trim().parse().map_err(|_| format!("height '{h}' is not a number"))?;
    if !(min..=8192).contains(&w) || !(min..=8192).contains(&h) {
        return Err(format!("{what} {w}x{h} must be between {min}x{min} and 8192x8192"));
    }
    Ok((w, h))
}

/// An image size, `WxH`, 1x1 to 8192x8192.
/// A pixel, `X,Y`.
pub fn pixel(s: &str) -> Result<(u32, u32), String> {
    let (x, y) = s.split_once(',').ok_or_else(|| format!("pixel '{s}' is not X,Y"))?;
    let parse = |v: &str| v.trim().parse::<u32>().map_err(|e| format!("pixel '{s}': '{v}': {e}"));
    Ok((parse(x)?, parse(y)?))
}

pub fn image_size(s: &str) -> Result<(u32, u32), String> {
    size_at_least(s, 1, "size")
}

/// A window size in logical pixels, `WxH`, 64x64 to 8192x8192.
pub fn window_size(s: &str) -> Result<(u32, u32), String> {
    size_at_least(s, 64, "window size")
}

#[derive(Parser)]
#[command(name = "lampshade", version, about = "A workbench for deferred shading with light-volume culling")]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand)]
pub enum Command {
    /// Render one frame headless to a PNG.
    Render(RenderArgs),
    /// Open the viewer (the default command).
    #[cfg(feature = "viewer")]
    View(ViewArgs),
    /// Sweep the knobs that trade speed for error; write CSV, markdown and a plot.
    Bench(BenchArgs),
    /// Two configurations of one scene side by side: both pictures, FLIP's map and an amplified
    /// difference of B against A, each side's GPU time per pass and its error against the
    /// bench's reference, and the lights whose cost changed most (markdown and JSON).
    Compare(CompareArgs),
    /// Hold every culling mode against brute force (every light at every pixel) on a scene, at
    /// its cameras and at cameras generated around it: missed light, extra light, the worst
    /// pixel and a difference image per mode (the forward paths: their light lists against
    /// themselves unculled). Exits 1 when any frame misses or adds light.
    Check(CheckArgs),
    /// Which path and culling mode is fastest for a scene, and up to how many lights each
    /// stays fastest: predicted from a cost model fitted on short calibration frames, then
    /// measured; prints prediction against measurement, writes advise.md, advise.json and a plot.
    Advise(AdviseArgs),
    /// Measure the cost model's constants on this adapter (per draw, per fragment, per listed
    /// pair, each list mode's full-screen passes) in under a minute, and keep them in the
    /// user's cache folder, where `render`, `advise`, `bench` and the viewer read them.
    Calibrate(CalibrateArgs),
    /// List the graphics adapters found and what each supports (paths, layouts, culling modes,
    /// knobs), from each adapter's capability table.
    Adapters(AdaptersArgs),
    /// List the built-in scenes.
    Scenes,
    /// Print the seed presets (`--preset`): what each sets, the seed's line behind each
    /// setting, and what the seed names that no knob gives yet (Markdown; docs/presets.md).
    Presets,
    /// Bake seed 004's lightmaps for a scene (ambient through occlusion, sun through
    /// visibility; `scene::lightmap`): writes DIR/lightmaps.json and a PNG per object, which
    /// `render --baked DIR` applies.
    Bake(BakeArgs),
    /// Regenerate the project's own glTF scene (assets/room) from code.
    MakeAssets {
        /// Output directory.
        #[arg(long, default_value = "assets/room")]
        out: PathBuf,
    },
}

/// Which adapter a command runs on.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct AdapterArgs {
    /// Graphics backend: vulkan, gl, metal or dx12 (default: WGPU_BACKEND, else Vulkan, Metal
    /// and DX12 headless, any in the viewer).
    #[arg(long, value_enum)]
    pub backend: Option<crate::gpu::Backend>,
    /// Adapter: its index in `lampshade adapters`' list or a part of its name (default: the
    /// backend's high-performance adapter).
    #[arg(long)]
    pub adapter: Option<String>,
    /// Mask the adapter's capability table to another adapter class's (gl: wgpu's GL backend
    /// on Mesa), to see what that class would render.
    #[arg(long, value_enum)]
    pub restrict: Option<crate::renderer::kit::adapter::Profile>,
}

impl AdapterArgs {
    pub fn choice(&self) -> crate::gpu::AdapterChoice {
        crate::gpu::AdapterChoice { backend: self.backend, adapter: self.adapter.clone(), restrict: self.restrict }
    }
}

#[derive(clap::Args)]
pub struct AdaptersArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Write each adapter's capability table and supported choices as JSON instead.
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Built-in scene name (see `lampshade scenes`) or a glTF file (.gltf, .glb); default
    /// `demo`, or the settings file's.
    pub scene: Option<String>,
    /// glTF without lights: add N x N point lights (the same as `--lights` N²).
    #[arg(long, conflicts_with = "lights")]
    pub light_grid: Option<u32>,
    /// Start from the file's viewpoint K (its cameras in order, then a framing view).
    #[arg(long)]
    pub viewpoint: Option<usize>,
    /// Apply the lightmaps `lampshade bake` wrote to DIR for this scene.
    #[arg(long)]
    pub baked: Option<PathBuf>,
    /// Output PNG.
    #[arg(long)]
    pub out: PathBuf,
    /// Image size, WxH (default 1280x720, or the settings file's).
    #[arg(long, value_parser = image_size)]
    pub size: Option<(u32, u32)>,
    /// Number of point lights: the demo's (default 1024), or those added to a glTF file that has
    /// none (default 64, over the model's surface; see docs/gltf.md).
    #[arg(long)]
    pub lights: Option<usize>,
    /// Animation time in seconds (default 0, or the settings file's).
    #[arg(long)]
    pub time: Option<f64>,
    /// The renderer's knobs, one flag per row of `renderer::knobs::KNOBS` (`--culling`,
    /// `--layout`, `--debug-view`, `--accumulation`, `--depth-format`, `--light-cutoff`, …).
    #[command(flatten)]
    pub knobs: KnobArgs,
    /// Restrict the stencil view to light K.
    #[arg(long)]
    pub light: Option<usize>,
    /// Count the ideal fragments too (a full-screen counting pass per light).
    #[arg(long)]
    pub ideal: bool,
    /// The light ledger, `on` or `off`: each light's evaluated pairs, wasted pairs (with
    /// `--ideal`) and cost in the stats. Default: on up to 4,096 lights, off above unless asked
    /// (its counters split the light pass's batched draws into a draw per light and add an
    /// atomic per pair in tiled and clustered; `bench --only ledger` measures what it costs).
    #[arg(long, value_parser = crate::renderer::knobs::parse_switch)]
    pub ledger: Option<bool>,
    /// Write the frame's statistics as JSON.
    #[arg(long)]
    pub stats: Option<PathBuf>,
    /// Explain pixel X,Y (from the top left): every light whose bounds cover it, what the
    /// culling did with it, what it adds and what zeroed it (deferred path and light
    /// pre-pass). Printed as a table; with `--stats`, also the JSON's `probe`.
    #[arg(long, value_parser = pixel)]
    pub probe: Option<(u32, u32)>,
    /// Start from a settings file (as the viewer's F12 screenshots write: renderer settings plus
    /// scene, lights, time, camera and size); flags override it.
    #[arg(long)]
    pub settings: Option<PathBuf>,
    #[command(flatten)]
    pub calibration: CalibrationArgs,
}

#[derive(clap::Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Built-in scene name (see `lampshade scenes`) or a glTF file (.gltf, .glb).
    pub scene: String,
    /// Side A: a settings file (as `render --settings` reads and the viewer's F12 writes).
    pub a: PathBuf,
    /// Side B: a settings file.
    pub b: PathBuf,
    /// Writes a.png, b.png, flip.png, difference.png, compare.md and compare.json here.
    #[arg(long)]
    pub out: PathBuf,
    /// Image size, WxH (default: the files' size, else 640x360).
    #[arg(long, value_parser = image_size)]
    pub size: Option<(u32, u32)>,
    /// Number of point lights (as `render --lights`; default: the files', else the scene's).
    #[arg(long)]
    pub lights: Option<usize>,
    /// Timed rounds, one frame of each side a round (their medians are reported), 1..=1000.
    #[arg(long, default_value_t = 5)]
    pub frames: usize,
    #[command(flatten)]
    pub calibration: CalibrationArgs,
}

#[derive(clap::Args)]
pub struct CheckArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Built-in scene name (see `lampshade scenes`) or a glTF file (.gltf, .glb).
    pub scene: String,
    /// Check only the file's viewpoint K (default: the scene's camera, each of its viewpoints
    /// and the generated cameras).
    #[arg(long)]
    pub viewpoint: Option<usize>,
    /// Number of point lights (as `render --lights`).
    #[arg(long)]
    pub lights: Option<usize>,
    /// Cameras generated around the scene's bounds (inside, at the edge and outside; from
    /// straight down to above the horizon; near planes down to a thousandth of the bounds).
    #[arg(long, default_value_t = 8)]
    pub cameras: usize,
    /// Image size, WxH.
    #[arg(long, value_parser = image_size, default_value = "160x90")]
    pub size: (u32, u32),
    /// Write check.json and, for each frame that misses or adds light, its difference image
    /// (red: light missing, blue: extra light; brighter the further past the rounding bound).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// The renderer's knobs (as `render`'s). `--culling` checks that mode alone, `--path` that
    /// path alone; by default every mode on the deferred path and the light pre-pass, and the
    /// forward paths' light lists against themselves unculled.
    #[command(flatten)]
    pub knobs: KnobArgs,
    /// The calibration `auto` decides with (so the check holds the choices `render` makes).
    #[command(flatten)]
    pub calibration: CalibrationArgs,
}

#[derive(clap::Args)]
pub struct AdviseArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Built-in scene name (see `lampshade scenes`) or a glTF file (.gltf, .glb).
    pub scene: String,
    /// The light counts to advise at: a built-in scene that takes a count is built with each;
    /// any other scene keeps that many of its lights, evenly strided (default: the scene's own
    /// count, or 64, 256, 1024 and 4096 for a scene that takes a count).
    #[arg(long, num_args = 1.., value_delimiter = ',')]
    pub lights: Vec<usize>,
    /// Image size, WxH.
    #[arg(long, value_parser = image_size, default_value = "640x360")]
    pub size: (u32, u32),
    /// Advise for the file's viewpoint K (its cameras in order, then a framing view) instead of
    /// the scene's camera.
    #[arg(long)]
    pub viewpoint: Option<usize>,
    /// Timed frames per calibration point, and interleaved rounds per measurement (one frame
    /// of each candidate a round); medians are taken, with their standard errors.
    #[arg(long, default_value_t = 5)]
    pub frames: usize,
    /// Write advise.md, advise.json and advise.png here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub calibration: CalibrationArgs,
    /// The renderer's knobs (as `render`'s), applied under every candidate's path and mode.
    #[command(flatten)]
    pub knobs: KnobArgs,
}

/// Which calibration a command weighs with.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct CalibrationArgs {
    /// The cost model's constants from FILE (as `calibrate --out` writes) instead of the
    /// cache's for this adapter (also: the environment variable LAMPSHADE_CALIBRATION).
    #[arg(long, value_name = "FILE")]
    pub calibration: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct CalibrateArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Frame size, WxH.
    #[arg(long, value_parser = image_size, default_value = "640x360")]
    pub size: (u32, u32),
    /// The light counts of `demo` measured (the two largest also at half the radii); `auto`
    /// weighs the list modes from the fewest of them up.
    #[arg(long, num_args = 1.., value_delimiter = ',', default_value = "64,256,1024,2048")]
    pub lights: Vec<usize>,
    /// Timed frames per point (their median is taken).
    #[arg(long, default_value_t = 5)]
    pub frames: usize,
    /// Write the calibration to FILE instead of the cache folder.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct BakeArgs {
    /// Built-in scene name or a glTF file (.gltf, .glb); objects whose mesh has a second
    /// texture coordinate set (the built-in cube has one) are baked.
    pub scene: String,
    /// Output directory.
    #[arg(long)]
    pub out: PathBuf,
    /// Texels along a cube face's cell (the map is 3N x 2N), 1..=256.
    #[arg(long, default_value_t = 16)]
    pub texels: u32,
    /// Occlusion rays per texel, 1..=4096.
    #[arg(long, default_value_t = 64)]
    pub rays: u32,
    /// How far an occluder may be and still shade the ambient (world units).
    #[arg(long, default_value_t = 4.0)]
    pub occlusion_distance: f64,
}

/// `--lights N` or `--light-grid N` (N² lights): the light count a scene is asked for, if any.
pub fn requested_lights(lights: Option<usize>, light_grid: Option<u32>) -> Option<usize> {
    lights.or(light_grid.map(|n| (n as usize) * (n as usize)))
}

#[derive(clap::Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Built-in scene name or a glTF file (.gltf, .glb).
    #[arg(default_value = "demo")]
    pub scene: String,
    /// Output directory for bench.csv, bench.md and bench.png.
    #[arg(long)]
    pub out: PathBuf,
    /// A short sweep (small size, fewer lights and frames), about a minute.
    #[arg(long)]
    pub quick: bool,
    /// Frames timed per configuration.
    #[arg(long)]
    pub frames: Option<usize>,
    #[arg(long, value_parser = image_size)]
    pub size: Option<(u32, u32)>,
    /// Number of point lights: a built-in scene's that takes a count (default 1024, or 256 with
    /// --quick), or those added to a glTF file that has none (default 64); the `lights` group
    /// varies it.
    #[arg(long)]
    pub lights: Option<usize>,
    /// glTF without lights: N x N point lights (the same as `--lights` N²).
    #[arg(long, conflicts_with = "lights")]
    pub light_grid: Option<u32>,
    /// Only these groups (comma-separated): culling, engines (the shortcuts engines ship: their caps
    /// and grids, each against the same frame uncapped), presets, near, materials, layout,
    /// accumulation, depth, cutoff, tessellation, resolution, lights, radius, ambient, forward,
    /// post, shadows, path; ledger (the per-light cost model fitted and checked by removing
    /// lights, per culling mode); and gbuffer (the G-buffer span split: an empty scene's clears,
    /// one triangle, the scene with and without timestamps and debug groups, a bare wgpu pass);
    /// and stochastic (run only when named: RIS and stochastic culling against the exact modes
    /// and the engines' caps over eleven layouts of their own, written to stochastic.md and
    /// stochastic.png).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,

    /// The `lights` group's light counts (comma-separated; default 64 to 100,000, or 16 and
    /// 1,024 with --quick; a glTF file's, 16 to 256)
    #[arg(long, value_delimiter = ',')]
    pub counts: Vec<usize>,
    #[command(flatten)]
    pub calibration: CalibrationArgs,
    /// With --only restir: write restir.md and restir.png from the rows of a run's restir.json
    /// (a run cut short writes it after each layout) instead of measuring.
    #[arg(long, value_name = "FILE")]
    pub restir_json: Option<PathBuf>,
    /// Replay the configurations along the camera path in FILE (as the viewer records it; see
    /// `assets/paths/`) instead of the sweep: per configuration the GPU frame time's p50, p95
    /// and p99, the worst frame and where on the path, and the flicker (mean FLIP between
    /// adjacent frames) beside the fastest exact mode's. Writes path.md and path.json.
    #[arg(long, value_name = "FILE")]
    pub camera_path: Option<PathBuf>,
    /// With --camera-path: seconds of path time a frame (default: the file's, else 1/60).
    #[arg(long, requires = "camera_path")]
    pub path_step: Option<f64>,
    /// With --camera-path: the culling modes replayed (comma-separated; default tiled,
    /// clustered and zbin).
    #[arg(long, value_delimiter = ',', requires = "camera_path")]
    pub modes: Vec<crate::renderer::CullingMode>,
}

#[derive(clap::Args, Clone, Debug)]
pub struct ViewArgs {
    #[command(flatten)]
    pub adapter: AdapterArgs,
    /// Built-in scene name (see `lampshade scenes`) or a glTF file (.gltf, .glb); default: the
    /// last one shown (saved state), else `demo`.
    pub scene: Option<String>,
    /// glTF without lights: add N x N point lights (the same as `--lights` N²).
    #[arg(long, conflicts_with = "lights")]
    pub light_grid: Option<u32>,
    /// Replay frame-numbered actions from FILE (see `src/app/script.rs`), e.g. in tests.
    #[arg(long)]
    pub script: Option<PathBuf>,
    /// Number of point lights: the demo's (default 1024), or those added to a glTF file that has
    /// none (default 64).
    #[arg(long)]
    pub lights: Option<usize>,
    /// Window size in logical pixels, WxH (default: the saved size, else 1280x720).
    #[arg(long, value_parser = window_size)]
    pub size: Option<(u32, u32)>,
    /// Share of the viewport's pixels the scene is rendered at (0.1..2; default: the saved
    /// scale, else 0.5).
    #[arg(long)]
    pub scale: Option<f32>,
    /// Exposure: a factor on the lit picture before tonemapping (the knob table's range).
    #[arg(long)]
    pub exposure: Option<f32>,
    /// Where F12 writes screenshots.
    #[arg(long, default_value = ".")]
    pub screenshot_dir: PathBuf,
    /// The viewer's saved state (window size, panels, scale, culling mode, layout, last scene):
    /// read at start, written on exit. Default: `<config dir>/lampshade/viewer.json`; scripted
    /// runs use none unless this is given.
    #[arg(long, conflicts_with = "no_state")]
    pub state: Option<PathBuf>,
    /// Neither read nor write the saved state.
    #[arg(long)]
    pub no_state: bool,
    /// Write one JSON line per presented frame to FILE: its wall and GPU time, the
    /// configuration drawn (and the one building meanwhile), and what it waited on (compile,
    /// read-back, calibration or nothing).
    #[arg(long, value_name = "FILE")]
    pub frame_log: Option<PathBuf>,
    /// Replay the camera path in FILE from the first frame (as F10 replays a recorded one:
    /// 1/60 s of path time a frame, looping; `assets/paths/` holds one per bench scene).
    #[arg(long, value_name = "FILE")]
    pub camera_path: Option<PathBuf>,
    #[command(flatten)]
    pub calibration: CalibrationArgs,
}

/// What `lampshade` with no subcommand runs: the same defaults as `lampshade view`.
impl Default for ViewArgs {
    fn default() -> Self {
        Self {
            adapter: AdapterArgs::default(),
            scene: None,
            light_grid: None,
            script: None,
            lights: None,
            size: None,
            scale: None,
            exposure: None,
            screenshot_dir: PathBuf::from("."),
            state: None,
            no_state: false,
            frame_log: None,
            camera_path: None,
            calibration: CalibrationArgs::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_view_is_the_view_command_without_arguments() {
        use clap::Parser;
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            view: ViewArgs,
        }
        let parsed = Cli::parse_from(["lampshade"]).view;
        let default = ViewArgs::default();
        assert_eq!(format!("{parsed:?}"), format!("{default:?}"));
    }

    #[test]
    fn the_bench_help_names_every_group() {
        use clap::CommandFactory;
        let cmd = Cli::command();
        let bench = cmd.find_subcommand("bench").expect("the bench command");
        let only = bench.get_arguments().find(|a| a.get_id() == "only").expect("--only");
        let help = only.get_help().map(|h| h.to_string()).unwrap_or_default();
        for g in crate::bench::GROUPS {
            assert!(help.contains(g), "`bench --only`'s help does not name the group {g}: {help}");
        }
    }
}
