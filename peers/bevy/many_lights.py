"""Bevy's many_lights layout as Lampshade's built-in `many-lights` scene draws it, as a glTF that
both apps load (scripts/vs-bevy.sh): an inward-facing UV sphere of radius 50 (128 x 64 quads,
the poles' degenerate triangles left out), the camera at its centre looking down -Z with a
vertical field of view of 45 degrees, and N point lights of range 0.3 on a Fibonacci sphere of
radius 49.9 (0.1 inside the wall, in front of its flat faces).

The built-in scene's light colours come from its own hash; here they are drawn from a seeded
generator, as `../shared/peers/sphere_wall.py` draws its own. Nothing else differs.

usage: python3 many_lights.py N OUT.gltf
"""
import base64, json, math, random, struct, sys

n = int(sys.argv[1])
out = sys.argv[2]
SEGMENTS, RINGS, WALL, AT, RANGE, INTENSITY = 128, 64, 50.0, 49.9, 0.3, 2.0

pos, nrm, idx = [], [], []
for r in range(RINGS + 1):
    theta = math.pi * r / RINGS
    for s in range(SEGMENTS + 1):
        phi = 2 * math.pi * s / SEGMENTS
        p = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
        pos += [c * WALL for c in p]
        nrm += [-c for c in p]
row = SEGMENTS + 1
for r in range(RINGS):
    for s in range(SEGMENTS):
        a, b, c, d = r * row + s, r * row + s + 1, (r + 1) * row + s, (r + 1) * row + s + 1
        # Counter-clockwise seen from the centre.
        if r != 0:
            idx += [a, c, b]
        if r + 1 != RINGS:
            idx += [b, c, d]

rng = random.Random(1)
golden = math.pi * (3 - 5 ** 0.5)
lights, nodes = [], [{"mesh": 0}, {"camera": 0, "name": "centre"}]
for i in range(n):
    y = 1 - 2 * (i + 0.5) / n
    ring = math.sqrt(max(0.0, 1 - y * y))
    a = golden * i
    p = [ring * math.cos(a) * AT, y * AT, ring * math.sin(a) * AT]
    lights.append({"type": "point", "color": [rng.random(), rng.random(), rng.random()],
                   "intensity": INTENSITY, "range": RANGE})
    nodes.append({"translation": p, "extensions": {"KHR_lights_punctual": {"light": i}}})

pb = struct.pack(f"<{len(pos)}f", *pos)
nb = struct.pack(f"<{len(nrm)}f", *nrm)
ib = struct.pack(f"<{len(idx)}I", *idx)
buf = pb + nb + ib
count = len(pos) // 3
g = {
    "asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": lights}},
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "nodes": nodes,
    "cameras": [{"type": "perspective", "perspective": {"yfov": math.radians(45), "znear": 0.1, "zfar": 200,
                                                        "aspectRatio": 16 / 9}}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.6, 1], "metallicFactor": 0,
                                            "roughnessFactor": 0.5}}],
    "buffers": [{"byteLength": len(buf),
                 "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pb)},
                    {"buffer": 0, "byteOffset": len(pb), "byteLength": len(nb)},
                    {"buffer": 0, "byteOffset": len(pb) + len(nb), "byteLength": len(ib)}],
    "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
         "min": [min(pos[i::3]) for i in range(3)], "max": [max(pos[i::3]) for i in range(3)]},
        {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC3"},
        {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
    ],
}
with open(out, "w") as f:
    json.dump(g, f)
print(len(idx) // 3, "triangles", n, "lights")
