#!/usr/bin/env python3
"""Regenerates the malformed glTF inputs in this folder (see README.md for what each tests).

Every file is a one-triangle scene with exactly one thing wrong. Run from anywhere:
    python3 tests/data/bad/make_bad_inputs.py
"""
import base64
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def triangle_buffer(positions=None, normals=None, indices=(0, 1, 2)):
    """Bytes of: u16 indices (padded to 4) | f32 VEC3 positions | f32 VEC3 normals."""
    positions = positions or [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    data = struct.pack("<%dH" % len(indices), *indices)
    data += b"\0" * (-len(data) % 4)
    pos_offset = len(data)
    for p in positions:
        data += struct.pack("<3f", *p)
    nrm_offset = len(data)
    for n in normals or []:
        data += struct.pack("<3f", *n)
    return data, pos_offset, nrm_offset


def triangle_gltf(positions=None, normals=None, indices=(0, 1, 2), uri=None):
    """A valid one-triangle glTF (dict) and its buffer bytes; the buffer is embedded unless
    `uri` is given."""
    data, pos_offset, nrm_offset = triangle_buffer(positions, normals, indices)
    n = len(positions or [0, 0, 0])
    accessors = [
        {"bufferView": 0, "componentType": 5123, "count": len(indices), "type": "SCALAR"},
        {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC3"},
    ]
    views = [
        {"buffer": 0, "byteOffset": 0, "byteLength": 2 * len(indices)},
        {"buffer": 0, "byteOffset": pos_offset, "byteLength": 12 * n},
    ]
    attributes = {"POSITION": 1}
    if normals:
        accessors.append({"bufferView": 2, "componentType": 5126, "count": n, "type": "VEC3"})
        views.append({"buffer": 0, "byteOffset": nrm_offset, "byteLength": 12 * n})
        attributes["NORMAL"] = 2
    buffer = {"byteLength": len(data)}
    buffer["uri"] = uri if uri else (
        "data:application/octet-stream;base64," + base64.b64encode(data).decode())
    doc = {
        "asset": {"version": "2.0", "generator": "glint make_bad_inputs.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 0}]}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [buffer],
    }
    return doc, data


def one_pixel_png():
    """A 1x1 white RGB PNG."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))
    header = struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
            chunk(b"IDAT", zlib.compress(b"\x00\xff\xff\xff")) + chunk(b"IEND", b""))


def write_json(name, doc):
    with open(os.path.join(HERE, name), "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")


def write_bytes(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


def glb(doc, bin_data):
    """A GLB container: header, JSON chunk (space padded), BIN chunk (zero padded)."""
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    bin_data += b"\0" * (-len(bin_data) % 4)
    length = 12 + 8 + len(js) + 8 + len(bin_data)
    return (struct.pack("<III", 0x46546C67, 2, length) +
            struct.pack("<II", len(js), 0x4E4F534A) + js +
            struct.pack("<II", len(bin_data), 0x004E4942) + bin_data)


def main():
    # truncated.glb: a valid GLB cut short; the header still claims the full length.
    doc, data = triangle_gltf()
    del doc["buffers"][0]["uri"]
    whole = glb(doc, data)
    write_bytes("truncated.glb", whole[:100])

    # accessor_out_of_bounds.gltf: POSITION claims 4 vertices, its view holds 3.
    doc, _ = triangle_gltf()
    doc["accessors"][1]["count"] = 4
    write_json("accessor_out_of_bounds.gltf", doc)

    # buffer_view_out_of_bounds.gltf: the position view runs past the end of the buffer.
    doc, _ = triangle_gltf()
    doc["bufferViews"][1]["byteLength"] = 48
    write_json("buffer_view_out_of_bounds.gltf", doc)

    # missing_bin.gltf: the external buffer file does not exist.
    doc, _ = triangle_gltf(uri="missing_bin.bin")
    write_json("missing_bin.gltf", doc)

    # bin_too_short.gltf: the external buffer file is shorter than byteLength.
    doc, data = triangle_gltf(uri="bin_too_short.bin")
    write_json("bin_too_short.gltf", doc)
    write_bytes("bin_too_short.bin", data[:-4])

    # index_out_of_range.gltf: index 57 into a 3-vertex primitive.
    doc, _ = triangle_gltf(indices=(0, 57, 2))
    write_json("index_out_of_range.gltf", doc)

    # nan_positions.gltf / inf_positions.gltf: one non-finite coordinate.
    doc, _ = triangle_gltf(positions=[(0, 0, 0), (1, 0, 0), (0, math.nan, 0)])
    write_json("nan_positions.gltf", doc)
    doc, _ = triangle_gltf(positions=[(0, 0, 0), (math.inf, 0, 0), (0, 1, 0)])
    write_json("inf_positions.gltf", doc)

    # zero_length_normals.gltf: normal 2 is (0, 0, 0).
    doc, _ = triangle_gltf(normals=[(0, 0, 1), (0, 0, 1), (0, 0, 0)])
    write_json("zero_length_normals.gltf", doc)

    # camera_znear_ge_zfar.gltf: a perspective camera with znear 10 > zfar 1.
    doc, _ = triangle_gltf()
    doc["cameras"] = [{"type": "perspective",
                       "perspective": {"yfov": 0.8, "znear": 10.0, "zfar": 1.0}}]
    doc["nodes"].append({"camera": 0})
    doc["scenes"][0]["nodes"].append(1)
    write_json("camera_znear_ge_zfar.gltf", doc)

    # buffer_uri_outside_folder.gltf / absolute_uri.gltf: URIs that leave this folder.
    doc, _ = triangle_gltf(uri="../outside.bin")
    write_json("buffer_uri_outside_folder.gltf", doc)
    doc, _ = triangle_gltf(uri="/etc/hostname")
    write_json("absolute_uri.gltf", doc)

    # wrong_type.gltf: "count": "three".
    doc, _ = triangle_gltf()
    doc["accessors"][1]["count"] = "three"
    write_json("wrong_type.gltf", doc)

    # unsupported_required_extension.gltf
    doc, _ = triangle_gltf()
    doc["extensionsUsed"] = ["KHR_materials_pbrSpecularGlossiness"]
    doc["extensionsRequired"] = ["KHR_materials_pbrSpecularGlossiness"]
    write_json("unsupported_required_extension.gltf", doc)

    # texture_transform_nan_scale.gltf: KHR_texture_transform whose scale holds a NaN (JSON
    # cannot: a string, which is what an exporter bug writes).
    doc, _ = triangle_gltf()
    doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(one_pixel_png()).decode()}]
    doc["textures"] = [{"source": 0}]
    doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {
        "index": 0, "extensions": {"KHR_texture_transform": {"scale": [1, "NaN"]}}}}}]
    doc["meshes"][0]["primitives"][0]["material"] = 0
    doc["extensionsUsed"] = ["KHR_texture_transform"]
    write_json("texture_transform_nan_scale.gltf", doc)

    # node_cycle.gltf: node 0 is the child of node 1 and vice versa.
    doc, _ = triangle_gltf()
    doc["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [0]}]
    write_json("node_cycle.gltf", doc)

    # singular_matrix.gltf: a node matrix with a zero column.
    doc, _ = triangle_gltf()
    doc["nodes"][0]["matrix"] = [1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    write_json("singular_matrix.gltf", doc)

    # material_index_out_of_range.gltf: material 3 of 0.
    doc, _ = triangle_gltf()
    doc["meshes"][0]["primitives"][0]["material"] = 3
    write_json("material_index_out_of_range.gltf", doc)

    # Skins and morph targets: each file is ../gltf/skin_morph.gltf (valid) with one thing wrong.
    with open(os.path.join(HERE, "..", "gltf", "skin_morph.gltf")) as f:
        good = json.load(f)

    def variant(name, change):
        doc = json.loads(json.dumps(good))
        change(doc)
        write_json(name, doc)

    # skin_joint_out_of_range.gltf: vertex 1 names joint 1 of a skin that keeps only joint 0.
    variant("skin_joint_out_of_range.gltf",
            lambda d: d["skins"][0].update(joints=[4]))
    # skin_index_out_of_range.gltf: node 3 names skin 2 of 1.
    variant("skin_index_out_of_range.gltf", lambda d: d["nodes"][3].update(skin=2))
    # morph_weights_count_mismatch.gltf: three default weights for two targets.
    variant("morph_weights_count_mismatch.gltf",
            lambda d: d["meshes"][0].update(weights=[0.5, 0.25, 1]))
    # morph_target_count_mismatch.gltf: a second primitive with one target where the first has
    # two.
    def second_primitive(d):
        p = json.loads(json.dumps(d["meshes"][0]["primitives"][0]))
        p["targets"] = p["targets"][:1]
        d["meshes"][0]["primitives"].append(p)
    variant("morph_target_count_mismatch.gltf", second_primitive)
    # morph_animation_output_count.gltf: the weights channel's output keeps 3 of its 4 values.
    variant("morph_animation_output_count.gltf",
            lambda d: d["accessors"][d["animations"][0]["samplers"][0]["output"]].update(count=3))

    # ../gltf/instanced_quantized.gltf (valid) with one thing wrong.
    with open(os.path.join(HERE, "..", "gltf", "instanced_quantized.gltf")) as f:
        good = json.load(f)

    # quantized_without_extension.gltf: UNSIGNED_SHORT positions without KHR_mesh_quantization.
    def drop_quantization(d):
        for key in ("extensionsUsed", "extensionsRequired"):
            d[key].remove("KHR_mesh_quantization")
    variant("quantized_without_extension.gltf", drop_quantization)
    # instancing_count_mismatch.gltf: SCALE has 2 elements where TRANSLATION has 3.
    variant("instancing_count_mismatch.gltf",
            lambda d: d["accessors"][d["nodes"][1]["extensions"]["EXT_mesh_gpu_instancing"]
                                     ["attributes"]["SCALE"]].update(count=2))

    # variant_index_out_of_range.gltf: ../gltf/variants.gltf mapping variant 5 of 3.
    with open(os.path.join(HERE, "..", "gltf", "variants.gltf")) as f:
        good = json.load(f)
    variant("variant_index_out_of_range.gltf",
            lambda d: d["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]
                       ["mappings"][1].update(variants=[1, 5]))

    # ../gltf/material_layers.gltf (valid) with one material extension value out of range.
    with open(os.path.join(HERE, "..", "gltf", "material_layers.gltf")) as f:
        good = json.load(f)
    layers = lambda d: d["materials"][1]["extensions"]
    # clearcoat_factor_above_one.gltf: clearcoatFactor 2.
    variant("clearcoat_factor_above_one.gltf",
            lambda d: layers(d)["KHR_materials_clearcoat"].update(clearcoatFactor=2))
    # sheen_color_negative.gltf: a negative sheen colour channel.
    variant("sheen_color_negative.gltf",
            lambda d: layers(d)["KHR_materials_sheen"].update(sheenColorFactor=[-0.5, 0, 0]))
    # iridescence_ior_below_one.gltf: a film index of 0.5.
    variant("iridescence_ior_below_one.gltf",
            lambda d: layers(d)["KHR_materials_iridescence"].update(iridescenceIor=0.5))
    # volume_attenuation_distance_zero.gltf: attenuationDistance 0 (it must be > 0).
    variant("volume_attenuation_distance_zero.gltf",
            lambda d: d["materials"][0]["extensions"]["KHR_materials_volume"].update(
                attenuationDistance=0))

    # json_syntax_error.gltf is written by hand (a missing comma at line 5, column 5).
    with open(os.path.join(HERE, "json_syntax_error.gltf"), "w") as f:
        f.write('{\n'
                '  "asset": {"version": "2.0"},\n'
                '  "nodes": [\n'
                '    {"name": "a"}\n'
                '    {"name": "b"}\n'
                '  ]\n'
                '}\n')


if __name__ == "__main__":
    main()
