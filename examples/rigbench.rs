//! The default light rig of a file without lights against the dome it replaced, on the same
//! files in the same run: `cargo run --release --example rigbench -- FILE... [--lights N]
//! [--size WxH] [--rounds R]`. For each file, from its framing view, with each rig: the
//! shaded fragments (occlusion counts), the model's mean 8-bit luma with the sun and ambient
//! (as the viewer shows it), the share of the model's pixels that the point lights alone raise
//! above 2 of 255 (coverage), and GPU milliseconds of a frame, the rigs rendered in turn for
//! `R` rounds (medians). The dome is kept here only as the baseline: 64 lights on a Fibonacci
//! spiral over the ellipsoid through the bounds' corners (+15%), from straight above to 0.35
//! below the horizon, each reaching 1.25× its distance to the centre, normalised over 4,096
//! vertices as the rig is.

use glam::{DVec3, Vec3};
use lampshade::headless::render_image;
use lampshade::renderer::{DebugView, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::import::{self, lighting, ImportOptions};
use lampshade::scene::{Light, Scene};

/// The dome the surface rig replaced: (position, radius) of `count` lights for bounds lo..hi.
fn dome(lo: DVec3, hi: DVec3, count: usize) -> Vec<(DVec3, f64)> {
    let centre = (lo + hi) * 0.5;
    let mut half = ((hi - lo) * 0.5).max(DVec3::splat(1e-3));
    let widest = half.x.max(half.z).max(half.y);
    half = half.max(DVec3::splat(widest * 0.1));
    half.y = half.y.max(0.25 * half.x.max(half.z));
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..count)
        .map(|k| {
            let t = (k as f64 + 0.5) / count as f64;
            let y = 1.0 - t * 1.35;
            let ring = (1.0 - y * y).max(0.0).sqrt();
            let a = golden * k as f64;
            let position = centre + DVec3::new(ring * a.cos(), y, ring * a.sin()) * half * (1.732_050_8 * 1.15);
            (position, (position - centre).length() * 1.25)
        })
        .collect()
}

/// `scene` with its point lights replaced by the dome's, coloured and normalised as the rig's.
fn with_dome(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    let (lo, hi) = s.bounds().unwrap();
    let colours: Vec<Vec3> =
        s.lights.iter().filter_map(|l| if let Light::Point(p) = l { Some(p.color) } else { None }).collect();
    let placed: Vec<(DVec3, f64, Vec3)> =
        dome(lo, hi, colours.len()).into_iter().zip(colours).map(|((p, r), c)| (p, r, c)).collect();
    let intensity =
        lighting::normalising_intensity(&lighting::sample_vertices(&s, lighting::IRRADIANCE_SAMPLES), &placed);
    s.set_lights(placed.into_iter().map(|l| lighting::default_light(l, intensity)).collect());
    s
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn luma(p: &image::Rgba<u8>) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}

struct Rig {
    name: &'static str,
    scene: Scene,
    renderer: Renderer,
    gpu_ms: Vec<f64>,
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut files, mut lights, mut size, mut rounds) = (Vec::new(), 64usize, (1280u32, 720u32), 5usize);
    let mut k = 0;
    while k < args.len() {
        match args[k].as_str() {
            "--lights" => (lights, k) = (args[k + 1].parse()?, k + 1),
            "--rounds" => (rounds, k) = (args[k + 1].parse()?, k + 1),
            "--size" => {
                let (w, h) = args[k + 1].split_once('x').ok_or_else(|| anyhow::anyhow!("--size WxH"))?;
                (size, k) = ((w.parse()?, h.parse()?), k + 1);
            }
            f => files.push(f.to_string()),
        }
        k += 1;
    }
    let gpu = lampshade::Gpu::headless()?;
    let (w, h) = size;
    let base = Settings { timestamps: true, ..Settings::default() };
    println!("{lights} lights, {w}x{h}, {rounds} rounds; GPU ms medians of uncounted frames");
    println!("| file | rig | shaded fragments | mean luma | coverage | GPU ms (lighting) | GPU ms (frame) |");
    println!("|---|---|---|---|---|---|---|");
    for file in &files {
        let options = ImportOptions { lights, ..ImportOptions::default() };
        let started = std::time::Instant::now();
        let imported = import::load(std::path::Path::new(file), &options, &mut |_| {})?;
        let load_ms = started.elapsed().as_secs_f64() * 1e3;
        let mut new = imported.scene;
        new.camera = new.viewpoints.last().unwrap().1;
        let started = std::time::Instant::now();
        let old = with_dome(&new);
        let dome_ms = started.elapsed().as_secs_f64() * 1e3;
        eprintln!("{file}: loaded with the surface rig in {load_ms:.0} ms; the dome took {dome_ms:.0} ms more");
        let mut rigs: Vec<Rig> = [("dome", old), ("surface", new)]
            .into_iter()
            .map(|(name, scene)| Rig {
                name,
                scene,
                renderer: Renderer::new(&gpu, OUTPUT_FORMAT, &base).unwrap(),
                gpu_ms: Vec::new(),
            })
            .collect();
        for _ in 0..rounds {
            for r in rigs.iter_mut() {
                let (_, st) = render_image(&gpu, &mut r.renderer, &r.scene, &base, w, h)?;
                r.gpu_ms.push(st.gpu_ms.lighting.unwrap_or(f64::NAN));
                r.gpu_ms.push(-st.gpu_ms.total.unwrap_or(f64::NAN));
            }
        }
        let stem = std::path::Path::new(file).file_stem().unwrap().to_string_lossy().to_string();
        for r in rigs.iter_mut() {
            let counted = Settings { count_fragments: true, ..base.clone() };
            let (lit, st) = render_image(&gpu, &mut r.renderer, &r.scene, &counted, w, h)?;
            let depth = Settings { debug_view: DebugView::Depth, ..base.clone() };
            let (mask, _) = render_image(&gpu, &mut r.renderer, &r.scene, &depth, w, h)?;
            let mut dark = r.scene.clone();
            dark.sun = None;
            dark.ambient = Vec3::ZERO;
            let (points_only, _) = render_image(&gpu, &mut r.renderer, &dark, &base, w, h)?;
            let (mut sum, mut model, mut covered) = (0.0, 0usize, 0usize);
            for (x, y, p) in lit.enumerate_pixels() {
                if mask.get_pixel(x, y).0[..3] != [0, 0, 0] {
                    model += 1;
                    sum += luma(p);
                    covered += (luma(points_only.get_pixel(x, y)) > 2.0) as usize;
                }
            }
            lit.save(format!("target/rigbench-{stem}-{}.png", r.name))?;
            let lighting: Vec<f64> = r.gpu_ms.iter().copied().filter(|&t| t >= 0.0).collect();
            let frame: Vec<f64> = r.gpu_ms.iter().copied().filter(|&t| t < 0.0).map(|t| -t).collect();
            println!(
                "| {stem} | {} | {} | {:.1} | {:.1}% | {:.1} | {:.1} |",
                r.name,
                st.shaded_fragments.unwrap_or(0),
                sum / model.max(1) as f64,
                100.0 * covered as f64 / model.max(1) as f64,
                median(lighting),
                median(frame)
            );
        }
    }
    Ok(())
}
