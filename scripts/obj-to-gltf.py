#!/usr/bin/env python3
"""Converts a Wavefront OBJ file's triangles and polygons (positions and normals; no materials)
into a glTF 2.0 file with one mesh and no lights, so that an OBJ sample can be read by
Lampshade: `scripts/obj-to-gltf.py IN.obj OUT.gltf`. Polygons are fanned; faces without
normals get none (Lampshade computes flat ones)."""
import base64, json, struct, sys

def main(src, dst):
    pos, nrm, verts, index, keys = [], [], [], [], {}
    for line in open(src, encoding="latin-1"):
        f = line.split()
        if not f:
            continue
        if f[0] == "v":
            pos.append(tuple(float(x) for x in f[1:4]))
        elif f[0] == "vn":
            nrm.append(tuple(float(x) for x in f[1:4]))
        elif f[0] == "f":
            corners = []
            for c in f[1:]:
                parts = c.split("/")
                p = int(parts[0])
                p = p - 1 if p > 0 else len(pos) + p
                n = None
                if len(parts) > 2 and parts[2]:
                    n = int(parts[2])
                    n = n - 1 if n > 0 else len(nrm) + n
                key = (p, n)
                if key not in keys:
                    keys[key] = len(verts)
                    verts.append(key)
                corners.append(keys[key])
            for k in range(1, len(corners) - 1):
                index += [corners[0], corners[k], corners[k + 1]]
    with_normals = all(n is not None for _, n in verts)
    P = b"".join(struct.pack("<3f", *pos[p]) for p, _ in verts)
    N = b"".join(struct.pack("<3f", *nrm[n]) for _, n in verts) if with_normals else b""
    I = b"".join(struct.pack("<I", i) for i in index)
    data = P + N + I
    lo = [min(pos[p][k] for p, _ in verts) for k in range(3)]
    hi = [max(pos[p][k] for p, _ in verts) for k in range(3)]
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": len(P)}]
    accessors = [{"bufferView": 0, "componentType": 5126, "count": len(verts), "type": "VEC3", "min": lo, "max": hi}]
    attributes = {"POSITION": 0}
    if with_normals:
        views.append({"buffer": 0, "byteOffset": len(P), "byteLength": len(N)})
        accessors.append({"bufferView": 1, "componentType": 5126, "count": len(verts), "type": "VEC3"})
        attributes["NORMAL"] = 1
    views.append({"buffer": 0, "byteOffset": len(P) + len(N), "byteLength": len(I)})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5125, "count": len(index), "type": "SCALAR"})
    gltf = {
        "asset": {"version": "2.0", "generator": "lampshade scripts/obj-to-gltf.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": len(accessors) - 1}]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(data), "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
    }
    with open(dst, "w") as out:
        json.dump(gltf, out)

if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
