//! The light pre-pass's figures against deferred shading: per configuration the
//! median GPU ms per pass over interleaved rounds, draws, fragments per pass (a counted frame),
//! bytes per pixel of the intermediate targets, and FLIP against the bench's reference (every
//! light full-screen or as plain volumes, `reference` layout, f32 accumulation).
//! `cargo run --example prepassbench [SCENE] [WxH] [ROUNDS]` (default demo 640x360 5; SCENE may
//! be a glTF file).

use lampshade::compare::flip;
use lampshade::headless::render_image;
use lampshade::renderer::{
    AccumFormat, CullingMode, LayoutChoice, Msaa, RenderPath, Renderer, Settings, OUTPUT_FORMAT,
};

fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(|a, b| a.total_cmp(b));
    v.get(v.len() / 2).copied()
}

fn main() -> anyhow::Result<()> {
    let gpu = lampshade::Gpu::headless()?;
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).cloned().unwrap_or_else(|| "demo".into());
    let (w, h) = match args.get(2).and_then(|s| s.split_once('x')) {
        Some((a, b)) => (a.parse()?, b.parse()?),
        None => (640u32, 360u32),
    };
    let rounds: usize = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(5);
    let options = lampshade::scene::import::ImportOptions::default();
    let (scene, _) = lampshade::scene::open(&name, Default::default(), &options, &mut |_| {})?;
    let reference_settings = Settings {
        culling: lampshade::bench::reference_culling(scene.lights.len(), (w, h)),
        layout: LayoutChoice::Reference,
        accumulation: AccumFormat::Rgba32Float,
        count_fragments: false,
        ..Settings::default()
    };
    let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &reference_settings)?;
    let (reference, _) = render_image(&gpu, &mut r, &scene, &reference_settings, w, h)?;
    let configs: Vec<(&str, Settings)> = [
        ("deferred rgba16-float", RenderPath::Deferred, AccumFormat::Rgba16Float, Msaa::X1),
        ("light-prepass rgba16-float", RenderPath::LightPrepass, AccumFormat::Rgba16Float, Msaa::X1),
        ("light-prepass rgba8-log", RenderPath::LightPrepass, AccumFormat::Rgba8Log, Msaa::X1),
        ("light-prepass rgba16-float msaa 4", RenderPath::LightPrepass, AccumFormat::Rgba16Float, Msaa::X4),
    ]
    .into_iter()
    .map(|(label, path, accumulation, msaa)| {
        let culling = CullingMode::Volume;
        (label, Settings { path, accumulation, msaa, culling, timestamps: true, ..Settings::default() })
    })
    .collect();
    let mut renderers = Vec::new();
    for (_, s) in &configs {
        let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, s)?;
        render_image(&gpu, &mut r, &scene, s, w, h)?;
        renderers.push((r, Vec::new()));
    }
    for _ in 0..rounds {
        for ((_, s), (r, times)) in configs.iter().zip(renderers.iter_mut()) {
            let timed = Settings { count_fragments: false, ..s.clone() };
            times.push(render_image(&gpu, r, &scene, &timed, w, h)?.1);
        }
    }
    println!("{name} {w}x{h}, {} lights, volume culling, medians of {rounds} interleaved rounds", scene.lights.len());
    for ((label, s), (r, times)) in configs.iter().zip(renderers.iter_mut()) {
        let pick =
            |f: fn(&lampshade::renderer::FrameStats) -> Option<f64>| median(times.iter().filter_map(f).collect());
        let fmt = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
        let (image, stats) = render_image(&gpu, r, &scene, &Settings { count_fragments: true, ..s.clone() }, w, h)?;
        let (f, _) = flip(&reference, &image)?;
        println!("{label}:");
        println!(
            "  GPU ms: pass 1 / g-buffer {}, lights {}, pass 3 {}, compose/tonemap {}, total {}",
            fmt(pick(|s| s.gpu_ms.gbuffer)),
            fmt(pick(|s| s.gpu_ms.lighting)),
            fmt(pick(|s| s.gpu_ms.prepass_final)),
            fmt(pick(|s| s.gpu_ms.compose)),
            fmt(pick(|s| s.gpu_ms.total)),
        );
        println!(
            "  light draws {}, light fragments {}, FLIP mean {:.5}",
            stats.draw_calls,
            stats.shaded_fragments.unwrap_or(0),
            f.mean
        );
        match &stats.prepass {
            Some(p) => println!(
                "  pass 1 draws {} fragments {}, pass 3 draws {} fragments {} (samples); B/pixel: normal+exp {}, \
                 depth copy {}, light buffer {} ({}), HDR {}, MSAA colour+depth {}",
                p.base_draw_calls,
                p.base_fragments.unwrap_or(0),
                p.final_draw_calls,
                p.final_fragments.unwrap_or(0),
                p.normal_exp_bytes_per_pixel,
                p.depth_copy_bytes_per_pixel,
                p.light_buffer_bytes_per_pixel,
                p.light_buffer_format,
                p.hdr_bytes_per_pixel,
                p.msaa_bytes_per_pixel
            ),
            None => println!(
                "  G-buffer {} B/pixel ({}), accumulation 2 x {}",
                stats.gbuffer_bytes_per_pixel, stats.gbuffer_layout, stats.accumulation_format
            ),
        }
    }
    Ok(())
}
