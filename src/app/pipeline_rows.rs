//! The pipelines window's rows: each configuration the viewer has drawn or built, every
//! pipeline it declares with its compile time, and how it was built (`app::compiling`). Plain
//! data, read by the panels.

use crate::renderer::Settings;

/// One pipeline of a configuration: its label, its compile time and whether this build
/// compiled it (else it was compiled before, for another configuration or frame).
#[derive(Clone, Debug, serde::Serialize)]
pub struct PipelineTime {
    pub label: String,
    /// Milliseconds its creation took, where it is compiled.
    pub ms: Option<f64>,
    pub now: bool,
}

/// One configuration's build, as the pipelines panel lists it.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ConfigPipelines {
    pub config: String,
    /// `background`: built on the worker while the viewport drew another configuration;
    /// `frame`: compiled by the viewport's own frame, which waited for it.
    pub built_by: &'static str,
    /// Every pipeline the configuration declares, in the order its passes declare them.
    pub pipelines: Vec<PipelineTime>,
    /// Milliseconds of the build's pipeline creation (the sum over those it compiled).
    pub compile_ms: f64,
    /// Milliseconds of the warm-up draw on the second device (`None`: none was needed).
    pub warm_ms: Option<f64>,
    /// Milliseconds from the request to the set being ready.
    pub wall_ms: f64,
}

impl ConfigPipelines {
    /// From a declared set after its build; `now[i]`: this build compiled pipeline `i`.
    pub fn of(config: String, built_by: &'static str, declared: &crate::renderer::kit::Declared, now: &[bool]) -> Self {
        let pipelines: Vec<PipelineTime> = declared
            .timings()
            .into_iter()
            .enumerate()
            .map(|(i, (label, t))| PipelineTime {
                label,
                ms: t.map(|d| d.as_secs_f64() * 1e3),
                now: now.get(i).copied().unwrap_or(false),
            })
            .collect();
        let compile_ms = pipelines.iter().filter(|p| p.now).filter_map(|p| p.ms).sum();
        Self { config, built_by, pipelines, compile_ms, warm_ms: None, wall_ms: 0.0 }
    }

    /// Adds `more`'s pipelines (another part of the same configuration) to these.
    pub fn add(&mut self, more: ConfigPipelines) {
        self.compile_ms += more.compile_ms;
        self.pipelines.extend(more.pipelines);
    }

    /// Pipelines this build compiled.
    pub fn compiled(&self) -> usize {
        self.pipelines.iter().filter(|p| p.now).count()
    }
}

/// A configuration's short name: path, culling, layout, shadows, view, and the post chain
/// when it runs.
pub fn config_name(s: &Settings) -> String {
    let mut name = format!(
        "{} · {} · {} · shadows {} · {}",
        s.path.name(),
        s.culling.name(),
        s.layout.name(),
        s.shadows.name(),
        s.debug_view.name()
    );
    if crate::renderer::post::chain_active(s.debug_view, &s.post_options()) {
        name.push_str(" · post");
    }
    name
}

/// Keeps `built` in the pipelines panel's list: one row per configuration, its latest build
/// (a configuration found ready adds a row only when it has none).
pub fn remember(list: &mut Vec<ConfigPipelines>, built: ConfigPipelines) {
    /// Configurations the panel keeps, the oldest let go first.
    const KEPT: usize = 64;
    match list.iter().position(|c| c.config == built.config) {
        Some(_) if built.built_by == "earlier" => return,
        Some(i) => {
            list.remove(i);
        }
        None => {}
    }
    list.push(built);
    if list.len() > KEPT {
        list.remove(0);
    }
}
