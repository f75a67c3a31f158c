//! Writes the memory test's glTF: `cargo run --example heavy_gltf -- DIR [BOXES] [SIDE]` (8
//! boxes and 2048-pixel maps unless given), each box with its own material and base-colour,
//! normal and metal-roughness maps (`lampshade::scene::room::heavy`). The bench's peak memory on
//! it is measured in docs/measurements.md.

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let Some(dir) = args.next() else { anyhow::bail!("usage: heavy_gltf DIR [BOXES] [SIDE]") };
    let boxes: usize = args.next().map(|a| a.parse()).transpose()?.unwrap_or(8);
    let side: u32 = args.next().map(|a| a.parse()).transpose()?.unwrap_or(2048);
    let dir = std::path::PathBuf::from(dir);
    std::fs::create_dir_all(&dir)?;
    for (name, bytes) in lampshade::scene::room::heavy(boxes, side)? {
        std::fs::write(dir.join(name), bytes)?;
    }
    println!("{}", dir.join("heavy.gltf").display());
    Ok(())
}
