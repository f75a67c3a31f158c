//! The pipeline cache cold against warm: creates the pipelines of a few configurations of
//! `demo` (`Renderer::build_pipelines`) on a device whose `wgpu::PipelineCache` is read from
//! FILE (empty when there is none) and written back after. Run it twice with the same FILE:
//! the first run is cold, the second warm.
//!
//! `cargo run --release --example pipecache -- FILE [ADAPTER]`

use lampshade::renderer::{CullingMode, RenderPath, Renderer, Settings, OUTPUT_FORMAT};
use lampshade::scene::builtin::{self, BuiltinOptions};

fn fail(msg: String) -> ! {
    eprintln!("pipecache: {msg}\nusage: pipecache FILE [ADAPTER]");
    std::process::exit(2);
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(file) = args.get(1).map(std::path::PathBuf::from) else { fail("no cache file given".into()) };
    let choice = lampshade::gpu::AdapterChoice { adapter: args.get(2).cloned(), ..Default::default() };
    let gpu = lampshade::Gpu::open(&choice).unwrap_or_else(|e| fail(format!("{e:#}")));
    let read = match lampshade::pipeline_cache::load_from(&gpu, &file) {
        Ok(Some(n)) => n,
        Ok(None) => fail(format!("{} has no pipeline cache", gpu.info.name)),
        Err(e) => fail(format!("{e:#}")),
    };
    let scene = builtin::build("demo", BuiltinOptions::default()).unwrap_or_else(|e| fail(e));
    let base = Settings { count_ideal: false, ..Settings::default() };
    let configs = [
        ("volume", base.clone()),
        ("tiled", Settings { culling: CullingMode::Tiled, ..base.clone() }),
        ("light pre-pass", Settings { path: RenderPath::LightPrepass, ..base.clone() }),
        ("forward", Settings { path: RenderPath::Forward, ..base.clone() }),
    ];
    println!("{} ({:?}): cache {} bytes read from {}", gpu.info.name, gpu.info.backend, read, file.display());
    let mut total = 0.0;
    for (name, s) in configs {
        let mut r = Renderer::new(&gpu, OUTPUT_FORMAT, &s).unwrap_or_else(|e| fail(format!("{e:#}")));
        let t = std::time::Instant::now();
        let (declared, built) = r.build_pipelines(&scene, &s, (1280, 720)).unwrap_or_else(|e| fail(format!("{e:#}")));
        let ms = t.elapsed().as_secs_f64() * 1e3;
        total += ms;
        println!("{name}: {built} of {declared} pipelines created in {ms:.1} ms");
    }
    match lampshade::pipeline_cache::save_to(&gpu, &file) {
        Ok(Some(n)) => println!("all: {total:.1} ms; cache {n} bytes written"),
        Ok(None) => println!("all: {total:.1} ms; no cache data to write"),
        Err(e) => fail(format!("{e:#}")),
    }
}
