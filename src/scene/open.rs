//! A scene by name: a built-in one, or a glTF file by path.

use super::{builtin, import, Scene};

/// The warning for a light count (`--lights`, `--light-grid`) that scene `name` does not take:
/// a glTF file with `lights_from_file` lights of its own, or a built-in scene with a fixed set.
/// `None` when the count is used or none was asked for.
pub fn unused_light_count(name: &str, requested: Option<usize>, lights_from_file: usize) -> Option<String> {
    let n = requested?;
    if import::is_gltf_path(name) {
        (lights_from_file > 0).then(|| {
            format!(
                "--lights {n} is not used: the file has {lights_from_file} light(s) of its own, and lights are added only to a file without any"
            )
        })
    } else {
        (!builtin::TAKES_LIGHT_COUNT.contains(&name)).then(|| {
            format!(
                "--lights {n} is not used: the built-in scene '{name}' has a fixed set of lights (a count is taken by {})",
                builtin::TAKES_LIGHT_COUNT.join(", ")
            )
        })
    }
}

/// A built-in scene by name, or a glTF file by path (`.gltf`/`.glb`). Returns the scene and the
/// loader's warnings (empty for built-in scenes).
pub fn open(
    name: &str,
    builtin: builtin::BuiltinOptions,
    options: &import::ImportOptions,
    progress: &mut dyn FnMut(import::Progress<'_>),
) -> anyhow::Result<(Scene, Vec<String>)> {
    if import::is_gltf_path(name) {
        // `--lights N` on a file: the number of lights added when it has none.
        let mut options = options.clone();
        if let Some(n) = builtin.lights {
            options.lights = n;
        }
        let imported = import::load(std::path::Path::new(name), &options, progress)?;
        log::info!("{name}: {:?}", imported.stats);
        let mut warnings = imported.warnings;
        warnings.extend(unused_light_count(name, builtin.lights, imported.stats.lights_from_file));
        Ok((imported.scene, warnings))
    } else {
        let warnings = unused_light_count(name, builtin.lights, 0).into_iter().collect();
        Ok((builtin::build(name, builtin).map_err(anyhow::Error::msg)?, warnings))
    }
}
