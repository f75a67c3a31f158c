//! The winit + egui viewer (placeholder until the viewer lands).
use anyhow::Result;

#[derive(clap::Args, Default, Clone)]
pub struct ViewArgs {
    #[arg(default_value = "demo")]
    pub scene: String,
}

pub fn run(_args: ViewArgs) -> Result<()> {
    anyhow::bail!("the viewer is not built yet; use `lampshade render`")
}
