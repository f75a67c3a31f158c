#!/usr/bin/env python3
"""Writes the seed corpora of the settings_file and viewer_script targets into
../corpus/settings_file and ../corpus/viewer_script (from this script): the project's own scripts
(tests/*.script), settings files shaped as the viewer's F12 and `lampshade render --settings`
read them, every script action, and the edge cases the parsers must reject or accept cleanly.
The regression inputs in ../../tests/data/fuzz-regressions/ of both targets are copied too."""
import glob, json, os

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.normpath(os.path.join(here, "..", ".."))
corpus = os.path.join(here, "..", "corpus")


def write(target, name, text):
    d = os.path.join(corpus, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(text.encode() if isinstance(text, str) else text)


# --- settings files -------------------------------------------------------------------------
settings = {
    "culling": "volume", "layout": "compact", "debug_view": "lit", "selected_light": None,
    "reversed_z": False, "exposure": 1.0, "count_fragments": True, "count_ideal": False,
    "timestamps": True, "accumulation": "rgba16-float", "depth_clamp": True,
    "depth_format": "depth32-float-stencil8", "light_cutoff": 0.0, "sphere_subdivisions": 1,
    "cone_sides": 12,
}
camera = {"position": [0.0, 3.5, 12.0], "yaw": 0.0, "pitch": -0.25, "fov_y": 0.9, "near": 0.05, "far": 200.0}
# As F12 writes it: the settings flattened, the scene keys, and the viewer's whole state.
f12 = dict(settings, scene="demo", lights=1024, time=0.0, camera=camera, size=[1000, 640],
           viewer={"scene": "demo", "lights": None, "time": 0.0, "animate": False, "time_speed": 1.0,
                   "settings": settings, "resolution_scale": 0.75, "selected_light": 3,
                   "scope": "All", "wireframes": "Off"})
write("settings_file", "f12-demo.json", json.dumps(f12, indent=2))
enums = [
    ("culling", ["fullscreen", "volume", "stencil-two-pass", "stencil-invert", "stencil-replace", "auto"]),
    ("layout", ["compact", "seed000", "packed", "reference", "fit", "oct8", "oct16", "xyz8", "xyz16f"]),
    ("debug_view", ["lit", "albedo", "normal", "depth", "specular", "emissive", "diffuse-light",
                    "specular-light", "stencil", "complexity"]),
    ("accumulation", ["rgba16-float", "rgba32-float", "rg11b10-ufloat", "rgba8-log"]),
    ("depth_format", ["depth32-float-stencil8", "depth24-plus-stencil8"]),
]
for k, values in enums:
    for v in values:
        write("settings_file", "%s-%s.json" % (k, v), json.dumps(dict(settings, **{k: v})))
# The file a pre-depth-format viewer wrote (renderer/settings.rs's test).
old = {k: settings[k] for k in ["culling", "layout", "debug_view", "selected_light", "reversed_z", "exposure",
                                 "count_fragments", "count_ideal", "timestamps", "accumulation", "depth_clamp"]}
write("settings_file", "old-viewer.json", json.dumps(old))
write("settings_file", "scene-keys-only.json", json.dumps({"scene": "spot", "time": 2.5, "size": [64, 48]}))
write("settings_file", "gltf-scene.json", json.dumps({"scene": "assets/room/room.gltf", "camera": camera}))
# `render --stats` output: the settings nested, not flattened (read as defaults + scene keys).
write("settings_file", "stats-output.json",
      json.dumps({"scene": "demo", "time": 0.0, "settings": settings, "size": [320, 180], "lights": 68}))
edge = {
    "empty-object.json": "{}",
    "empty.json": "",
    "not-object.json": "[1, 2, 3]",
    "nulls.json": json.dumps({k: None for k in list(settings) + ["scene", "lights", "time", "camera", "size"]}),
    "limits-ok.json": json.dumps(dict(settings, exposure=999999.0, light_cutoff=0.999999, sphere_subdivisions=4,
                                      cone_sides=64, size=[8192, 1], selected_light=18446744073709551615,
                                      lights=18446744073709551615, time=-1.7976931348623157e308)),
    "limits-bad.json": json.dumps(dict(settings, exposure=1e39, light_cutoff=1.0, sphere_subdivisions=4294967295,
                                       cone_sides=2, size=[8193, 0])),
    "negative.json": '{"cone_sides": -1, "lights": -5, "size": [-1, 2], "selected_light": -0}',
    "float-overflow.json": '{"time": 1e400, "exposure": -1e-400}',
    "camera-edges.json": json.dumps({"camera": dict(camera, fov_y=3.1405, near=1e-300, far=1.7976931348623157e308)}),
    "camera-bad.json": json.dumps({"camera": dict(camera, position=[0, 0]), "size": [1, 2, 3]}),
    "duplicate-keys.json": '{"exposure": 1, "exposure": 2}',
    "deep.json": '{"viewer": ' + "[" * 200 + "]" * 200 + "}",
    "unicode.json": '{"scene": "d\u00e9mo \U0001f600", "viewer": "\\ud83d", "time": 1}',
    "wrong-types.json": '{"reversed_z": "yes", "exposure": "1", "culling": 3, "camera": []}',
    "trailing.json": '{"exposure": 1} {"exposure": 2}',
}
for name, text in edge.items():
    write("settings_file", name, text)

# --- viewer scripts -------------------------------------------------------------------------
for p in glob.glob(os.path.join(root, "tests", "*.script")):
    write("viewer_script", os.path.basename(p), open(p, "rb").read())
every = """# every action of src/app/script.rs
0 key W
0 key f12
1 hold Shift 3
1 scene demo
1 scene model.glb
2 culling stencil-replace
2 view specular-light
2 layout packed
3 select 0
3 select none
3 scope selected
4 wireframes selected
4 wire-colour efficiency
4 wire-color light
5 tab materials
5 set exposure 2
5 set colour 1,0.2,0
5 set ambient #ff8000
5 set sun on
5 set light-cutoff 0.01
5 set cone-sides 24
5 set accumulation rgba8-log
5 set depth-format d24s8
6 hover 0 1
6 click 0.5 0.5
7 leave
7 resize 800 600
8 minimize
9 restore
10 screenshot out/a.png
10 screenshot /tmp/b.png
11 quit
"""
write("viewer_script", "every-action.script", every)
sets = ["lights 100", "scale 0.5", "exposure 1", "time 3", "speed -2", "move-speed 5", "animate off", "counts on",
        "ideal yes", "timestamps 0", "reversed-z true", "depth-clamp no", "accumulation rgba16-float",
        "radius-scale 2", "intensity-scale 0", "ambient 0.1,0.1,0.1", "sun off", "radius 3", "intensity 5",
        "colour #00ff00", "color 1,1,1", "inner 0.2", "outer 0.5", "sphere-subdivisions 4", "depth-format d32s8"]
write("viewer_script", "every-set.script", "0 select 0\n" + "".join("%d set %s\n" % (i + 1, s) for i, s in enumerate(sets)))
edge = {
    "huge-frames.script": "18446744073709551615 quit\n18446744073709551614 key W\n",
    "huge-hold.script": "1 hold W 18446744073709551615\n2 quit\n",
    "overflow-frame.script": "18446744073709551616 quit\n",
    "negative.script": "-1 quit\n1 select -1\n1 resize -800 600\n1 hold W -3\n",
    "floats.script": "1 hover NaN 0\n1 hover inf -inf\n1 click 1e-45 0.99999999\n1 set exposure NaN\n1 set time 1e308\n",
    "resize-edges.script": "1 resize 0 0\n1 resize 16384 16384\n1 resize 16385 1\n1 resize 4294967296 1\n",
    "paths.script": "1 screenshot /\n1 screenshot ..\n1 screenshot .\n1 screenshot a/../../b\n1 screenshot \u00e9\u00e8.png\n",
    "unknown.script": "1 jump\n1 set warp 9\n1 key Tab\n1 tab nowhere\n",
    "comments.script": "# only\n   # indented\n\t1\tquit\t# tabs\r\n2 key W#glued\r\n",
    "empty.script": "",
    "select-huge.script": "1 select 18446744073709551615\n1 select 99999999999999999999\n2 quit\n",
    "same-frame.script": "5 quit\n5 screenshot a.png\n5 key W\n0 key E\n5 hold W 1\n",
}
for name, text in edge.items():
    write("viewer_script", name, text)

# --- regression inputs ----------------------------------------------------------------------
regressions = os.path.join(root, "tests", "data", "fuzz-regressions")
for p in glob.glob(os.path.join(regressions, "settings-*")):
    write("settings_file", "regression-" + os.path.basename(p), open(p, "rb").read())
for p in glob.glob(os.path.join(regressions, "script-*")):
    write("viewer_script", "regression-" + os.path.basename(p), open(p, "rb").read())
for t in ["settings_file", "viewer_script"]:
    print("%s: %d seeds in %s" % (t, len(os.listdir(os.path.join(corpus, t))), os.path.normpath(os.path.join(corpus, t))))
