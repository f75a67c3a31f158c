//! Where calibrations are kept: one file per adapter in the user's cache folder
//! (`$XDG_CACHE_HOME/lampshade/`, else `~/.cache/lampshade/`), named by the adapter's key.
//!
//! The CLI and the viewer read it ([`resolve`]); the library and the test suite never do: a
//! `Renderer` uses the built-in defaults unless it is given a calibration. A calibration file
//! named explicitly (`--calibration FILE`, or [`ENV`]) is read instead of the cache.
//!
//! A cache file that is stale (another format version or another adapter's key) or corrupt is
//! a warning and the defaults, never an error; an explicitly named file that cannot be read is
//! an error.

use crate::renderer::options::calibration::{Calibration, CALIBRATION_VERSION};
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The environment variable naming a calibration file, as `--calibration` does.
pub const ENV: &str = "LAMPSHADE_CALIBRATION";

/// The key a calibration is measured under: the adapter's name, driver and driver info, and
/// for a CPU adapter (lavapipe's name is the same on every machine) the CPU's model and its
/// core count.
pub fn key(info: &wgpu::AdapterInfo) -> String {
    let mut k = format!("{} / {} / {}", info.name, info.driver, info.driver_info);
    if info.device_type == wgpu::DeviceType::Cpu {
        let (model, cores) = cpu();
        k += &format!(" / {model} / {cores} cores");
    }
    k
}

/// The CPU's model ("model name" in /proc/cpuinfo, else "unknown CPU") and its cores (the
/// processors /proc/cpuinfo lists, else those the process may use).
fn cpu() -> (String, usize) {
    let text = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = text
        .lines()
        .find_map(|l| {
            let (k, v) = l.split_once(':')?;
            (k.trim() == "model name").then(|| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let listed = text.lines().filter(|l| l.split(':').next().is_some_and(|k| k.trim() == "processor")).count();
    let cores = if listed > 0 { listed } else { std::thread::available_parallelism().map_or(1, |n| n.get()) };
    (model, cores)
}

/// The cache folder: `$XDG_CACHE_HOME/lampshade` (an absolute path), else
/// `$HOME/.cache/lampshade`; `None` without either.
pub fn cache_dir() -> Option<PathBuf> {
    let xdg = std::env::var_os("XDG_CACHE_HOME").map(PathBuf::from).filter(|p| p.is_absolute());
    let base = xdg.or_else(|| {
        std::env::var_os("HOME").map(PathBuf::from).filter(|p| p.is_absolute()).map(|h| h.join(".cache"))
    })?;
    Some(base.join("lampshade"))
}

/// The cache file of `key` in `dir`: `calibration-<the key's letters and digits>-<hash>.json`.
pub fn cache_file(dir: &Path, key: &str) -> PathBuf {
    keyed_file(dir, "calibration", key, "json")
}

/// `<prefix>-<the key's letters and digits>-<hash>.<ext>` in `dir`: one file per adapter key
/// (the calibration, the pipeline cache).
pub fn keyed_file(dir: &Path, prefix: &str, key: &str, ext: &str) -> PathBuf {
    let mut slug = String::new();
    for c in key.chars() {
        if c.is_ascii_alphanumeric() {
            slug.push(c.to_ascii_lowercase());
        } else if !slug.ends_with('-') {
            slug.push('-');
        }
    }
    let slug: String = slug.trim_matches('-').chars().take(80).collect();
    // FNV-1a over the whole key: two keys whose slugs agree still get two files.
    let hash = key.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ b as u64).wrapping_mul(0x0100_0000_01b3));
    dir.join(format!("{prefix}-{slug}-{hash:016x}.{ext}"))
}

/// Reads a calibration file: an error when it cannot be read, is not one, is of another
/// version or holds a cost that is not finite and at zero or above.
pub fn read(path: &Path) -> Result<Calibration> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let version =
        serde_json::from_str::<serde_json::Value>(&text).ok().and_then(|v| v.get("version").and_then(|v| v.as_u64()));
    if let Some(v) = version.filter(|v| *v != CALIBRATION_VERSION as u64) {
        bail!("{}: calibration format version {v}, this build reads {CALIBRATION_VERSION}", path.display());
    }
    let c: Calibration =
        serde_json::from_str(&text).with_context(|| format!("{} is not a calibration file", path.display()))?;
    c.costs.validate().map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    if c.key.is_empty() {
        bail!("{}: the calibration names no adapter key", path.display());
    }
    Ok(c)
}

/// Writes `c` to its cache file in `dir` (made if missing); returns the file.
pub fn write(dir: &Path, c: &Calibration) -> Result<PathBuf> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let path = cache_file(dir, &c.key);
    std::fs::write(&path, serde_json::to_string_pretty(c)?).with_context(|| format!("writing {}", path.display()))?;
    Ok(path)
}

/// The calibration the CLI and the viewer use on the adapter `info`: the file `explicit` names
/// (else the one [`ENV`] names), else the cache's file for the adapter's key, else the
/// built-in defaults. A stale or corrupt cache file is logged as a warning and gives the
/// defaults; an explicit file of another adapter is used with a warning.
pub fn resolve(info: &wgpu::AdapterInfo, explicit: Option<&Path>) -> Result<Calibration> {
    let key = key(info);
    let env = std::env::var_os(ENV).filter(|v| !v.is_empty()).map(PathBuf::from);
    if let Some(path) = explicit.map(Path::to_path_buf).or(env) {
        let c = read(&path).context("the calibration asked for")?;
        if c.key != key {
            log::warn!(
                "calibration {}: measured on '{}', not on this adapter ('{key}'); using it as asked",
                path.display(),
                c.key
            );
        }
        return Ok(c);
    }
    Ok(from_cache(&key))
}

/// The cache's calibration for `key`, or the defaults (a warning when its file is stale or
/// corrupt).
pub fn from_cache(key: &str) -> Calibration {
    let Some(dir) = cache_dir() else { return Calibration::builtin() };
    let path = cache_file(&dir, key);
    if !path.exists() {
        return Calibration::builtin();
    }
    match read(&path) {
        Ok(c) if c.key == key => c,
        Ok(c) => {
            log::warn!(
                "calibration cache {}: measured under another key ('{}'); using the built-in defaults \
                 (run `lampshade calibrate`)",
                path.display(),
                c.key
            );
            Calibration::builtin()
        }
        Err(e) => {
            log::warn!("calibration cache: {e:#}; using the built-in defaults (run `lampshade calibrate`)");
            Calibration::builtin()
        }
    }
}

/// Today's UTC date, `YYYY-MM-DD`.
pub fn today() -> String {
    let days = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs() / 86_400);
    // Howard Hinnant's civil_from_days.
    let z = days as i64 + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + if m <= 2 { 1 } else { 0 };
    format!("{y:04}-{m:02}-{d:02}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cpu_adapters_key_names_its_cpu_and_every_key_has_a_file_of_its_own() {
        let info = |device_type| wgpu::AdapterInfo {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            driver: "llvmpipe".into(),
            driver_info: "Mesa 22.3.6".into(),
            ..wgpu::AdapterInfo::new(device_type, wgpu::Backend::Vulkan)
        };
        let gpu = key(&info(wgpu::DeviceType::DiscreteGpu));
        assert_eq!(gpu, "llvmpipe (LLVM 15.0.6, 256 bits) / llvmpipe / Mesa 22.3.6");
        let cpu = key(&info(wgpu::DeviceType::Cpu));
        let (model, cores) = super::cpu();
        assert_eq!(cpu, format!("{gpu} / {model} / {cores} cores"));
        assert!(cores >= 1);
        let dir = Path::new("/cache");
        assert_ne!(cache_file(dir, &cpu), cache_file(dir, &gpu));
        // Keys whose letters and digits agree still get two files.
        assert_ne!(cache_file(dir, "a b"), cache_file(dir, "a-b"));
        assert!(cache_file(dir, &cpu).starts_with(dir));
        assert_eq!(today().len(), 10);
    }
}
