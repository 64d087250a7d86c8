#!/usr/bin/env python3
"""Writes first_image.gltf: five spheres on a floor, glTF metallic-roughness materials, and no
light and no camera, so that glint's defaults decide everything: the automatic camera frames
the spheres from the asset's front (+Z), the default studio environment lights them, and
`--integrator auto` picks the path tracer. Left to right: white diffuse, red plastic, gold
(rough metal), chrome (polished metal), glass (KHR_materials_transmission).

    python3 scenes/first_image/make_first_image.py   # rewrites scenes/first_image/first_image.gltf
    build/glint render scenes/first_image/first_image.gltf -o first_image.png
"""
import base64
import json
import math
import os
import struct


def sphere(segments=48, rings=24):
    positions, normals, indices = [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
            positions.append(n)
            normals.append(n)
    for r in range(rings):
        for s in range(segments):
            a = r * (segments + 1) + s
            b = a + segments + 1
            if r != 0:
                indices += [a, a + 1, b]
            if r != rings - 1:
                indices += [a + 1, b + 1, b]
    return positions, normals, indices


def main():
    sp, sn, si = sphere()
    fp = [(-6, 0, -6), (6, 0, -6), (6, 0, 6), (-6, 0, 6)]
    fn = [(0, 1, 0)] * 4
    fi = [0, 2, 1, 0, 3, 2]
    blob = bytearray()
    views, accessors = [], []

    def add(values, fmt, target, component, kind, minmax=False):
        while len(blob) % 4:
            blob.append(0)
        offset = len(blob)
        for v in values:
            blob.extend(struct.pack(fmt, *(v if isinstance(v, tuple) else (v,))))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(blob) - offset,
                      "target": target})
        acc = {"bufferView": len(views) - 1, "componentType": component, "count": len(values),
               "type": kind}
        if minmax:
            acc["min"] = [min(v[i] for v in values) for i in range(3)]
            acc["max"] = [max(v[i] for v in values) for i in range(3)]
        accessors.append(acc)
        return len(accessors) - 1

    ARRAY, ELEMENTS, FLOAT, USHORT = 34962, 34963, 5126, 5123
    s_pos = add(sp, "<3f", ARRAY, FLOAT, "VEC3", True)
    s_nrm = add(sn, "<3f", ARRAY, FLOAT, "VEC3")
    s_idx = add(si, "<H", ELEMENTS, USHORT, "SCALAR")
    f_pos = add(fp, "<3f", ARRAY, FLOAT, "VEC3", True)
    f_nrm = add(fn, "<3f", ARRAY, FLOAT, "VEC3")
    f_idx = add(fi, "<H", ELEMENTS, USHORT, "SCALAR")

    def pbr(name, color, metallic, roughness, extensions=None):
        m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0],
                                                    "metallicFactor": metallic,
                                                    "roughnessFactor": roughness}}
        if extensions:
            m["extensions"] = extensions
        return m

    materials = [
        pbr("WhiteDiffuse", (0.8, 0.8, 0.8), 0.0, 1.0),
        pbr("RedPlastic", (0.8, 0.08, 0.06), 0.0, 0.3),
        pbr("Gold", (1.0, 0.77, 0.34), 1.0, 0.35),
        pbr("Chrome", (0.95, 0.95, 0.95), 1.0, 0.04),
        pbr("Glass", (1.0, 1.0, 1.0), 0.0, 0.0,
            {"KHR_materials_transmission": {"transmissionFactor": 1.0},
             "KHR_materials_ior": {"ior": 1.5}}),
        pbr("Floor", (0.45, 0.45, 0.45), 0.0, 0.8),
    ]
    meshes, nodes = [], []
    for i, m in enumerate(materials[:5]):
        meshes.append({"name": m["name"], "primitives": [
            {"attributes": {"POSITION": s_pos, "NORMAL": s_nrm}, "indices": s_idx, "material": i}]})
        nodes.append({"name": m["name"], "mesh": i, "translation": [2.3 * (i - 2), 1.0, 0.0]})
    meshes.append({"name": "Floor", "primitives": [
        {"attributes": {"POSITION": f_pos, "NORMAL": f_nrm}, "indices": f_idx, "material": 5}]})
    nodes.append({"name": "Floor", "mesh": 5})
    doc = {
        "asset": {"version": "2.0", "generator": "glint scenes/first_image/make_first_image.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(bytes(blob)).decode()}],
    }
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "first_image.gltf")
    with open(out, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
