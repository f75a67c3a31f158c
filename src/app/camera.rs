//! Seed 000's camera controls: WASD up/down/left/right, E/Q forward/back, Z/X rotate, arrows and
//! the left mouse button look around, Shift faster. Pure functions of the camera and the keys.

use crate::scene::Camera;
use glam::DVec3;
use winit::keyboard::KeyCode;

/// Radians per second for the arrow keys and Z/X.
pub const TURN_SPEED: f64 = 1.2;
/// Radians per logical pixel of mouse drag.
pub const DRAG_SPEED: f64 = 0.005;
pub const FAST: f64 = 4.0;
const MAX_PITCH: f64 = 1.55;

/// The bindings, as the help panel lists them.
pub const BINDINGS: &[(&str, &str)] = &[
    ("W / S", "move up / down"),
    ("A / D", "move left / right"),
    ("E / Q", "forward / back"),
    ("Z / X", "rotate about the view"),
    ("Arrows, drag", "look around"),
    ("Shift", "4x faster"),
    ("Space", "animate lights"),
    ("Click", "select a light"),
    ("F9", "record a camera path (again: stop, save)"),
    ("F10", "replay the camera path (again: stop)"),
    ("F11", "RenderDoc: capture the next frame"),
    ("F12", "screenshot + settings"),
    ("F1", "this help"),
];

/// Camera-relative up: right x forward.
pub fn up(c: &Camera) -> DVec3 {
    c.right().cross(c.forward())
}

/// The point the Z/X rotation turns around: where the view ray meets the ground (y = 0), or a
/// point 20 units ahead when it does not.
pub fn pivot(c: &Camera) -> DVec3 {
    let f = c.forward();
    if f.y < -0.05 {
        let t = -c.position.y / f.y;
        if t > 0.0 && t < c.far {
            return c.position + f * t;
        }
    }
    c.position + f * 20.0
}

/// Turns the camera around the vertical axis through `pivot(c)` by `angle` radians.
pub fn orbit(c: &mut Camera, angle: f64) {
    let p = pivot(c);
    let o = c.position - p;
    let (s, co) = angle.sin_cos();
    let o = DVec3::new(o.x * co + o.z * s, o.y, -o.x * s + o.z * co);
    c.position = p + o;
    c.yaw -= angle;
}

pub fn look(c: &mut Camera, dyaw: f64, dpitch: f64) {
    c.yaw = (c.yaw + dyaw).rem_euclid(std::f64::consts::TAU);
    c.pitch = (c.pitch + dpitch).clamp(-MAX_PITCH, MAX_PITCH);
}

/// Applies `dt` seconds of the held keys. Returns whether the camera moved.
pub fn apply_keys(c: &mut Camera, held: &dyn Fn(KeyCode) -> bool, speed: f64, dt: f64) -> bool {
    let axis = |plus: KeyCode, minus: KeyCode| (held(plus) as i32 - held(minus) as i32) as f64;
    let fast = if held(KeyCode::ShiftLeft) || held(KeyCode::ShiftRight) { FAST } else { 1.0 };
    let step = speed * fast * dt;
    let turn = TURN_SPEED * fast.sqrt() * dt;
    let mv = up(c) * axis(KeyCode::KeyW, KeyCode::KeyS)
        + c.right() * axis(KeyCode::KeyD, KeyCode::KeyA)
        + c.forward() * axis(KeyCode::KeyE, KeyCode::KeyQ);
    let rotate = axis(KeyCode::KeyX, KeyCode::KeyZ);
    let yaw = axis(KeyCode::ArrowRight, KeyCode::ArrowLeft);
    let pitch = axis(KeyCode::ArrowUp, KeyCode::ArrowDown);
    let moved = mv != DVec3::ZERO || rotate != 0.0 || yaw != 0.0 || pitch != 0.0;
    c.position += mv * step;
    if rotate != 0.0 {
        orbit(c, rotate * turn);
    }
    look(c, yaw * turn, pitch * turn);
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cam() -> Camera {
        Camera::looking_at(DVec3::new(0.0, 10.0, 20.0), DVec3::ZERO)
    }

    #[test]
    fn keys_move_along_the_camera_axes() {
        let only = |k: KeyCode| move |q: KeyCode| q == k;
        let mut c = cam();
        apply_keys(&mut c, &only(KeyCode::KeyE), 10.0, 0.5);
        assert!((c.position - (cam().position + cam().forward() * 5.0)).length() < 1e-9);
        let mut c = cam();
        apply_keys(&mut c, &only(KeyCode::KeyW), 10.0, 0.5);
        assert!(c.position.y > cam().position.y, "W moves up");
        let mut c = cam();
        apply_keys(&mut c, &only(KeyCode::KeyD), 10.0, 0.5);
        assert!(c.position.x > 0.0, "D moves right");
    }

    #[test]
    fn rotation_keeps_the_pivot_in_view() {
        let mut c = cam();
        let p = pivot(&c);
        orbit(&mut c, 0.7);
        let to_pivot = (p - c.position).normalize();
        assert!(to_pivot.dot(c.forward()) > 0.9999, "{to_pivot} vs {}", c.forward());
        assert!((pivot(&c) - p).length() < 1e-6);
    }
}
