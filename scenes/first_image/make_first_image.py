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


def sphere_uvs_and_tangents(segments=48, rings=24):
    """Texture coordinates (u around, v down) and tangents along +u for sphere()'s vertices:
    anisotropic materials need a tangent frame."""
    uvs, tangents = [], []
    for r in range(rings + 1):
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            uvs.append((s / segments, r / rings))
            tangents.append((-math.sin(phi), 0.0, math.cos(phi), 1.0))
    return uvs, tangents


def spheres_on_floor(materials, places, extensions_used, floor_half=6, generator=""):
    """A glTF document: one unit sphere per (material, place) and a floor of the last
    material, with no light and no camera."""
    sp, sn, si = sphere()
    su, st = sphere_uvs_and_tangents()
    h = floor_half
    fp = [(-h, 0, -h), (h, 0, -h), (h, 0, h), (-h, 0, h)]
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
    s_uv = add(su, "<2f", ARRAY, FLOAT, "VEC2")
    s_tan = add(st, "<4f", ARRAY, FLOAT, "VEC4")
    f_pos = add(fp, "<3f", ARRAY, FLOAT, "VEC3", True)
    f_nrm = add(fn, "<3f", ARRAY, FLOAT, "VEC3")
    f_idx = add(fi, "<H", ELEMENTS, USHORT, "SCALAR")

    meshes, nodes = [], []
    for i, (m, place) in enumerate(zip(materials, places)):
        meshes.append({"name": m["name"], "primitives": [
            {"attributes": {"POSITION": s_pos, "NORMAL": s_nrm, "TEXCOORD_0": s_uv,
                            "TANGENT": s_tan}, "indices": s_idx, "material": i}]})
        nodes.append({"name": m["name"], "mesh": i, "translation": list(place)})
    floor = len(materials) - 1
    meshes.append({"name": "Floor", "primitives": [
        {"attributes": {"POSITION": f_pos, "NORMAL": f_nrm}, "indices": f_idx,
         "material": floor}]})
    nodes.append({"name": "Floor", "mesh": len(meshes) - 1})
    doc = {
        "asset": {"version": "2.0", "generator": generator},
        "extensionsUsed": extensions_used,
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
    return doc


def pbr(name, color, metallic, roughness, extensions=None):
    m = {"name": name, "pbrMetallicRoughness": {"baseColorFactor": list(color) + [1.0],
                                                "metallicFactor": metallic,
                                                "roughnessFactor": roughness}}
    if extensions:
        m["extensions"] = extensions
    return m


def write(doc, path):
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


def main():
    materials = [
        pbr("WhiteDiffuse", (0.8, 0.8, 0.8), 0.0, 1.0),
        pbr("RedPlastic", (0.8, 0.08, 0.06), 0.0, 0.3),
        pbr("Gold", (1.0, 0.77, 0.34), 1.0, 0.35),
        pbr("Chrome", (0.95, 0.95, 0.95), 1.0, 0.04),
        pbr("Glass", (1.0, 1.0, 1.0), 0.0, 0.0,
            {"KHR_materials_transmission": {"transmissionFactor": 1.0},
             "KHR_materials_ior": {"ior": 1.5},
             # A solid ball (it refracts); without a volume glTF's transmission is a thin sheet.
             "KHR_materials_volume": {"thicknessFactor": 2.0}}),
        pbr("Floor", (0.45, 0.45, 0.45), 0.0, 0.8),
    ]
    places = [(2.3 * (i - 2), 1.0, 0.0) for i in range(5)]
    doc = spheres_on_floor(materials, places, ["KHR_materials_transmission", "KHR_materials_ior",
                                               "KHR_materials_volume"],
                           generator="glint scenes/first_image/make_first_image.py")
    write(doc, os.path.join(os.path.dirname(os.path.abspath(__file__)), "first_image.gltf"))


if __name__ == "__main__":
    main()
