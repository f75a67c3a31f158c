//! Bevy's side of Lampshade's like-for-like frame comparison (`scripts/vs-bevy.sh`).
//!
//! It loads a glTF (the sphere wall of `../shared/peers/sphere_wall.py`, or the many-lights
//! layout of `many_lights.py` beside this crate), renders it from a still camera at the glTF's
//! origin looking down -Z (vertical field of view 45 degrees, as the glTF's camera), deferred or
//! forward, with Bevy's GPU light clustering on or off, HDR with the ACES tone curve (Bevy's `AcesFitted`), no MSAA,
//! no bloom, no shadows, no vsync, and prints each frame's raw wall delta to stdout:
//!
//! ```text
//! frame 61 wall_ms 183.402 gpu_clustering on
//! ```
//!
//! The delta is the time between two consecutive runs of the main schedule's `Last` stage, read
//! from `std::time::Instant` (not a smoothed diagnostic). With pipelined rendering the render
//! world draws frame N while the main world runs frame N+1, so in steady state the delta is the
//! slower of the two, as an app's frame is. After `--warmup` frames and `--frames` timed ones it
//! exits (writing a screenshot first if asked).

use bevy::camera::{Exposure, Hdr};
use bevy::core_pipeline::prepass::{DeferredPrepass, DepthPrepass};
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::light::cluster::GlobalClusterSettings;
use bevy::pbr::DefaultOpaqueRendererMethod;
use bevy::prelude::*;
use bevy::render::view::screenshot::{save_to_disk, Screenshot};
use bevy::render::view::Msaa;
use bevy::window::{PresentMode, WindowResolution};
use bevy::world_serialization::WorldAssetRoot;
use bevy::render::render_resource::PipelineCache;
use bevy::render::{Render, RenderApp, RenderSystems};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// The run, from the command line.
#[derive(Resource, Clone, Debug)]
struct Run {
    gltf: PathBuf,
    size: (u32, u32),
    deferred: bool,
    gpu_clustering: bool,
    warmup: u64,
    frames: u64,
    /// Where screenshots go (`PREFIX-frameK.png`) and at which frames (counted as `frame`,
    /// from the settled scene; default: the last timed frame).
    screenshot: Option<PathBuf>,
    screenshot_frames: Vec<u64>,
    /// The lights are hidden until this settled frame (`--lights-at K`), so that they enter
    /// a running app's clustering at once, as a camera turning toward them would bring them.
    lights_at: Option<u64>,
}

const USAGE: &str = "usage: lampshade-vs-bevy GLTF [--size WxH] [--method deferred|forward] \
[--gpu-clustering on|off] [--warmup N] [--frames N] [--lights-at K] \
[--screenshot PREFIX [--screenshot-frames K,K,..]]";

fn parse(args: &[String]) -> Result<Run, String> {
    let mut run = Run {
        gltf: PathBuf::new(),
        size: (1280, 720),
        deferred: true,
        gpu_clustering: true,
        warmup: 60,
        frames: 300,
        screenshot: None,
        screenshot_frames: Vec::new(),
        lights_at: None,
    };
    let mut gltf = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = |name: &str| it.next().cloned().ok_or_else(|| format!("{name} needs a value"));
        match a.as_str() {
            "--size" => {
                let v = value("--size")?;
                let (w, h) = v.split_once('x').ok_or_else(|| format!("--size '{v}' is not WxH"))?;
                let w: u32 = w.parse().map_err(|_| format!("--size '{v}': width is not a number"))?;
                let h: u32 = h.parse().map_err(|_| format!("--size '{v}': height is not a number"))?;
                if w == 0 || h == 0 || w > 8192 || h > 8192 {
                    return Err(format!("--size '{v}' is outside 1..=8192"));
                }
                run.size = (w, h);
            }
            "--method" => {
                run.deferred = match value("--method")?.as_str() {
                    "deferred" => true,
                    "forward" => false,
                    m => return Err(format!("--method '{m}': deferred or forward")),
                }
            }
            "--gpu-clustering" => {
                run.gpu_clustering = match value("--gpu-clustering")?.as_str() {
                    "on" => true,
                    "off" => false,
                    m => return Err(format!("--gpu-clustering '{m}': on or off")),
                }
            }
            "--warmup" => {
                let v = value("--warmup")?;
                run.warmup = v.parse().map_err(|_| format!("--warmup '{v}' is not a whole number"))?;
            }
            "--frames" => {
                let v = value("--frames")?;
                run.frames = v.parse().map_err(|_| format!("--frames '{v}' is not a whole number"))?;
                if run.frames == 0 {
                    return Err("--frames must be at least 1".into());
                }
            }
            "--lights-at" => {
                let v = value("--lights-at")?;
                run.lights_at = Some(v.parse().map_err(|_| format!("--lights-at '{v}' is not a whole number"))?);
            }
            "--screenshot" => run.screenshot = Some(PathBuf::from(value("--screenshot")?)),
            "--screenshot-frames" => {
                let v = value("--screenshot-frames")?;
                for k in v.split(',') {
                    let k: u64 = k.parse().map_err(|_| format!("--screenshot-frames '{v}' is not K,K,.."))?;
                    if k == 0 {
                        return Err("--screenshot-frames counts from 1".into());
                    }
                    run.screenshot_frames.push(k);
                }
            }
            "-h" | "--help" => return Err(USAGE.into()),
            s if s.starts_with("--") => return Err(format!("unknown option {s}\n{USAGE}")),
            s => {
                if gltf.replace(PathBuf::from(s)).is_some() {
                    return Err(format!("one glTF only\n{USAGE}"));
                }
            }
        }
    }
    run.gltf = gltf.ok_or_else(|| format!("no glTF given\n{USAGE}"))?;
    if !run.gltf.is_file() {
        return Err(format!("{} is not a file", run.gltf.display()));
    }
    Ok(run)
}

fn main() -> AppExit {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let run = match parse(&args) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("{e}");
            return AppExit::error();
        }
    };
    // Bevy's file source roots at `file_path`; an absolute folder makes the glTF's own.
    let gltf = match std::path::absolute(&run.gltf) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{}: {e}", run.gltf.display());
            return AppExit::error();
        }
    };
    let (folder, file) = match (gltf.parent(), gltf.file_name()) {
        (Some(d), Some(f)) => (d.to_string_lossy().into_owned(), f.to_string_lossy().into_owned()),
        _ => {
            eprintln!("{}: not a file path", gltf.display());
            return AppExit::error();
        }
    };
    let mut app = App::new();
    app.add_plugins(
        DefaultPlugins
            .set(WindowPlugin {
                primary_window: Some(Window {
                    title: "lampshade-vs-bevy".into(),
                    resolution: WindowResolution::new(run.size.0, run.size.1).with_scale_factor_override(1.0),
                    present_mode: PresentMode::AutoNoVsync,
                    resizable: false,
                    ..default()
                }),
                ..default()
            })
            .set(AssetPlugin { file_path: folder, ..default() }),
    );
    if run.deferred {
        app.insert_resource(DefaultOpaqueRendererMethod::deferred());
    } else {
        app.insert_resource(DefaultOpaqueRendererMethod::forward());
    }
    app.insert_resource(GlobalAmbientLight { color: Color::WHITE, brightness: 0.0, ..default() })
        .insert_resource(run.clone())
        .insert_resource(SceneFile(file))
        .insert_resource(Clock::default())
        .add_systems(Startup, (setup, clustering))
        .add_systems(Update, (no_shadows, show_lights))
        .add_systems(PostUpdate, quiet_gltf_cameras)
        .add_systems(Last, clock);
    let pending = Pending::default();
    app.insert_resource(pending.clone());
    if let Some(render) = app.get_sub_app_mut(RenderApp) {
        render.insert_resource(pending).add_systems(Render, count_pending.in_set(RenderSystems::Cleanup));
    }
    app.run()
}

#[derive(Resource)]
struct SceneFile(String);

/// Our camera: the only active one.
#[derive(Component)]
struct Ours;

fn setup(mut commands: Commands, assets: Res<AssetServer>, run: Res<Run>, file: Res<SceneFile>) {
    commands.spawn(WorldAssetRoot(assets.load(GltfAssetLabel::Scene(0).from_asset(file.0.clone()))));
    let mut camera = commands.spawn((
        Ours,
        Camera3d::default(),
        Projection::Perspective(PerspectiveProjection {
            fov: 45f32.to_radians(),
            near: 0.1,
            far: 200.0,
            ..default()
        }),
        Transform::IDENTITY,
        Hdr,
        Msaa::Off,
        // Lampshade's default curve is ACES too (Narkowicz's 2015 fit, in its compose pass).
        Tonemapping::AcesFitted,
        // A multiplier of 1 on the lit picture (Bevy's is 2^-ev100 / 1.2), as Lampshade's
        // exposure of 1.
        Exposure { ev100: -(1.2f32).log2() },
    ));
    if run.deferred {
        camera.insert((DepthPrepass, DeferredPrepass));
    }
}

/// GPU clustering is on wherever the adapter has compute shaders and storage buffers (Bevy's
/// `make_global_cluster_settings`); `--gpu-clustering off` takes it away, so Bevy clusters on
/// the CPU.
fn clustering(run: Res<Run>, mut settings: ResMut<GlobalClusterSettings>) {
    if !run.gpu_clustering {
        settings.gpu_clustering = None;
    }
}

/// The glTF's own camera would draw the scene a second time: it is switched off after the
/// scene spawner has made it (between `Update` and `PostUpdate`), before the frame extracts it.
/// Despawning it instead panics under the spawner.
fn quiet_gltf_cameras(mut cameras: Query<&mut Camera, Without<Ours>>) {
    for mut c in &mut cameras {
        if c.is_active {
            c.is_active = false;
        }
    }
}

/// glTF lights come without shadows already; this holds it whatever the loader's default.
/// Under `--lights-at` they are hidden as they arrive.
fn no_shadows(mut lights: Query<(&mut PointLight, &mut Visibility), Added<PointLight>>, run: Res<Run>) {
    for (mut l, mut v) in &mut lights {
        l.shadow_maps_enabled = false;
        if run.lights_at.is_some() {
            *v = Visibility::Hidden;
        }
    }
}

/// `--lights-at K`: the lights shown at settled frame K.
fn show_lights(mut lights: Query<&mut Visibility, With<PointLight>>, run: Res<Run>, clock: Res<Clock>) {
    if run.lights_at.is_some_and(|k| k == clock.frame) {
        for mut v in &mut lights {
            *v = Visibility::Inherited;
        }
    }
}

/// Pipelines the render world is still compiling, as its last frame saw them (Bevy draws an
/// entity only once its pipeline is ready, so frames before are not the scene's).
#[derive(Resource, Clone, Default)]
struct Pending(Arc<AtomicUsize>);

fn count_pending(cache: Res<PipelineCache>, pending: Res<Pending>) {
    pending.0.store(cache.waiting_pipelines().count(), Ordering::Relaxed);
}

/// Frames in a row with the scene loaded and no pipeline compiling before the timed frames
/// start counting (`frame` 1).
const SETTLE: u64 = 3;

#[derive(Resource, Default)]
struct Clock {
    /// App frames so far.
    app: u64,
    /// Frames since the scene settled (0 before).
    frame: u64,
    /// Settled frames in a row before `frame` starts.
    calm: u64,
    last: Option<Instant>,
    lights: usize,
    cameras: usize,
    pending: usize,
}

#[allow(clippy::too_many_arguments)]
fn clock(
    mut clock: ResMut<Clock>,
    run: Res<Run>,
    settings: Res<GlobalClusterSettings>,
    pending: Res<Pending>,
    lights: Query<(), With<PointLight>>,
    meshes: Query<(), With<Mesh3d>>,
    cameras: Query<&Camera>,
    mut commands: Commands,
    mut exit: MessageWriter<AppExit>,
) {
    let now = Instant::now();
    clock.app += 1;
    if let Some(last) = clock.last {
        let ms = now.duration_since(last).as_secs_f64() * 1e3;
        let on = if settings.gpu_clustering.is_some() { "on" } else { "off" };
        println!(
            "frame {} app {} wall_ms {ms:.3} gpu_clustering {on} lights {} cameras {} pending {}",
            clock.frame, clock.app, clock.lights, clock.cameras, clock.pending
        );
    }
    clock.last = Some(now);
    clock.lights = lights.iter().count();
    clock.cameras = cameras.iter().filter(|c| c.is_active).count();
    clock.pending = pending.0.load(Ordering::Relaxed);
    if clock.frame > 0 {
        clock.frame += 1;
    } else if !meshes.is_empty() && clock.pending == 0 {
        clock.calm += 1;
        if clock.calm >= SETTLE {
            clock.frame = 1;
        }
    } else {
        clock.calm = 0;
    }
    let last = run.warmup + run.frames;
    let shoot = match &run.screenshot_frames[..] {
        [] => clock.frame == last,
        frames => clock.frame > 0 && frames.contains(&clock.frame),
    };
    if let Some(prefix) = run.screenshot.as_ref().filter(|_| shoot) {
        let path = format!("{}-frame{}.png", prefix.display(), clock.frame);
        commands.spawn(Screenshot::primary_window()).observe(save_to_disk(path));
    }
    // The line of frame K is printed by the frame after (its delta ends there); a few frames
    // more for a screenshot to be written.
    if clock.frame > last + if run.screenshot.is_some() { 5 } else { 0 } {
        exit.write(AppExit::Success);
    }
}
