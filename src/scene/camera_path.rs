//! Camera paths: timed camera keys, sampled at a fixed step of path time per frame.
//!
//! A path is a list of keys `(t, camera)` with strictly increasing times from 0. Between keys
//! the position and the angles follow a cubic Hermite curve whose tangents are the
//! Catmull-Rom tangents for uneven spacing, `(p[i+1] - p[i-1]) / (t[i+1] - t[i-1])` (zero at
//! the ends, so a path starts and stops at rest); the field of view and the near and far
//! planes are interpolated linearly (so they stay between their keys' values: a near plane is
//! never zero or negative). Yaw is unwrapped key to key before interpolating, so a turn through
//! 2π takes the short way.
//!
//! Replay never reads the wall clock: frame `n` is the camera at `t = n · step` (`step` 1/60 s
//! unless the file or the caller sets another), a pure function of the file, so frame `n` is the
//! same camera on every machine and at every frame time.
//!
//! The file is JSON: `{"scene": "demo", "step": 0.0166, "keys": [{"t": 0, "camera": {...}}]}`
//! (`scene` and `step` optional). Its text comes from the user: [`CameraPath::parse`] gives the
//! path or an error that says what is wrong, never a panic.

use super::Camera;
use anyhow::{bail, Context, Result};
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The path time one replayed frame advances by, unless the file or the caller says otherwise.
pub const DEFAULT_STEP: f64 = 1.0 / 60.0;
/// Most keys a path file may hold (an hour recorded at 60 keys a second is 216,000).
pub const MAX_KEYS: usize = 1 << 20;
/// Fewest frames a replay draws: a path shorter than this many steps is refused by the bench.
pub const MIN_BENCH_FRAMES: usize = 100;

/// One key of a path: the camera at path time `t` (seconds).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Key {
    pub t: f64,
    pub camera: Camera,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPath {
    /// The scene the path was recorded in (built-in name or file), if it says.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// Path time per replayed frame (default [`DEFAULT_STEP`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<f64>,
    pub keys: Vec<Key>,
}

impl CameraPath {
    /// Parses and checks a path file's text (see [`CameraPath::validate`]).
    pub fn parse(text: &str) -> Result<Self> {
        let path: CameraPath = serde_json::from_str(text).context("not a camera path (JSON with \"keys\")")?;
        path.validate()?;
        Ok(path)
    }

    pub fn load(file: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(file).with_context(|| format!("reading camera path {}", file.display()))?;
        Self::parse(&text).with_context(|| format!("camera path {}", file.display()))
    }

    pub fn save(&self, file: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self)?;
        std::fs::write(file, text).with_context(|| format!("writing camera path {}", file.display()))
    }

    /// At least one key; the first at t = 0; times finite and strictly increasing; every
    /// camera valid (`Camera::validate`); a step, if given, finite and in (0, 10] s.
    pub fn validate(&self) -> Result<()> {
        let Some(first) = self.keys.first() else { bail!("a camera path needs at least one key") };
        if self.keys.len() > MAX_KEYS {
            bail!("{} keys: a camera path holds at most {MAX_KEYS}", self.keys.len());
        }
        if first.t != 0.0 {
            bail!("the first key is at t = {}; a path starts at t = 0", first.t);
        }
        for (i, k) in self.keys.iter().enumerate() {
            if !k.t.is_finite() {
                bail!("key {i}: time {} is not finite", k.t);
            }
            if i > 0 && k.t <= self.keys[i - 1].t {
                bail!("key {i}: time {} does not come after key {}'s {}", k.t, i - 1, self.keys[i - 1].t);
            }
            k.camera.validate().map_err(|e| anyhow::anyhow!("key {i}: {e}"))?;
        }
        if let Some(s) = self.step {
            if !(s.is_finite() && s > 0.0 && s <= 10.0) {
                bail!("step {s} must lie in (0, 10] seconds");
            }
        }
        Ok(())
    }

    /// The path's length in seconds (its last key's time).
    pub fn duration(&self) -> f64 {
        self.keys.last().map_or(0.0, |k| k.t)
    }

    /// The step of path time per frame: `asked`, else the file's, else [`DEFAULT_STEP`].
    pub fn step(&self, asked: Option<f64>) -> f64 {
        asked.or(self.step).unwrap_or(DEFAULT_STEP)
    }

    /// Frames a replay at `step` draws: frame 0 at t = 0 up to the last frame at or before the
    /// end.
    pub fn frames(&self, step: f64) -> usize {
        // The small allowance keeps a path of 10 s at 1/60 s from losing its last frame to
        // rounding (600 · (1/60) is 10 in f64, but 10 / (1/60) is 599.99…).
        (self.duration() / step + 1e-9).floor() as usize + 1
    }

    /// Frame `n`'s camera at `step`: the path at t = n · step (clamped to the end).
    pub fn frame(&self, n: usize, step: f64) -> Camera {
        self.at(n as f64 * step)
    }

    /// The camera at path time `t` (before the start: the first key; after the end: the last).
    /// A path without keys (which `validate` refuses) stands at the origin looking down -Z.
    pub fn at(&self, t: f64) -> Camera {
        let keys = &self.keys;
        let Some(last) = keys.len().checked_sub(1) else {
            return Camera::looking_at(DVec3::ZERO, DVec3::NEG_Z);
        };
        if t <= 0.0 || last == 0 {
            return keys[0].camera;
        }
        if t >= keys[last].t {
            return keys[last].camera;
        }
        // The segment [i, i+1] holding t.
        let i = keys.partition_point(|k| k.t <= t) - 1;
        let (a, b) = (&keys[i], &keys[i + 1]);
        let h = b.t - a.t;
        let s = (t - a.t) / h;
        // Unwrapped angles (yaw, pitch) and positions of the four keys around the segment.
        let q = |k: usize| -> [f64; 5] {
            let c = keys[k].camera;
            [c.position.x, c.position.y, c.position.z, c.yaw, c.pitch]
        };
        let mut p = [q(i.saturating_sub(1)), q(i), q(i + 1), q((i + 2).min(last))];
        for j in 1..4 {
            p[j][3] = p[j - 1][3] + wrap(p[j][3] - p[j - 1][3]);
        }
        let t_at = |k: usize| keys[k].t;
        // Catmull-Rom tangents for uneven spacing; zero at the path's ends.
        let tangent = |k: usize, lo: usize, hi: usize| -> [f64; 5] {
            if k == 0 || k == last {
                return [0.0; 5];
            }
            let dt = t_at(k + 1) - t_at(k - 1);
            std::array::from_fn(|c| (p[hi][c] - p[lo][c]) / dt)
        };
        let (m0, m1) = (tangent(i, 0, 2), tangent(i + 1, 1, 3));
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2);
        let v: [f64; 5] = std::array::from_fn(|c| h00 * p[1][c] + h10 * h * m0[c] + h01 * p[2][c] + h11 * h * m1[c]);
        let lerp = |x: f64, y: f64| x + (y - x) * s;
        let (ca, cb) = (a.camera, b.camera);
        Camera {
            position: DVec3::new(v[0], v[1], v[2]),
            yaw: v[3].rem_euclid(std::f64::consts::TAU),
            // The curve may overshoot between keys: kept within the keys' own range.
            pitch: v[4].clamp(ca.pitch.min(cb.pitch) - 0.2, ca.pitch.max(cb.pitch) + 0.2).clamp(-1.55, 1.55),
            fov_y: lerp(ca.fov_y, cb.fov_y),
            near: lerp(ca.near, cb.near),
            far: lerp(ca.far, cb.far),
        }
    }
}

/// `a` wrapped into (-π, π].
fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let r = a.rem_euclid(t);
    if r > std::f64::consts::PI {
        r - t
    } else {
        r
    }
}

/// A path being replayed, looping: frame after frame of path time, from the start.
#[derive(Clone, Debug)]
pub struct Replay {
    pub path: CameraPath,
    pub step: f64,
    /// The frame drawn next.
    pub next: usize,
}

impl Replay {
    /// A replay at the path's own step ([`CameraPath::step`]).
    pub fn new(path: CameraPath) -> Self {
        let step = path.step(None);
        Self { path, step, next: 0 }
    }

    /// This frame's camera; moves on a frame (back to the start after the last).
    pub fn advance(&mut self) -> Camera {
        let frames = self.path.frames(self.step);
        let n = self.next % frames.max(1);
        self.next = n + 1;
        self.path.frame(n, self.step)
    }
}

/// Records a path as the viewer's camera moves: a key each time the camera changes, at the
/// path time `dt` by `dt` since the recording began (keys closer than a thousandth of a second
/// are merged into the later one).
#[derive(Clone, Debug, Default)]
pub struct Recorder {
    t: f64,
    keys: Vec<Key>,
}

impl Recorder {
    /// Starts a recording at `camera`.
    pub fn start(camera: Camera) -> Self {
        Self { t: 0.0, keys: vec![Key { t: 0.0, camera }] }
    }

    /// Advances the recording by `dt` seconds to `camera`.
    pub fn push(&mut self, dt: f64, camera: Camera) {
        if !(dt.is_finite() && dt > 0.0) || self.keys.len() >= MAX_KEYS {
            return;
        }
        self.t += dt;
        let n = self.keys.len();
        let still = n > 1 && self.keys[n - 1].camera == camera && self.keys[n - 2].camera == camera;
        let close = n > 1 && self.t - self.keys[n - 1].t < 1e-3;
        if still || close {
            // Still (or within a millisecond): the last key moves on instead of a new one.
            self.keys[n - 1] = Key { t: self.t, camera };
        } else {
            self.keys.push(Key { t: self.t, camera });
        }
    }

    /// Seconds recorded so far.
    pub fn seconds(&self) -> f64 {
        self.t
    }

    /// The recorded path (a single key when the recording never advanced).
    pub fn finish(self, scene: Option<String>) -> CameraPath {
        CameraPath { scene, step: None, keys: self.keys }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam(x: f64, yaw: f64) -> Camera {
        Camera { yaw, ..Camera::looking_at(DVec3::new(x, 2.0, 0.0), DVec3::new(x, 2.0, -1.0)) }
    }

    fn path() -> CameraPath {
        CameraPath {
            scene: None,
            step: None,
            keys: vec![
                Key { t: 0.0, camera: cam(0.0, 0.1) },
                Key { t: 1.0, camera: cam(4.0, 6.2) },
                Key { t: 3.0, camera: cam(5.0, 0.3) },
            ],
        }
    }

    #[test]
    fn the_path_passes_through_its_keys_and_rests_at_its_ends() {
        let p = path();
        for k in &p.keys {
            let c = p.at(k.t);
            assert!((c.position - k.camera.position).length() < 1e-12, "{c:?} at {}", k.t);
            assert!(wrap(c.yaw - k.camera.yaw).abs() < 1e-12);
        }
        // Zero tangent at the start: the first step moves less than a linear path would.
        let linear = 4.0 * 0.01;
        assert!(p.at(0.01).position.x < linear);
        assert_eq!(p.at(-1.0), p.keys[0].camera);
        assert_eq!(p.at(99.0), p.keys[2].camera);
    }

    #[test]
    fn yaw_takes_the_short_way_round() {
        // 0.1 to 6.2 rad is -0.183 rad the short way: halfway stays near 0, not near π.
        let y = path().at(0.5).yaw;
        assert!(wrap(y).abs() < 0.2, "yaw {y}");
    }

    #[test]
    fn frames_are_a_function_of_the_frame_number_only() {
        let p = path();
        assert_eq!(p.frames(DEFAULT_STEP), 181);
        let ten = CameraPath { keys: vec![p.keys[0], Key { t: 10.0, camera: cam(1.0, 0.0) }], ..p.clone() };
        assert_eq!(ten.frames(DEFAULT_STEP), 601);
        // The same frame however it is reached (no accumulated time).
        assert_eq!(p.frame(77, DEFAULT_STEP), p.at(77.0 * DEFAULT_STEP));
    }

    #[test]
    fn bad_files_are_errors_that_say_why() {
        for (text, needle) in [
            ("[]", "not a camera path"),
            (r#"{"keys": []}"#, "at least one key"),
            (r#"{"keys": [], "extra": 1}"#, "unknown field"),
            (
                r#"{"keys": [{"t": 1, "camera": {"position": [0,0,0], "yaw": 0, "pitch": 0, "fov_y": 1, "near": 0.1, "far": 10}}]}"#,
                "starts at t = 0",
            ),
            (
                r#"{"keys": [{"t": 0, "camera": {"position": [0,0,0], "yaw": 0, "pitch": 0, "fov_y": 1, "near": 0, "far": 10}}]}"#,
                "near",
            ),
            (
                r#"{"step": -1, "keys": [{"t": 0, "camera": {"position": [0,0,0], "yaw": 0, "pitch": 0, "fov_y": 1, "near": 0.1, "far": 10}}]}"#,
                "step",
            ),
        ] {
            let e = format!("{:#}", CameraPath::parse(text).expect_err(text));
            assert!(e.contains(needle), "{text}: {e}");
        }
        let mut p = path();
        p.keys[2].t = 1.0;
        assert!(format!("{:#}", p.validate().unwrap_err()).contains("does not come after"));
    }

    #[test]
    fn a_recording_keeps_its_moves_and_drops_its_pauses() {
        let mut r = Recorder::start(cam(0.0, 0.0));
        for i in 1..=10 {
            r.push(0.1, cam(i as f64, 0.0));
        }
        for _ in 0..50 {
            r.push(0.1, cam(10.0, 0.0));
        }
        let p = r.finish(Some("demo".into()));
        p.validate().unwrap();
        assert!((p.duration() - 6.0).abs() < 1e-9, "{}", p.duration());
        assert!(p.keys.len() <= 13, "{} keys for 10 moves and a pause", p.keys.len());
        assert!((p.at(0.5).position.x - 5.0).abs() < 1e-6);
    }
}
