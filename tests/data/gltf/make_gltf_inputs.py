#!/usr/bin/env python3
"""Regenerates the hand-made valid glTF files in this folder, which exercise loader features
the Khronos samples do not: strips and fans, sparse accessors, normalized u8/u16 attributes,
8- and 16-bit PNGs, samplers, cameras, KHR_lights_punctual, emissive strength, a non-default
`scene`, skipped POINTS primitives, texCoord 2 (unsupported), a second UV set, a file without `scenes`, a .glb, and morph
targets with a skin whose poses have closed forms, and glTF's material extensions (a tinted
volume whose render has a closed form).

    python3 tests/data/gltf/make_gltf_inputs.py
"""
import base64
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def png(width, height, color_type, bit_depth, rows):
    """A minimal PNG; `rows` holds one bytes object per row (no filter byte)."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    raw = b"".join(b"\0" + r for r in rows)
    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


class Builder:
    """Appends typed data to one buffer and records views and accessors."""

    def __init__(self):
        self.data = b""
        self.views = []
        self.accessors = []

    def view(self, payload):
        self.data += b"\0" * (-len(self.data) % 4)
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(payload)})
        self.data += payload
        return len(self.views) - 1

    def accessor(self, fmt, values, component_type, type_, count, normalized=False, **extra):
        view = self.view(struct.pack("<" + fmt * len(values), *values)) if values is not None else None
        a = {"componentType": component_type, "count": count, "type": type_}
        if view is not None:
            a["bufferView"] = view
        if normalized:
            a["normalized"] = True
        a.update(extra)
        self.accessors.append(a)
        return len(self.accessors) - 1


def flat(points):
    return [c for p in points for c in p]


def features():
    b = Builder()
    # Mesh 0 "Strip": a unit quad as a 4-vertex TRIANGLE_STRIP without indices, with u16
    # normalized UVs and u8 normalized VEC3 colours; plus a POINTS primitive (skipped).
    strip_pos = b.accessor("f", flat([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)]), 5126, "VEC3", 4,
                           min=[0, 0, 0], max=[1, 1, 0])
    strip_uv = b.accessor("H", [0, 0, 65535, 0, 0, 65535, 65535, 65535], 5123, "VEC2", 4, True)
    strip_col = b.accessor("B", [255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255], 5121, "VEC3", 4,
                           True)
    # Mesh 1 "Fan": 5 vertices, u8 indices, TRIANGLE_FAN -> 3 triangles.
    fan_pos = b.accessor("f", flat([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (-1, 1, 0)]), 5126,
                         "VEC3", 5)
    fan_idx = b.accessor("B", [0, 1, 2, 3, 4], 5121, "SCALAR", 5)
    # Mesh 2 "Sparse": positions are zeros except vertices 1 and 2, set through `sparse`;
    # normals are given unnormalized (length 2) to check that they are normalized.
    sparse_idx = b.view(struct.pack("<2H", 1, 2))
    sparse_val = b.view(struct.pack("<6f", 2, 0, 0, 0, 3, 0))
    b.accessors.append({"componentType": 5126, "count": 3, "type": "VEC3",
                        "sparse": {"count": 2,
                                   "indices": {"bufferView": sparse_idx, "componentType": 5123},
                                   "values": {"bufferView": sparse_val}}})
    sparse_pos = len(b.accessors) - 1
    sparse_nrm = b.accessor("f", flat([(0, 0, 2)] * 3), 5126, "VEC3", 3)
    # Mesh 3 "Unused": only in scene 0, which is not the default scene.
    unused_pos = b.accessor("f", flat([(0, 0, 0), (5, 0, 0), (0, 5, 0)]), 5126, "VEC3", 3)

    image8 = png(2, 2, 2, 8, [bytes([255, 0, 0, 0, 255, 0]), bytes([0, 0, 255, 255, 255, 255])])
    image16 = png(2, 1, 0, 16, [struct.pack(">2H", 0, 65535)])
    image16_view = b.view(image16)

    doc = {
        "asset": {"version": "2.0", "generator": "glint make_gltf_inputs.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength",
                           "EXT_unknown_optional"],
        "extensionsRequired": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 0.5, 0.25], "intensity": 20, "range": 10},
            {"type": "spot", "name": "Spot", "intensity": 5,
             "spot": {"innerConeAngle": 0.1, "outerConeAngle": 0.5}},
            {"type": "directional", "intensity": 3},
        ]}},
        "scene": 1,
        "scenes": [{"nodes": [0]}, {"nodes": [1, 4, 5, 6, 7, 8, 9, 10]}],
        "nodes": [
            {"name": "OnlyInScene0", "mesh": 3},
            {"name": "Parent", "translation": [10, 0, 0], "scale": [2, 2, 2], "children": [2, 3]},
            {"name": "StripA", "mesh": 0, "translation": [0, 1, 0]},
            {"name": "StripB", "mesh": 0,
             "rotation": [0, 0, math.sin(math.pi / 4), math.cos(math.pi / 4)]},
            {"name": "CameraNode", "camera": 0, "translation": [0, 0, 5]},
            {"name": "OrthoNode", "camera": 1},
            {"name": "PointNode", "translation": [0, 3, 0],
             "extensions": {"KHR_lights_punctual": {"light": 0}}},
            {"extensions": {"KHR_lights_punctual": {"light": 1}}},
            {"extensions": {"KHR_lights_punctual": {"light": 2}},
             "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 2, 3, 1], "extras": {"anything": 1}},
            {"name": "SparseNode", "mesh": 2},
            {"name": "FanNode", "mesh": 1},
        ],
        "cameras": [
            {"name": "Persp", "type": "perspective",
             "perspective": {"yfov": 0.5, "aspectRatio": 1.5, "znear": 0.1, "zfar": 100}},
            {"type": "orthographic",
             "orthographic": {"xmag": 2, "ymag": 1, "znear": 0, "zfar": 50}},
        ],
        "meshes": [
            {"name": "Strip", "primitives": [
                {"attributes": {"POSITION": strip_pos, "TEXCOORD_0": strip_uv, "COLOR_0": strip_col},
                 "mode": 5, "material": 0},
                {"attributes": {"POSITION": strip_pos}, "mode": 0},
            ]},
            {"name": "Fan", "primitives": [
                {"attributes": {"POSITION": fan_pos}, "indices": fan_idx, "mode": 6}]},
            {"name": "Sparse", "primitives": [
                {"attributes": {"POSITION": sparse_pos, "NORMAL": sparse_nrm}, "material": 1}]},
            {"name": "Unused", "primitives": [{"attributes": {"POSITION": unused_pos}}]},
        ],
        "materials": [
            {"name": "Glowing",
             "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 0.75],
                                      "baseColorTexture": {"index": 0, "texCoord": 2},
                                      "metallicFactor": 0.25, "roughnessFactor": 0.5},
             "emissiveFactor": [1, 0.5, 0], "emissiveTexture": {"index": 1},
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}},
             "doubleSided": True},
            {},
        ],
        "samplers": [{"magFilter": 9728, "wrapS": 33071, "wrapT": 33648}],
        "textures": [{"sampler": 0, "source": 0}, {"source": 1}],
        "images": [
            {"uri": "data:image/png;base64," + base64.b64encode(image8).decode()},
            {"bufferView": image16_view, "mimeType": "image/png"},
        ],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(b.data).decode()}],
    }
    return doc


def no_scenes():
    """Two root nodes (one with a child) and no `scenes`: all roots are loaded."""
    b = Builder()
    pos = b.accessor("f", flat([(0, 0, 0), (1, 0, 0), (0, 1, 0)]), 5126, "VEC3", 3)
    return {
        "asset": {"version": "2.0"},
        "nodes": [{"mesh": 0, "children": [2]}, {"mesh": 0, "translation": [0, 0, -1]},
                  {"mesh": 0, "translation": [0, 0, 1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos}}]}],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.data), "uri": "no_scenes.bin"}],
    }, b.data


def pbr_materials():
    """One triangle with NORMAL, TANGENT (left-handed bitangent) and TEXCOORD_0, and a material
    with a normal map, a metallic-roughness texture, alphaMode MASK, KHR_materials_transmission
    and KHR_materials_ior."""
    b = Builder()
    pos = b.accessor("f", flat([(0, 0, 0), (1, 0, 0), (0, 1, 0)]), 5126, "VEC3", 3,
                     min=[0, 0, 0], max=[1, 1, 0])
    nrm = b.accessor("f", flat([(0, 0, 1)] * 3), 5126, "VEC3", 3)
    tan = b.accessor("f", [2, 0, 0, -1] * 3, 5126, "VEC4", 3)  # unnormalized on purpose
    uv = b.accessor("f", [0, 0, 1, 0, 0, 1], 5126, "VEC2", 3)
    image = png(2, 2, 2, 8, [bytes([128, 128, 255, 128, 128, 255]),
                             bytes([128, 128, 255, 128, 128, 255])])
    uri = "data:image/png;base64," + base64.b64encode(image).decode()
    return {
        "asset": {"version": "2.0", "generator": "glint make_gltf_inputs.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "Tri", "mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "TANGENT": tan,
                                                   "TEXCOORD_0": uv}, "material": 0}]}],
        "materials": [{
            "name": "Clear",
            "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0.4,
                                     "metallicRoughnessTexture": {"index": 0}},
            "normalTexture": {"index": 0, "scale": 0.5},
            "alphaMode": "MASK", "alphaCutoff": 0.3,
            "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.8,
                                                          "transmissionTexture": {"index": 0}},
                           "KHR_materials_ior": {"ior": 1.33}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": uri}],
        "buffers": [{"byteLength": len(b.data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(b.data).decode()}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }


def skin_morph():
    """Morph targets and a skin, each with a closed-form pose (tests/scenes/deform_test.cpp).

    Mesh 0, a triangle (0,0,0) (1,0,0) (0,1,0) facing +z, has two position targets: T0 moves
    every vertex by (0,0,1), T1 moves vertex 1 by (1,0,0); its default weights are [0.5, 0.25].
    Node 0 uses them, node 1 (at x = 5) sets weights [1, 0], node 2 (at x = 10) animates them
    linearly from [0, 0] at t = 0 to [1, 2] at t = 1.
    Mesh 1, a triangle (0,0,0) (1,0,0) (0,2,0), is skinned by skin 0 on node 3, whose own
    translation (100, 0, 0) glTF says to ignore. Joint 0 is node 4 (the origin, at rest); joint
    1 is its child node 5 at (0,1,0), turning about +z from 0 at t = 0 to 90 degrees at t = 1;
    inverse bind matrices: identity and a translation by (0,-1,0). Vertices 0 and 1 follow
    joint 0 and joint 1 fully; vertex 2 half each. Its normals all point along +x."""
    b = Builder()
    tri = b.accessor("f", flat([(0, 0, 0), (1, 0, 0), (0, 1, 0)]), 5126, "VEC3", 3,
                     min=[0, 0, 0], max=[1, 1, 0])
    nrm = b.accessor("f", flat([(0, 0, 1)] * 3), 5126, "VEC3", 3)
    t0 = b.accessor("f", flat([(0, 0, 1)] * 3), 5126, "VEC3", 3, min=[0, 0, 1], max=[0, 0, 1])
    t1 = b.accessor("f", flat([(0, 0, 0), (1, 0, 0), (0, 0, 0)]), 5126, "VEC3", 3,
                    min=[0, 0, 0], max=[1, 0, 0])
    times = b.accessor("f", [0, 1], 5126, "SCALAR", 2, min=[0], max=[1])
    weights = b.accessor("f", [0, 0, 1, 2], 5126, "SCALAR", 4)
    skinned = b.accessor("f", flat([(0, 0, 0), (1, 0, 0), (0, 2, 0)]), 5126, "VEC3", 3,
                         min=[0, 0, 0], max=[1, 2, 0])
    # Normals along +x (not the face's, on purpose: a rotation about z must turn them).
    skinned_normals = b.accessor("f", flat([(1, 0, 0)] * 3), 5126, "VEC3", 3)
    joints = b.accessor("B", [0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0], 5121, "VEC4", 3)
    jweights = b.accessor("f", [1, 0, 0, 0, 1, 0, 0, 0, 0.5, 0.5, 0, 0], 5126, "VEC4", 3)
    ibm = b.accessor("f", [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                           1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1], 5126, "MAT4", 2)
    s45 = math.sin(math.pi / 4)
    rotations = b.accessor("f", [0, 0, 0, 1, 0, 0, s45, s45], 5126, "VEC4", 2)
    return {
        "asset": {"version": "2.0", "generator": "glint make_gltf_inputs.py"},
        "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
        "nodes": [
            {"name": "rest weights", "mesh": 0},
            {"name": "node weights", "mesh": 0, "translation": [5, 0, 0], "weights": [1, 0]},
            {"name": "animated weights", "mesh": 0, "translation": [10, 0, 0]},
            {"name": "skinned", "mesh": 1, "skin": 0, "translation": [100, 0, 0]},
            {"name": "joint 0", "children": [5]},
            {"name": "joint 1", "translation": [0, 1, 0]},
        ],
        "meshes": [
            {"name": "Morphed", "weights": [0.5, 0.25],
             "primitives": [{"attributes": {"POSITION": tri, "NORMAL": nrm},
                             "targets": [{"POSITION": t0}, {"POSITION": t1}]}]},
            {"name": "Skinned",
             "primitives": [{"attributes": {"POSITION": skinned, "NORMAL": skinned_normals,
                                            "JOINTS_0": joints,
                                            "WEIGHTS_0": jweights}}]},
        ],
        "skins": [{"joints": [4, 5], "inverseBindMatrices": ibm}],
        "animations": [{
            "samplers": [{"input": times, "output": weights},
                         {"input": times, "output": rotations}],
            "channels": [{"sampler": 0, "target": {"node": 2, "path": "weights"}},
                         {"sampler": 1, "target": {"node": 5, "path": "rotation"}}]}],
        "buffers": [{"byteLength": len(b.data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(b.data).decode()}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }


def instanced_quantized():
    """EXT_mesh_gpu_instancing and KHR_mesh_quantization (tests/scenes/gltf_loader_test.cpp).

    Mesh 0 is a triangle stored as UNSIGNED_SHORT positions (0,0,0) (65535,0,0) (0,65535,0),
    normalized BYTE normals (0,0,127) and normalized SHORT texture coordinates; node 0 scales it
    by 1/65535 into the unit triangle. Node 1 uses mesh 0 too, with three GPU instances under a
    node translation (0,0,-1):
    translations (0,0,0) (2,0,0) (4,0,0), rotations identity, 90 degrees about z (as normalized
    SHORT), identity, and scales 1, 1, 2 (each times the node's scale 1/65535)."""
    b = Builder()
    pos = b.accessor("H", [0, 0, 0, 65535, 0, 0, 0, 65535, 0], 5123, "VEC3", 3,
                     min=[0, 0, 0], max=[65535, 65535, 0])
    nrm = b.accessor("b", [0, 0, 127, 0] * 3, 5120, "VEC3", 3, normalized=True)
    # VEC3 of BYTE needs 4-byte aligned elements in a vertex buffer: give the view a stride.
    b.views[-1]["byteStride"] = 4
    uv = b.accessor("h", [0, 0, 32767, 0, 0, 32767], 5122, "VEC2", 3, normalized=True)
    translations = b.accessor("f", flat([(0, 0, 0), (2, 0, 0), (4, 0, 0)]), 5126, "VEC3", 3)
    h = round(math.sqrt(0.5) * 32767)
    rotations = b.accessor("h", [0, 0, 0, 32767, 0, 0, h, h, 0, 0, 0, 32767], 5122, "VEC4", 3,
                           normalized=True)
    scales = b.accessor("f", flat([(1, 1, 1), (1, 1, 1), (2, 2, 2)]), 5126, "VEC3", 3)
    k = 1 / 65535
    return {
        "asset": {"version": "2.0", "generator": "glint make_gltf_inputs.py"},
        "extensionsUsed": ["KHR_mesh_quantization", "EXT_mesh_gpu_instancing"],
        "extensionsRequired": ["KHR_mesh_quantization", "EXT_mesh_gpu_instancing"],
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"name": "dequantized", "mesh": 0, "scale": [k, k, k]},
            {"name": "forest", "mesh": 0, "scale": [k, k, k], "translation": [0, 0, -1],
             "extensions": {"EXT_mesh_gpu_instancing": {"attributes": {
                 "TRANSLATION": translations, "ROTATION": rotations, "SCALE": scales}}}},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm,
                                                   "TEXCOORD_0": uv}}]}],
        "buffers": [{"byteLength": len(b.data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(b.data).decode()}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }


def variants():
    """KHR_materials_variants: a camera-filling square whose default material is unlit red;
    variant "blue" maps it to unlit blue, variants "green" and "lime" to unlit green. A
    camera looks at it head-on."""
    b = Builder()
    pos = b.accessor("f", flat([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]), 5126, "VEC3", 4,
                     min=[-1, -1, 0], max=[1, 1, 0])
    idx = b.accessor("H", [0, 1, 2, 0, 2, 3], 5123, "SCALAR", 6)

    def unlit(name, rgb):
        return {"name": name, "pbrMetallicRoughness": {"baseColorFactor": rgb + [1]},
                "extensions": {"KHR_materials_unlit": {}}}
    return {
        "asset": {"version": "2.0", "generator": "glint make_gltf_inputs.py"},
        "extensionsUsed": ["KHR_materials_variants", "KHR_materials_unlit"],
        "extensions": {"KHR_materials_variants": {"variants": [
            {"name": "blue"}, {"name": "green"}, {"name": "lime"}]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0, 0, 2]}],
        "cameras": [{"type": "orthographic",
                     "orthographic": {"xmag": 0.5, "ymag": 0.5, "znear": 0.1, "zfar": 10}}],
        "materials": [unlit("red", [0.8, 0, 0]), unlit("blue", [0, 0, 0.8]),
                      unlit("green", [0, 0.8, 0])],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": pos}, "indices": idx, "material": 0,
            "extensions": {"KHR_materials_variants": {"mappings": [
                {"material": 1, "variants": [0]}, {"material": 2, "variants": [1, 2]}]}}}]}],
        "buffers": [{"byteLength": len(b.data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(b.data).decode()}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }


def second_uv_set():
    """TEXCOORD_1: a camera-filling square whose TEXCOORD_0 is (0.25, 0.5) everywhere and
    TEXCOORD_1 (0.75, 0.5), under an unlit material whose base colour texture (2 x 1 pixels: red,
    green; nearest filtering) reads texCoord 1: the image is green. A second material reads the
    same texture through texCoord 0 (red), on a square off camera."""
    b = Builder()
    pos = b.accessor("f", flat([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]), 5126, "VEC3", 4,
                     min=[-1, -1, 0], max=[1, 1, 0])
    uv0 = b.accessor("f", flat([(0.25, 0.5)] * 4), 5126, "VEC2", 4)
    uv1 = b.accessor("f", flat([(0.75, 0.5)] * 4), 5126, "VEC2", 4)
    idx = b.accessor("H", [0, 1, 2, 0, 2, 3], 5123, "SCALAR", 6)
    image = png(2, 1, 2, 8, [bytes([255, 0, 0, 0, 255, 0])])

    def unlit(name, tex_coord):
        return {"name": name, "pbrMetallicRoughness": {
                    "baseColorTexture": {"index": 0, "texCoord": tex_coord}},
                "extensions": {"KHR_materials_unlit": {}}}
    attributes = {"POSITION": pos, "TEXCOORD_0": uv0, "TEXCOORD_1": uv1}
    return {
        "asset": {"version": "2.0", "generator": "glint make_gltf_inputs.py"},
        "extensionsUsed": ["KHR_materials_unlit"],
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [5, 0, 0]},
                  {"camera": 0, "translation": [0, 0, 2]}],
        "cameras": [{"type": "orthographic",
                     "orthographic": {"xmag": 0.5, "ymag": 0.5, "znear": 0.1, "zfar": 10}}],
        "samplers": [{"magFilter": 9728, "minFilter": 9728}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(image).decode()}],
        "textures": [{"sampler": 0, "source": 0}],
        "materials": [unlit("second set", 1), unlit("first set", 0)],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": idx, "material": 0}]},
                   {"primitives": [{"attributes": attributes, "indices": idx, "material": 1}]}],
        "buffers": [{"byteLength": len(b.data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(b.data).decode()}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }


def material_layers():
    """glTF's material extensions. A cube [-1, 1]^3 of clear (ior 1), tinted KHR_materials_volume
    glass (attenuation colour (0.5, 0.25, 0.8) per unit distance) fills an orthographic camera
    looking down -z: every camera ray crosses 2 units inside, so under a uniform white sky a
    pixel is the colour squared, (0.25, 0.0625, 0.64). Off camera, a square wears every other
    material extension at once (the loader test reads its values back)."""
    b = Builder()
    corners = [(x, y, z) for z in (-1, 1) for y in (-1, 1) for x in (-1, 1)]
    cube_pos = b.accessor("f", flat(corners), 5126, "VEC3", 8, min=[-1, -1, -1], max=[1, 1, 1])
    # Two counter-clockwise (outward) triangles per face.
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for a, b_, c, d in faces:
        tris += [a, b_, c, a, c, d]
    cube_idx = b.accessor("H", tris, 5123, "SCALAR", len(tris))
    sq_pos = b.accessor("f", flat([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]), 5126, "VEC3",
                        4, min=[-1, -1, 0], max=[1, 1, 0])
    sq_uv = b.accessor("f", flat([(0, 1), (1, 1), (1, 0), (0, 0)]), 5126, "VEC2", 4)
    sq_idx = b.accessor("H", [0, 1, 2, 0, 2, 3], 5123, "SCALAR", 6)
    tinted = {"name": "tinted volume",
              "pbrMetallicRoughness": {"metallicFactor": 0, "roughnessFactor": 0},
              "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                             "KHR_materials_ior": {"ior": 1.0},
                             "KHR_materials_volume": {"thicknessFactor": 2,
                                                      "attenuationColor": [0.5, 0.25, 0.8],
                                                      "attenuationDistance": 1}}}
    layered = {"name": "every layer",
               "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.6, 0.7, 1],
                                        "metallicFactor": 0.25, "roughnessFactor": 0.5},
               "extensions": {
                   "KHR_materials_specular": {"specularFactor": 0.5,
                                              "specularColorFactor": [1, 0.5, 2]},
                   "KHR_materials_clearcoat": {"clearcoatFactor": 0.75,
                                               "clearcoatRoughnessFactor": 0.125},
                   "KHR_materials_sheen": {"sheenColorFactor": [0.25, 0.5, 0.75],
                                           "sheenRoughnessFactor": 0.375},
                   "KHR_materials_diffuse_transmission": {
                       "diffuseTransmissionFactor": 0.25,
                       "diffuseTransmissionColorFactor": [1, 0.75, 0.5]},
                   "KHR_materials_iridescence": {"iridescenceFactor": 1, "iridescenceIor": 1.75,
                                                 "iridescenceThicknessMinimum": 50,
                                                 "iridescenceThicknessMaximum": 500},
                   "KHR_materials_anisotropy": {"anisotropyStrength": 0.5,
                                                "anisotropyRotation": 1.5},
                   "KHR_materials_dispersion": {"dispersion": 0.5},
                   "KHR_materials_emissive_strength": {"emissiveStrength": 1}}}
    used = sorted({k for m in (tinted, layered) for k in m["extensions"]})
    return {
        "asset": {"version": "2.0", "generator": "glint make_gltf_inputs.py"},
        "extensionsUsed": used,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [5, 0, 0]},
                  {"camera": 0, "translation": [0, 0, 5]}],
        "cameras": [{"type": "orthographic",
                     "orthographic": {"xmag": 0.5, "ymag": 0.5, "znear": 0.1, "zfar": 20}}],
        "materials": [tinted, layered],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": cube_pos}, "indices": cube_idx,
                             "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": sq_pos, "TEXCOORD_0": sq_uv},
                             "indices": sq_idx, "material": 1}]}],
        "buffers": [{"byteLength": len(b.data),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(b.data).decode()}],
        "bufferViews": b.views,
        "accessors": b.accessors,
    }


def glb(doc, bin_data):
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    bin_data += b"\0" * (-len(bin_data) % 4)
    length = 12 + 8 + len(js) + 8 + len(bin_data)
    return (struct.pack("<III", 0x46546C67, 2, length) +
            struct.pack("<II", len(js), 0x4E4F534A) + js +
            struct.pack("<II", len(bin_data), 0x004E4942) + bin_data)


def main():
    with open(os.path.join(HERE, "features.gltf"), "w") as f:
        json.dump(features(), f, indent=1)
        f.write("\n")
    with open(os.path.join(HERE, "skin_morph.gltf"), "w") as f:
        json.dump(skin_morph(), f, indent=1)
        f.write("\n")
    with open(os.path.join(HERE, "instanced_quantized.gltf"), "w") as f:
        json.dump(instanced_quantized(), f, indent=1)
        f.write("\n")
    with open(os.path.join(HERE, "variants.gltf"), "w") as f:
        json.dump(variants(), f, indent=1)
        f.write("\n")
    with open(os.path.join(HERE, "second_uv_set.gltf"), "w") as f:
        json.dump(second_uv_set(), f, indent=1)
        f.write("\n")
    with open(os.path.join(HERE, "material_layers.gltf"), "w") as f:
        json.dump(material_layers(), f, indent=1)
        f.write("\n")
    with open(os.path.join(HERE, "pbr_materials.gltf"), "w") as f:
        json.dump(pbr_materials(), f, indent=1)
        f.write("\n")
    doc, data = no_scenes()
    with open(os.path.join(HERE, "no_scenes.gltf"), "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    with open(os.path.join(HERE, "no_scenes.bin"), "wb") as f:
        f.write(data)
    # The same scene as a .glb whose buffer 0 is the BIN chunk.
    del doc["buffers"][0]["uri"]
    with open(os.path.join(HERE, "no_scenes.glb"), "wb") as f:
        f.write(glb(doc, data))


if __name__ == "__main__":
    main()
