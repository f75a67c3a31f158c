#!/usr/bin/env python3
"""Writes small hand-made glTF seeds (all data embedded) into the corpus directory given
(default: ../corpus/import_gltf from this script), and, with --assimp DIR, copies the .gltf/.glb
files under DIR and writes copies of the .gltf ones with their external buffers/images embedded
as data URIs (third-party files: they go to the gitignored corpus only)."""
import base64, json, os, struct, sys, zlib

here = os.path.dirname(os.path.abspath(__file__))
out = os.path.join(here, "..", "corpus", "import_gltf")
args = sys.argv[1:]
assimp = None
if "--assimp" in args:
    i = args.index("--assimp"); assimp = args[i + 1]; del args[i:i + 2]
if args:
    out = args[0]
os.makedirs(out, exist_ok=True)


def png(w, h, rgba=True):
    raw = b"".join(b"\x00" + b"".join(bytes((x * 60 % 256, y * 60 % 256, 128, 255)[: 4 if rgba else 3]) for x in range(w)) for y in range(h))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    ihdr = struct.pack(">IIBBBBB", w, h, 8, 6 if rgba else 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def uri(b, mime="application/octet-stream"):
    return "data:%s;base64,%s" % (mime, base64.b64encode(b).decode())


def f32(*v):
    return struct.pack("<%df" % len(v), *v)


def pad4(b):
    return b + b"\x00" * (-len(b) % 4)


class Builder:
    def __init__(self):
        self.bin = b""
        self.g = {"asset": {"version": "2.0"}, "buffers": [], "bufferViews": [], "accessors": []}

    def view(self, data, stride=None):
        off = len(self.bin)
        self.bin = pad4(self.bin + data)
        v = {"buffer": 0, "byteOffset": off, "byteLength": len(data)}
        if stride:
            v["byteStride"] = stride
        self.g["bufferViews"].append(v)
        return len(self.g["bufferViews"]) - 1

    def acc(self, data, ctype, count, typ, **kw):
        a = {"bufferView": self.view(data), "componentType": ctype, "count": count, "type": typ}
        a.update(kw)
        self.g["accessors"].append(a)
        return len(self.g["accessors"]) - 1

    def gltf(self):
        g = dict(self.g)
        g["buffers"] = [{"byteLength": len(self.bin), "uri": uri(self.bin)}]
        return json.dumps(g, separators=(",", ":")).encode()

    def glb(self):
        g = dict(self.g)
        g["buffers"] = [{"byteLength": len(self.bin)}]
        js = json.dumps(g, separators=(",", ":")).encode()
        js += b" " * (-len(js) % 4)
        body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(self.bin), 0x004E4942) + self.bin
        return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def tri_scene(b, mode=None, indices=True, normals=True, uvs=True, tangents=False, material=None, extra_nodes=()):
    pos = f32(0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0)
    attrs = {"POSITION": b.acc(pos, 5126, 4, "VEC3", min=[0, 0, 0], max=[1, 1, 0])}
    if normals:
        attrs["NORMAL"] = b.acc(f32(*([0, 0, 1] * 4)), 5126, 4, "VEC3")
    if uvs:
        attrs["TEXCOORD_0"] = b.acc(f32(0, 0, 1, 0, 0, 1, 1, 1), 5126, 4, "VEC2")
    if tangents:
        attrs["TANGENT"] = b.acc(f32(*([1, 0, 0, 1] * 4)), 5126, 4, "VEC4")
    prim = {"attributes": attrs}
    if indices:
        prim["indices"] = b.acc(struct.pack("<6H", 0, 1, 2, 2, 1, 3), 5123, 6, "SCALAR")
    if mode is not None:
        prim["mode"] = mode
    if material is not None:
        prim["material"] = material
    b.g["meshes"] = [{"primitives": [prim]}]
    b.g["nodes"] = [{"mesh": 0, "children": list(range(1, 1 + len(extra_nodes)))}] + list(extra_nodes)
    b.g["scenes"] = [{"nodes": [0]}]
    b.g["scene"] = 0


seeds = {}

b = Builder(); tri_scene(b); seeds["quad.gltf"] = b.gltf(); seeds["quad.glb"] = b.glb()
b = Builder(); tri_scene(b, mode=5, indices=False, normals=False); seeds["strip_flat.gltf"] = b.gltf()
b = Builder(); tri_scene(b, mode=6, uvs=False); seeds["fan.glb"] = b.glb()
b = Builder(); tri_scene(b, mode=1); seeds["lines.gltf"] = b.gltf()

# Lights (KHR_lights_punctual) and a camera on child nodes, with a mirrored (negative-scale) root.
b = Builder()
lights = [{"type": "point", "intensity": 10, "color": [1, 0.5, 0.2]},
          {"type": "spot", "intensity": 5, "range": 4, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
          {"type": "directional", "intensity": 3}, {"type": "directional", "intensity": 1}]
extra = [{"extensions": {"KHR_lights_punctual": {"light": i}}, "translation": [i, 2, 1]} for i in range(4)]
extra.append({"camera": 0, "translation": [0, 0, 5], "rotation": [0, 0, 0, 1]})
extra.append({"camera": 1, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 3, 1]})
tri_scene(b, extra_nodes=extra)
b.g["nodes"][0]["scale"] = [-1, 1, 1]
b.g["extensionsUsed"] = ["KHR_lights_punctual"]
b.g["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
b.g["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100, "aspectRatio": 1.5}},
                  {"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0.1, "zfar": 10}}]
seeds["lights_camera.gltf"] = b.gltf()
seeds["lights_camera.glb"] = b.glb()

# Textured material with a PNG in a buffer view (glb) and as a data URI (gltf); normal map
# without tangents (MikkTSpace path), specular/ior/emissive-strength extensions.
for kind in ("glb", "gltf"):
    b = Builder()
    mat = {"pbrMetallicRoughness": {"baseColorFactor": [1, 0.8, 0.6, 0.5], "baseColorTexture": {"index": 0},
                                    "metallicRoughnessTexture": {"index": 1}, "metallicFactor": 0.3, "roughnessFactor": 0.4},
           "normalTexture": {"index": 1, "scale": 0.5}, "emissiveTexture": {"index": 0, "texCoord": 1},
           "emissiveFactor": [0.1, 0.1, 0.1], "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": True,
           "extensions": {"KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.9, 0.8]},
                          "KHR_materials_ior": {"ior": 1.7}, "KHR_materials_emissive_strength": {"emissiveStrength": 4}}}
    tri_scene(b, material=0)
    b.g["materials"] = [mat]
    b.g["samplers"] = [{}]
    b.g["textures"] = [{"source": 0, "sampler": 0}, {"source": 1}]
    if kind == "glb":
        b.g["images"] = [{"bufferView": b.view(png(4, 4)), "mimeType": "image/png"},
                         {"bufferView": b.view(png(3, 5, rgba=False)), "mimeType": "image/png"}]
        seeds["textured.glb"] = b.glb()
    else:
        b.g["images"] = [{"uri": uri(png(4, 4), "image/png")}, {"uri": uri(png(3, 5, rgba=False), "image/png")}]
        b.g["extensionsUsed"] = ["KHR_materials_specular", "KHR_materials_ior", "KHR_materials_emissive_strength"]
        seeds["textured.gltf"] = b.gltf()

# Sparse accessor: positions from a zero base with two replaced values.
b = Builder(); tri_scene(b, normals=False, uvs=False)
b.g["accessors"][0] = {"componentType": 5126, "count": 4, "type": "VEC3",
                       "sparse": {"count": 2, "indices": {"bufferView": b.view(struct.pack("<2H", 1, 2)), "componentType": 5123},
                                  "values": {"bufferView": b.view(f32(1, 0, 0, 0, 1, 0))}}}
seeds["sparse.gltf"] = b.gltf()

# Interleaved (strided) attributes, u8 indices, u16 normalised UVs, a default scene-less file.
b = Builder()
verts = b"".join(f32(x, y, 0, 0, 0, 1) for x, y in ((0, 0), (1, 0), (0, 1)))
v = b.view(verts, stride=24)
b.g["accessors"] = [{"bufferView": v, "byteOffset": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                    {"bufferView": v, "byteOffset": 12, "componentType": 5126, "count": 3, "type": "VEC3"}]
uv = b.acc(struct.pack("<6H", 0, 0, 65535, 0, 0, 65535), 5123, 3, "VEC2", normalized=True)
ix = b.acc(bytes((0, 1, 2, 0)), 5121, 3, "SCALAR")
b.g["meshes"] = [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": uv}, "indices": ix}]}]
b.g["nodes"] = [{"mesh": 0, "children": [1]}, {"mesh": 0, "rotation": [0, 0.7071, 0, 0.7071]}]
seeds["interleaved_noscene.gltf"] = b.gltf()

seeds["empty_object.gltf"] = b'{"asset":{"version":"2.0"}}'
seeds["required_ext.gltf"] = b'{"asset":{"version":"2.0"},"extensionsRequired":["KHR_draco_mesh_compression"],"extensionsUsed":["KHR_draco_mesh_compression"]}'

for name, data in seeds.items():
    with open(os.path.join(out, "seed_" + name), "wb") as f:
        f.write(data)
print(f"wrote {len(seeds)} hand-made seeds to {out}")

if assimp:
    n = 0
    for root, _, files in os.walk(assimp):
        for fn in files:
            if not fn.endswith((".gltf", ".glb")):
                continue
            p = os.path.join(root, fn)
            d = os.path.basename(root)
            if os.path.getsize(p) <= 4 << 20:  # the raw file as well (libFuzzer truncates to -max_len)
                open(os.path.join(out, f"assimp_{d}_{fn}"), "wb").write(open(p, "rb").read())
                n += 1
            if fn.endswith(".glb"):
                continue
            try:
                g = json.load(open(p, "rb"))
                changed = False
                for key in ("buffers", "images"):
                    for item in g.get(key, []) or []:
                        u = item.get("uri") if isinstance(item, dict) else None
                        if isinstance(u, str) and not u.startswith("data:"):
                            q = os.path.join(root, u)
                            if os.path.isfile(q) and os.path.getsize(q) < 48000:
                                mime = "image/png" if u.endswith(".png") else "image/jpeg" if u.endswith((".jpg", ".jpeg")) else "application/octet-stream"
                                item["uri"] = uri(open(q, "rb").read(), mime)
                                changed = True
                if changed:
                    data = json.dumps(g, separators=(",", ":")).encode()
                    if len(data) <= 65536:
                        open(os.path.join(out, f"assimp_embedded_{d}_{fn}"), "wb").write(data)
                        n += 1
            except Exception as e:
                print("skip", p, e)
    print(f"wrote {n} assimp models and embedded copies")
