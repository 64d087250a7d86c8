#!/usr/bin/env python3
"""Writes material_extensions.gltf: eight spheres, each wearing one of glTF's material
extensions, on a floor, with no light and no camera (glint's studio and automatic camera
decide). Front row, left to right: clear coat over red paint (KHR_materials_clearcoat), velvet
(KHR_materials_sheen), a dark dielectric with a copper-tinted specular F0
(KHR_materials_specular), brushed aluminium (KHR_materials_anisotropy, brushed around the
sphere). Back row: tinted glass that absorbs with depth (KHR_materials_volume), a thin film
over a dark base (KHR_materials_iridescence), dense flint glass splitting colours
(KHR_materials_dispersion), translucent wax-like paper (KHR_materials_diffuse_transmission).

    python3 scenes/material_extensions/make_material_extensions.py
    build/glint render scenes/material_extensions/material_extensions.gltf -o extensions.png
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "first_image"))
from make_first_image import pbr, spheres_on_floor, write  # noqa: E402


def main():
    glass = {"KHR_materials_transmission": {"transmissionFactor": 1.0},
             "KHR_materials_ior": {"ior": 1.5}}
    materials = [
        pbr("Clearcoat", (0.6, 0.02, 0.02), 0.0, 0.6,
            {"KHR_materials_clearcoat": {"clearcoatFactor": 1.0,
                                         "clearcoatRoughnessFactor": 0.03}}),
        pbr("Sheen", (0.03, 0.03, 0.2), 0.0, 1.0,
            {"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.5, 0.9],
                                     "sheenRoughnessFactor": 0.4}}),
        pbr("Specular", (0.02, 0.02, 0.02), 0.0, 0.25,
            {"KHR_materials_specular": {"specularColorFactor": [5.0, 3.0, 1.0]}}),
        pbr("Anisotropy", (0.92, 0.92, 0.93), 1.0, 0.3,
            {"KHR_materials_anisotropy": {"anisotropyStrength": 0.9}}),
        pbr("Volume", (1.0, 1.0, 1.0), 0.0, 0.0,
            dict(glass, KHR_materials_volume={"thicknessFactor": 2.0,
                                              "attenuationColor": [0.2, 0.6, 0.9],
                                              "attenuationDistance": 1.0})),
        pbr("Iridescence", (0.03, 0.03, 0.03), 0.0, 0.1,
            {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceIor": 1.8,
                                           "iridescenceThicknessMaximum": 380}}),
        pbr("Dispersion", (1.0, 1.0, 1.0), 0.0, 0.0,
            dict(glass, KHR_materials_volume={"thicknessFactor": 2.0},
                 KHR_materials_dispersion={"dispersion": 3.0})),
        pbr("DiffuseTransmission", (0.9, 0.85, 0.7), 0.0, 0.6,
            {"KHR_materials_diffuse_transmission": {
                "diffuseTransmissionFactor": 0.6,
                "diffuseTransmissionColorFactor": [1.0, 0.5, 0.2]}}),
        pbr("Floor", (0.45, 0.45, 0.45), 0.0, 0.8),
    ]
    xs = [-3.45, -1.15, 1.15, 3.45]
    places = [(x, 1.0, 1.3) for x in xs] + [(x, 1.0, -1.3) for x in xs]
    used = sorted({k for m in materials for k in m.get("extensions", {})})
    doc = spheres_on_floor(materials, places, used, floor_half=5.2,
                           generator="glint scenes/material_extensions/make_material_extensions.py")
    write(doc, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                            "material_extensions.gltf"))


if __name__ == "__main__":
    main()
