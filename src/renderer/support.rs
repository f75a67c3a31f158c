//! What an adapter can give: each choice asked of the capability table (`kit::adapter`) before
//! any pipeline is built, for `lampshade adapters`, the viewer's choice boxes and the frame's
//! stats (`adapter.fallbacks`).

use super::kit::{self, gbuffer, PipelineKey};
use super::knobs::{Values, KNOBS};
use super::{post, DepthFormat, Settings, OUTPUT_FORMAT};
use anyhow::Result;

/// Whether `caps`' adapter can give `settings`: the other ways it takes (`fallbacks`), or why
/// it cannot. Asks only the table, so `lampshade adapters` and the viewer's choice boxes call it
/// for choices not yet made.
pub fn support(caps: &kit::adapter::AdapterCaps, settings: &Settings) -> Result<Vec<String>> {
    settings.validate().map_err(anyhow::Error::msg)?;
    let features = super::program::ShaderFeatures::of(None, settings, &caps.quirks);
    let key = super::key::pipeline_key(None, settings, settings.layout.layout(), caps, (OUTPUT_FORMAT, features))?;
    Ok(fallbacks(caps, &key, settings, true))
}

/// The other ways configuration `key` takes for what `caps`' adapter lacks, in words (the
/// stats' `adapter.fallbacks`; `chain`: the post chain runs).
pub(super) fn fallbacks(
    caps: &kit::adapter::AdapterCaps,
    key: &PipelineKey,
    settings: &Settings,
    chain: bool,
) -> Vec<String> {
    use kit::adapter::Occlusion;
    let mut v = Vec::new();
    if key.layout.targets.iter().any(|t| gbuffer::is_bits(t.format)) {
        v.push("the depth copy is R32Uint holding depth's bits (R32Float is not renderable; exact)".to_string());
    }
    if chain && key.post_format != post::POST_FORMAT {
        v.push(format!("the post chain runs in {:?} (Rgba32Float is not renderable)", key.post_format));
    }
    if settings.depth_format == DepthFormat::Depth32FloatStencil8
        && key.depth_format != wgpu::TextureFormat::Depth32FloatStencil8
    {
        v.push("depth is Depth24PlusStencil8 (no DEPTH32FLOAT_STENCIL8)".to_string());
    }
    if settings.depth_clamp && !key.depth_clamp {
        v.push("no depth clamp: light volumes crossing the far plane are drawn full-screen".to_string());
    }
    if settings.timestamps && !caps.has(wgpu::Features::TIMESTAMP_QUERY) {
        v.push("no per-pass GPU times (no timestamp queries)".to_string());
    }
    if settings.anisotropy > 1 && !caps.downlevel.contains(wgpu::DownlevelFlags::ANISOTROPIC_FILTERING) {
        v.push("textures are filtered trilinearly (no ANISOTROPIC_FILTERING)".to_string());
    }
    if (settings.count_fragments || settings.count_ideal) && caps.occlusion == Occlusion::Binary {
        v.push("no per-light pixel counts (occlusion queries say only 0 or 1)".to_string());
    }
    v
}

/// One value of one knob on an adapter.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Choice {
    pub knob: &'static str,
    pub value: String,
    /// `Ok`: the fallbacks it takes beyond the default configuration's; `Err`: why the adapter
    /// cannot give it.
    #[serde(serialize_with = "as_outcome")]
    pub outcome: Result<Vec<String>, String>,
}

fn as_outcome<S: serde::Serializer>(o: &Result<Vec<String>, String>, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut m = s.serialize_map(Some(1))?;
    match o {
        Ok(f) => m.serialize_entry("fallbacks", f)?,
        Err(e) => m.serialize_entry("refused", e)?,
    }
    m.end()
}

/// Every value of every choice and switch knob (paths, layouts, culling modes, formats, …)
/// from the default settings, asked of `caps`. Values the settings' own rules reject alone (a
/// knob that needs another set first) are left out.
pub fn choices(caps: &kit::adapter::AdapterCaps) -> Vec<Choice> {
    let base = Settings::default();
    let base_fallbacks = support(caps, &base).unwrap_or_default();
    let mut out = Vec::new();
    for k in KNOBS.iter().filter(|k| matches!(k.values, Values::Choice(_) | Values::Switch)) {
        for value in k.names() {
            let mut s = base.clone();
            if s.set(k.name, &value).is_err() {
                continue;
            }
            let outcome = support(caps, &s)
                .map(|f| f.into_iter().filter(|x| !base_fallbacks.contains(x)).collect())
                .map_err(|e| format!("{e:#}"));
            out.push(Choice { knob: k.name, value, outcome });
        }
    }
    out
}

/// Why `caps`' adapter cannot give knob `name` = `value` on top of `settings`, if it cannot
/// (the viewer's tooltip on a greyed-out choice).
pub fn refusal(caps: &kit::adapter::AdapterCaps, settings: &Settings, name: &str, value: &str) -> Option<String> {
    let mut s = settings.clone();
    s.set(name, value).ok()?;
    support(caps, &s).err().map(|e| format!("{e:#}"))
}
