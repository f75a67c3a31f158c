#!/usr/bin/env python3
"""Writes assets/paths/*.json: one camera path for each of the built-in scenes the bench replays
(`lampshade bench SCENE --camera-path assets/paths/SCENE.json`). Each key is a camera at a time,
looking from a point at a target (as `Camera::looking_at`); between keys the viewer and the
bench follow a Catmull-Rom curve (`scene::camera_path`). Run from the repository root."""
import json, math, os

def cam(eye, target, fov=60.0, near=0.1, far=200.0):
    d = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(c * c for c in d))
    d = [c / n for c in d]
    return {"position": list(eye), "yaw": math.atan2(d[0], -d[2]) % math.tau,
            "pitch": math.asin(max(-1.0, min(1.0, d[1]))), "fov_y": math.radians(fov), "near": near, "far": far}

PATHS = {
    # Down from the opening view into the pillars and boxes at head height, through the light
    # field, and out again.
    "demo": [(0, (0, 14, 46), (0, 0, 4), dict(far=300)),
             (3, (10, 6, 26), (0, 2, 0), dict(far=300)),
             (6, (16, 2.5, 2), (-10, 2, -16), dict(far=300)),
             (9, (0, 3, -20), (-20, 2, 0), dict(far=300)),
             (12, (-20, 8, 20), (0, 0, 0), dict(far=300))],
    # A walk down the street among its lights, many of which the camera passes through (their
    # volumes cross the near plane), weaving between the pavements.
    "street": [(0, (0, 1.7, 0), (0.3, 1.2, -40), {}),
               (3, (-2.5, 1.7, -18), (0, 1.5, -60), {}),
               (6, (2, 2.2, -36), (-3, 1.5, -80), {}),
               (9, (-1, 1.7, -55), (4, 1.2, -95), {}),
               (12, (0.5, 1.7, -75), (0, 1.2, -110), {})],
    # From outside the light's volume into it, round its centre looking back, and out: the
    # volume crosses the near plane on the way in and out.
    "inside": [(0, (0, 2, 14), (0, 0.5, -4), {}),
               (3, (0, 1.5, 4), (0, 0.5, -4), {}),
               (6, (1.5, 1.0, 1.5), (-1, 0.8, 8), {}),
               (9, (-2, 2, 7), (0, 0.5, -4), {}),
               (12, (0, 3, 15), (0, 0.5, -4), {})],
    # From the centre of the lit sphere out toward its wall, along it through the lights'
    # reach (range 5 at radius 49), and back.
    "sphere-wall": [(0, (0, 0, 0), (0, 0, -1), {}),
                    (3, (0, 5, -30), (0, 8, -49), {}),
                    (6, (20, 10, -38), (30, 15, -40), {}),
                    (9, (38, 6, -20), (45, 0, 0), {}),
                    (12, (0, 0, 0), (1, 0, 0), {})],
    # Toward the railings, along them (among the lights hanging between the bars), and back:
    # the tiles' depth discontinuity moves across the screen.
    "railings": [(0, (0, 1.4, 2), (0, 1.4, -40), dict(far=100)),
                 (3, (-3, 1.6, -1), (2, 1.2, -40), dict(far=100)),
                 (6, (0, 2.4, -1.2), (-4, 1.5, -40), dict(far=100)),
                 (9, (3, 1.2, -0.8), (-2, 2, -40), dict(far=100)),
                 (12, (0, 1.4, 3), (0, 1.4, -40), dict(far=100))],
    # Bevy's many_lights layout: from the centre out to a metre from the wall, past its lights
    # of range 0.3, turning, and back.
    "many-lights": [(0, (0, 0, 0), (0, 0, -1), dict(fov=45)),
                    (3, (0, 0, -30), (0, 0, -49.9), dict(fov=45)),
                    (6, (10, 5, -47), (30, 15, -40), dict(fov=45)),
                    (9, (40, 8, -25), (49.9, 0, 0), dict(fov=45)),
                    (12, (0, 0, 0), (1, 0, 0), dict(fov=45))],
}

os.makedirs("assets/paths", exist_ok=True)
for scene, keys in PATHS.items():
    doc = {"scene": scene, "keys": [{"t": float(t), "camera": cam(e, g, **kw)} for t, e, g, kw in keys]}
    with open(f"assets/paths/{scene}.json", "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print(f"assets/paths/{scene}.json: {len(keys)} keys, {keys[-1][0]} s")
