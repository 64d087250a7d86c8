#!/usr/bin/env python3
"""Generates glint's demo scene and the small test scenes.

    /usr/bin/python3 scripts/make_scenes.py        # from anywhere; paths are repo-relative

Writes scenes/demo/demo.gltf (+ .glint.json) and the scenes under tests/data/scenes/.
Every .gltf embeds its binary data and PNG textures as base64 data URIs, so the scenes need
nothing outside the repository. Output is deterministic (same bytes on every run): no
timestamps, no dict-order or hash dependence, floats written as the shortest decimal that
reads back as the same float32. Standard library only (json, struct, base64, zlib, math).

The scenes only use what the renderer supports at this stage: indexed triangle meshes with
normals / TEXCOORD_0 / COLOR_0, node hierarchies and instancing, perspective and orthographic
cameras, point / spot / directional lights (in the sidecar), baseColor / baseColorTexture /
emissive glTF materials and eyelight / lambert / phong sidecar overrides.
"""

import base64
import json
import math
import os
import re
import struct
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# glTF enums
FLOAT = 5126
UNSIGNED_BYTE = 5121
UNSIGNED_SHORT = 5123
UNSIGNED_INT = 5125
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963
NEAREST = 9728
LINEAR = 9729
LINEAR_MIPMAP_LINEAR = 9987
REPEAT = 10497
CLAMP_TO_EDGE = 33071
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
COMPONENT_SIZE = {UNSIGNED_BYTE: 1, UNSIGNED_SHORT: 2, UNSIGNED_INT: 4, FLOAT: 4}


# ---------------------------------------------------------------------------------------------
# Small vector math
# ---------------------------------------------------------------------------------------------

def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def scale(a, s):
    return tuple(x * s for x in a)


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def length(a):
    return math.sqrt(dot(a, a))


def normalize(a):
    n = length(a)
    return tuple(x / n for x in a)


def quat_axis_angle(axis, degrees):
    """glTF quaternion [x, y, z, w] rotating by `degrees` about `axis` (right-handed)."""
    ax = normalize(axis)
    h = math.radians(degrees) / 2
    s = math.sin(h)
    return [ax[0] * s, ax[1] * s, ax[2] * s, math.cos(h)]


def quat_look_at(eye, target, up=(0.0, 1.0, 0.0)):
    """Rotation that turns a glTF camera (looking down -Z, +Y up) to look from eye at target."""
    f = normalize(sub(target, eye))
    r = normalize(cross(f, up))
    u = cross(r, f)
    b = scale(f, -1)  # the camera's +Z axis points backwards
    # Columns of the rotation matrix are r, u, b.
    m00, m01, m02 = r[0], u[0], b[0]
    m10, m11, m12 = r[1], u[1], b[1]
    m20, m21, m22 = r[2], u[2], b[2]
    tr = m00 + m11 + m22
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = [(m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s]
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2
        q = [0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s]
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2
        q = [(m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s]
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2
        q = [(m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s]
    if q[3] < 0:
        q = [-x for x in q]
    return q


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def short_float(x):
    """Shortest decimal that reads back as the same float32 (exact min/max, tidy JSON)."""
    x = f32(x)
    if x == 0:
        return 0.0  # also turns -0.0 into 0.0
    for digits in range(1, 10):
        v = float("%.*g" % (digits, x))
        if f32(v) == x:
            return v
    return x


def tidy(value):
    """Recursively replaces floats by short_float; keeps ints, strings and structure."""
    if isinstance(value, float):
        return short_float(value)
    if isinstance(value, dict):
        return {k: tidy(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [tidy(v) for v in value]
    return value


def srgb_to_linear(c8):
    c = c8 / 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


# ---------------------------------------------------------------------------------------------
# PNG encoding (8-bit RGB, filter 0, one IDAT)
# ---------------------------------------------------------------------------------------------

def encode_png(width, height, pixel, alpha=False, level=9):
    """pixel(x, y) -> (r, g, b) bytes 0..255 (with a fourth, alpha, when `alpha`); y = 0 is the
    top row. `level`: zlib's compression level."""
    raw = bytearray()
    for y in range(height):
        raw.append(0)  # filter type None
        for x in range(width):
            raw.extend(bytes(pixel(x, y)))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    color_type = 6 if alpha else 2  # RGBA or RGB
    ihdr = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
            + chunk(b"IDAT", zlib.compress(bytes(raw), level)) + chunk(b"IEND", b""))


def hash01(x, y, seed=0):
    """Deterministic integer hash of a texel to [0, 1)."""
    h = (x * 374761393 + y * 668265263 + seed * 2246822519) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return ((h ^ (h >> 16)) & 0xFFFF) / 65536.0


def tile_texture():
    """128x128, one repeat = 2x2 floor tiles with grout lines and a little per-texel grain."""
    light, dark, grout = (200, 190, 172), (92, 84, 78), (44, 42, 40)

    def pixel(x, y):
        tx, ty = x // 64, y // 64
        lx, ly = x % 64, y % 64
        if lx < 2 or ly < 2:
            return grout
        base = light if (tx + ty) % 2 == 0 else dark
        g = int(round((hash01(x, y, 1) - 0.5) * 10))
        return tuple(max(0, min(255, c + g)) for c in base)

    return encode_png(128, 128, pixel)


def crate_texture():
    """64x64 wooden crate face: a dark frame around four horizontal planks with grain."""
    frame, plank = (96, 58, 30), (176, 122, 70)

    def pixel(x, y):
        edge = min(x, y, 63 - x, 63 - y)
        if edge < 7:
            base = frame
            grain = math.sin((x + y) * 0.9) * 6
            if edge == 0:
                base = (54, 34, 20)
        else:
            py = (y - 7) % 13
            if py == 0:
                return (62, 40, 22)  # gap between planks
            base = plank
            n = (y - 7) // 13
            grain = math.sin(x * 0.35 + n * 1.7 + math.sin(y * 0.6 + n) * 1.5) * 14
        g = grain + (hash01(x, y, 2) - 0.5) * 8
        return tuple(max(0, min(255, int(round(c + g)))) for c in base)

    return encode_png(64, 64, pixel)


CHECKER4_WHITE = (255, 255, 255)
CHECKER4_DARK = (64, 64, 64)
CHECKER4_MARK = (255, 0, 0)


def checker4_texture():
    """4x4 checker for textured_quad: texel (0,0) white cells where (x+y) even, dark where odd;
    the top-left texel is red to pin down orientation (glTF uv (0,0) = first texel in the file)."""
    def pixel(x, y):
        if x == 0 and y == 0:
            return CHECKER4_MARK
        return CHECKER4_WHITE if (x + y) % 2 == 0 else CHECKER4_DARK

    return encode_png(4, 4, pixel)


# ---------------------------------------------------------------------------------------------
# Mesh generators. Each returns a dict of attribute lists plus `indices` (flat list).
# ---------------------------------------------------------------------------------------------

def orient(mesh):
    """Makes every triangle wind counter-clockwise around its vertex normals (glTF front
    faces) and drops degenerate triangles (at sphere poles)."""
    p, n, idx = mesh["positions"], mesh["normals"], mesh["indices"]
    out = []
    for t in range(0, len(idx), 3):
        a, b, c = idx[t:t + 3]
        fn = cross(sub(p[b], p[a]), sub(p[c], p[a]))
        if length(fn) < 1e-12:
            continue
        if dot(fn, add(add(n[a], n[b]), n[c])) < 0:
            b, c = c, b
        out += [a, b, c]
    mesh["indices"] = out
    return mesh


def grid_indices(rows, cols, base=0):
    """Two triangles per cell of a (rows+1) x (cols+1) vertex grid, row-major."""
    idx = []
    for i in range(rows):
        for j in range(cols):
            v00 = base + i * (cols + 1) + j
            v01, v10 = v00 + 1, v00 + cols + 1
            v11 = v10 + 1
            idx += [v00, v10, v11, v00, v11, v01]
    return idx


def uv_sphere(radius, segments=48, rings=24):
    pos, nrm, uv = [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings  # from +Y (top) down
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            d = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            nrm.append(d)
            pos.append(scale(d, radius))
            uv.append((j / segments, i / rings))
    mesh = {"positions": pos, "normals": nrm, "uvs": uv, "indices": grid_indices(rings, segments)}
    return orient(mesh)


def box(sx, sy, sz):
    """Axis-aligned box centred at the origin; 4 vertices per face, uv 0..1 on each face."""
    hx, hy, hz = sx / 2, sy / 2, sz / 2
    faces = [  # normal, u axis, v axis (v points down the image = -up on the face)
        ((1, 0, 0), (0, 0, -1), (0, -1, 0)),
        ((-1, 0, 0), (0, 0, 1), (0, -1, 0)),
        ((0, 1, 0), (1, 0, 0), (0, 0, 1)),
        ((0, -1, 0), (1, 0, 0), (0, 0, -1)),
        ((0, 0, 1), (1, 0, 0), (0, -1, 0)),
        ((0, 0, -1), (-1, 0, 0), (0, -1, 0)),
    ]
    half = (hx, hy, hz)
    pos, nrm, uv, idx = [], [], [], []
    for n, u, v in faces:
        base = len(pos)
        for (cu, cv) in ((0, 0), (1, 0), (1, 1), (0, 1)):
            d = tuple(n[k] + (2 * cu - 1) * u[k] + (2 * cv - 1) * v[k] for k in range(3))
            pos.append(tuple(d[k] * half[k] for k in range(3)))
            nrm.append(tuple(float(c) for c in n))
            uv.append((float(cu), float(cv)))
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return orient({"positions": pos, "normals": nrm, "uvs": uv, "indices": idx})


def cylinder(radius, height, segments=40):
    """Capped cylinder standing on y = 0, axis +Y; smooth sides, flat caps."""
    pos, nrm, uv, idx = [], [], [], []
    for i in range(2):  # side: two rings
        y = height * (1 - i)
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            d = (math.cos(phi), 0.0, -math.sin(phi))
            pos.append((radius * d[0], y, radius * d[2]))
            nrm.append(d)
            uv.append((j / segments, float(i)))
    idx += grid_indices(1, segments)
    for y, ny in ((height, 1.0), (0.0, -1.0)):  # caps: centre + rim fan
        centre = len(pos)
        pos.append((0.0, y, 0.0))
        nrm.append((0.0, ny, 0.0))
        uv.append((0.5, 0.5))
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            c, s = math.cos(phi), math.sin(phi)
            pos.append((radius * c, y, -radius * s))
            nrm.append((0.0, ny, 0.0))
            uv.append((0.5 + 0.5 * c, 0.5 + 0.5 * s))
        for j in range(segments):
            idx += [centre, centre + 1 + j, centre + 1 + (j + 1) % segments]
    return orient({"positions": pos, "normals": nrm, "uvs": uv, "indices": idx})


def hue_rgb(h):
    """Fully saturated hue h in [0, 1) as linear RGB, softened towards white a little."""
    r = max(0.0, min(1.0, abs(h * 6 - 3) - 1))
    g = max(0.0, min(1.0, 2 - abs(h * 6 - 2)))
    b = max(0.0, min(1.0, 2 - abs(h * 6 - 4)))
    return tuple(0.15 + 0.8 * c for c in (r, g, b))


def torus(major, minor, segments=64, sides=24):
    """Torus around +Y with a rainbow COLOR_0 (VEC3) running around the ring."""
    pos, nrm, uv, col = [], [], [], []
    for i in range(segments + 1):
        phi = 2 * math.pi * i / segments
        cp, sp = math.cos(phi), -math.sin(phi)
        for j in range(sides + 1):
            th = 2 * math.pi * j / sides
            n = (math.cos(th) * cp, math.sin(th), math.cos(th) * sp)
            nrm.append(n)
            pos.append(((major + minor * math.cos(th)) * cp, minor * math.sin(th),
                        (major + minor * math.cos(th)) * sp))
            uv.append((i / segments, j / sides))
            col.append(hue_rgb((i % segments) / segments))
    mesh = {"positions": pos, "normals": nrm, "uvs": uv, "colors": col,
            "indices": grid_indices(segments, sides)}
    return orient(mesh)


def plane(size, uv_repeat):
    """Square in the XZ plane at y = 0, normal +Y, centred at the origin."""
    h = size / 2
    pos = [(-h, 0.0, -h), (h, 0.0, -h), (h, 0.0, h), (-h, 0.0, h)]
    uv = [(0.0, 0.0), (uv_repeat, 0.0), (uv_repeat, uv_repeat), (0.0, uv_repeat)]
    nrm = [(0.0, 1.0, 0.0)] * 4
    return orient({"positions": pos, "normals": nrm, "uvs": uv, "indices": [0, 2, 1, 0, 3, 2]})


# ---------------------------------------------------------------------------------------------
# glTF document builder: one embedded buffer, 4-byte aligned bufferViews
# ---------------------------------------------------------------------------------------------

class Gltf:
    def __init__(self):
        self.doc = {
            "asset": {"version": "2.0", "generator": "glint scripts/make_scenes.py"},
            "scene": 0,
            "scenes": [],
            "nodes": [],
            "cameras": [],
            "meshes": [],
            "materials": [],
            "textures": [],
            "images": [],
            "samplers": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }
        self.bin = bytearray()

    def _add(self, key, item):
        self.doc[key].append(item)
        return len(self.doc[key]) - 1

    def buffer_view(self, data, target, stride=None):
        while len(self.bin) % 4:
            self.bin.append(0)
        view = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride is not None:
            view["byteStride"] = stride
        view["target"] = target
        self.bin.extend(data)
        return self._add("bufferViews", view)

    def accessor(self, view, component_type, count, kind, byte_offset=0, minmax=None,
                 normalized=False):
        acc = {"bufferView": view}
        if byte_offset:
            acc["byteOffset"] = byte_offset
        acc["componentType"] = component_type
        if normalized:
            acc["normalized"] = True
        acc["count"] = count
        acc["type"] = kind
        if minmax is not None:
            acc["min"], acc["max"] = minmax
        return self._add("accessors", acc)

    @staticmethod
    def minmax(rows):
        rows = [[f32(c) for c in r] for r in rows]
        n = len(rows[0])
        return ([min(r[k] for r in rows) for k in range(n)],
                [max(r[k] for r in rows) for k in range(n)])

    def floats(self, rows, kind, with_minmax=False):
        data = b"".join(struct.pack("<%df" % len(r), *r) for r in rows)
        view = self.buffer_view(data, ARRAY_BUFFER)
        mm = self.minmax(rows) if with_minmax else None
        return self.accessor(view, FLOAT, len(rows), kind, minmax=mm)

    def indices(self, idx, component_type=None):
        if component_type is None:
            component_type = UNSIGNED_SHORT if max(idx) < 65535 else UNSIGNED_INT
        fmt = {UNSIGNED_BYTE: "B", UNSIGNED_SHORT: "H", UNSIGNED_INT: "I"}[component_type]
        view = self.buffer_view(struct.pack("<%d%s" % (len(idx), fmt), *idx), ELEMENT_ARRAY_BUFFER)
        return self.accessor(view, component_type, len(idx), "SCALAR")

    def geometry(self, mesh, uvs=False):
        """Writes a generated mesh's attributes; returns the primitive's attributes/indices.
        TEXCOORD_0 only when asked for: only textured materials use it."""
        attrs = {"POSITION": self.floats(mesh["positions"], "VEC3", with_minmax=True),
                 "NORMAL": self.floats(mesh["normals"], "VEC3")}
        if uvs:
            attrs["TEXCOORD_0"] = self.floats(mesh["uvs"], "VEC2")
        if "colors" in mesh:
            kind = "VEC%d" % len(mesh["colors"][0])
            attrs["COLOR_0"] = self.floats(mesh["colors"], kind)
        return {"attributes": attrs, "indices": self.indices(mesh["indices"])}

    def mesh(self, name, geometry, material=None):
        prim = dict(geometry)
        if material is not None:
            prim["material"] = material
        return self._add("meshes", {"name": name, "primitives": [prim]})

    def material(self, name, base_color=(1, 1, 1, 1), texture=None, emissive=None,
                 double_sided=False):
        pbr = {"baseColorFactor": list(base_color)}
        if texture is not None:
            pbr["baseColorTexture"] = {"index": texture}
        pbr["metallicFactor"] = 0.0
        pbr["roughnessFactor"] = 1.0
        mat = {"name": name, "pbrMetallicRoughness": pbr}
        if emissive is not None:
            mat["emissiveFactor"] = list(emissive)
        if double_sided:
            mat["doubleSided"] = True
        return self._add("materials", mat)

    def texture(self, name, png, mag, min_, wrap):
        image = self._add("images", {
            "name": name, "uri": "data:image/png;base64," + base64.b64encode(png).decode("ascii")})
        sampler = self._add("samplers", {"magFilter": mag, "minFilter": min_,
                                         "wrapS": wrap, "wrapT": wrap})
        return self._add("textures", {"name": name, "sampler": sampler, "source": image})

    def perspective_camera(self, name, yfov, aspect, znear=0.1, zfar=100.0):
        return self._add("cameras", {"name": name, "type": "perspective", "perspective": {
            "aspectRatio": aspect, "yfov": yfov, "zfar": zfar, "znear": znear}})

    def orthographic_camera(self, name, xmag, ymag, znear=0.1, zfar=100.0):
        return self._add("cameras", {"name": name, "type": "orthographic", "orthographic": {
            "xmag": xmag, "ymag": ymag, "zfar": zfar, "znear": znear}})

    def node(self, name, mesh=None, camera=None, translation=None, rotation=None, scale_=None,
             children=None):
        node = {"name": name}
        if mesh is not None:
            node["mesh"] = mesh
        if camera is not None:
            node["camera"] = camera
        if children:
            node["children"] = children
        if translation is not None:
            node["translation"] = list(translation)
        if rotation is not None:
            node["rotation"] = list(rotation)
        if scale_ is not None:
            node["scale"] = list(scale_)
        return self._add("nodes", node)

    def finish(self, scene_name, roots):
        self.doc["scenes"].append({"name": scene_name, "nodes": roots})
        while len(self.bin) % 4:
            self.bin.append(0)
        self.doc["buffers"].append({
            "byteLength": len(self.bin),
            "uri": "data:application/octet-stream;base64,"
                   + base64.b64encode(bytes(self.bin)).decode("ascii")})
        doc = {k: v for k, v in self.doc.items() if v != []}
        return tidy(doc)


def write_json(relpath, doc):
    path = os.path.join(ROOT, relpath)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    text = json.dumps(tidy(doc), indent=1, ensure_ascii=True) + "\n"
    # Put short lists of numbers on one line: readable diffs without one number per line.
    text = re.sub(r"\[\s+(-?[\d.e+-]+(?:,\s+-?[\d.e+-]+){0,15})\s+\]",
                  lambda m: "[" + re.sub(r",\s+", ", ", m.group(1)) + "]", text)
    with open(path, "w", encoding="ascii", newline="\n") as f:
        f.write(text)
    print("wrote", relpath, "(%d bytes)" % len(text))


# ---------------------------------------------------------------------------------------------
# The demo still life
# ---------------------------------------------------------------------------------------------

DEMO_CAMERA_EYE = (0.0, 2.5, 6.8)
DEMO_CAMERA_TARGET = (0.0, 0.65, 0.0)


def make_demo():
    g = Gltf()

    # Materials. "Ceramic", "Stone" and "Marble" are overridden by the sidecar.
    tiles_tex = g.texture("FloorTiles", tile_texture(), LINEAR, LINEAR_MIPMAP_LINEAR, REPEAT)
    crate_tex = g.texture("CrateWood", crate_texture(), LINEAR, LINEAR_MIPMAP_LINEAR, CLAMP_TO_EDGE)
    m_floor = g.material("Floor", texture=tiles_tex)
    m_ceramic = g.material("Ceramic", (0.6, 0.12, 0.08, 1.0))
    m_stone = g.material("Stone", (0.45, 0.44, 0.4, 1.0))
    m_marble = g.material("Marble", (0.8, 0.78, 0.74, 1.0))
    m_crate = g.material("Crate", texture=crate_tex)
    m_rainbow = g.material("Rainbow", (1.0, 1.0, 1.0, 1.0))
    m_glow = g.material("Glow", (0.05, 0.05, 0.05, 1.0), emissive=(0.95, 0.5, 0.15))

    # Meshes. The sphere's geometry is shared by two meshes with different materials.
    floor = g.mesh("Floor", g.geometry(plane(24.0, 24.0), uvs=True), m_floor)
    sphere_geo = g.geometry(uv_sphere(1.0, 64, 32))
    sphere = g.mesh("CeramicSphere", sphere_geo, m_ceramic)
    orb = g.mesh("GlowOrb", sphere_geo, m_glow)
    column = g.mesh("Column", g.geometry(cylinder(0.2, 2.0, 40)), m_marble)
    crate = g.mesh("Crate", g.geometry(box(0.9, 0.9, 0.9), uvs=True), m_crate)
    plinth = g.mesh("Plinth", g.geometry(box(1.1, 0.35, 1.1)), m_stone)
    ring = g.mesh("RainbowRing", g.geometry(torus(0.5, 0.16, 72, 24)), m_rainbow)

    roots = [g.node("Floor", mesh=floor)]
    # A colonnade: one mesh, five nodes.
    for i, x in enumerate((-3.0, -1.5, 0.0, 1.5, 3.0)):
        roots.append(g.node("Column.%d" % (i + 1), mesh=column, translation=(x, 0.0, -2.8)))
    roots.append(g.node("Sphere", mesh=sphere, translation=(0.15, 0.75, 0.35),
                        scale_=(0.75, 0.75, 0.75)))
    roots.append(g.node("Crate", mesh=crate, translation=(1.95, 0.45, -0.1),
                        rotation=quat_axis_angle((0, 1, 0), -28)))
    roots.append(g.node("Orb", mesh=orb, translation=(1.05, 0.22, 1.75), scale_=(0.22, 0.22, 0.22)))
    # A node hierarchy: the turntable turns both the plinth and the upright ring standing on it.
    plinth_node = g.node("Plinth", mesh=plinth, translation=(0.0, 0.175, 0.0))
    ring_node = g.node("Ring", mesh=ring, translation=(0.0, 0.35 + 0.5 + 0.16, 0.0),
                       rotation=quat_axis_angle((1, 0, 0), 90))
    roots.append(g.node("Turntable", translation=(-1.85, 0.0, 0.1),
                        rotation=quat_axis_angle((0, 1, 0), 35), children=[plinth_node, ring_node]))
    cam = g.perspective_camera("Main", 0.55, 16.0 / 9.0, 0.1, 100.0)
    roots.append(g.node("Main", camera=cam, translation=DEMO_CAMERA_EYE,
                        rotation=quat_look_at(DEMO_CAMERA_EYE, DEMO_CAMERA_TARGET)))
    write_json("scenes/demo/demo.gltf", g.finish("Still life", roots))

    sidecar = {
        "render": {"width": 800, "height": 450, "spp": 32, "seed": 0, "camera": "Main",
                   "filter": {"type": "gaussian", "radius": 1.5},
                   "background": [0.02, 0.02, 0.03],
                   "tonemap": {"exposure": 0.0, "operator": "none"}},
        "lights": [
            {"name": "Key", "type": "spot", "position": [2.5, 5.0, 3.5],
             "look_at": [0.0, 0.5, 0.0], "inner_cone_degrees": 18, "outer_cone_degrees": 38,
             "color": [1.0, 0.88, 0.72], "intensity": 140},
            {"name": "Fill", "type": "point", "position": [-4.0, 3.0, 3.0],
             "color": [0.6, 0.7, 1.0], "intensity": 40},
            {"name": "Sun", "type": "directional", "direction": [-0.3, -1.0, -0.2],
             "color": [1.0, 0.97, 0.92], "intensity": 0.6},
        ],
        "materials": [
            {"name": "Ceramic", "type": "phong", "diffuse": [0.6, 0.12, 0.08],
             "specular": [0.4, 0.4, 0.4], "shininess": 60},
            {"name": "Marble", "type": "phong", "diffuse": [0.8, 0.78, 0.74],
             "specular": [0.2, 0.2, 0.2], "shininess": 25},
            {"name": "Stone", "type": "lambert", "diffuse": [0.45, 0.44, 0.4]},
        ],
    }
    write_json("scenes/demo/demo.glint.json", sidecar)


# ---------------------------------------------------------------------------------------------
# Test scenes
# ---------------------------------------------------------------------------------------------

TOP_DOWN = quat_axis_angle((1, 0, 0), -90)  # camera -Z -> world -Y, camera +Y -> world -Z


def make_lambert_plane():
    g = Gltf()
    m = g.material("Plane", (0.5, 0.5, 0.5, 1.0))
    mesh = g.mesh("Plane", g.geometry(plane(20.0, 1.0)), m)
    cam = g.orthographic_camera("Top", 1.0, 1.0, 0.1, 100.0)
    roots = [g.node("Plane", mesh=mesh),
             g.node("Top", camera=cam, translation=(0.0, 10.0, 0.0), rotation=TOP_DOWN)]
    write_json("tests/data/scenes/lambert_plane.gltf", g.finish("Lambert plane", roots))
    write_json("tests/data/scenes/lambert_plane.glint.json", {
        "render": {"width": 64, "height": 64, "spp": 16, "seed": 0, "camera": "Top",
                   "filter": {"type": "box", "radius": 0.5}, "background": [0.0, 0.0, 0.0]},
        "lights": [{"name": "Bulb", "type": "point", "position": [0.0, 2.0, 0.0],
                    "color": [1.0, 1.0, 1.0], "intensity": 10}],
        "materials": [{"name": "Plane", "type": "lambert", "diffuse": [0.5, 0.5, 0.5]}],
    })


def make_two_instances():
    g = Gltf()
    cube = g.mesh("Cube", g.geometry(box(1.0, 1.0, 1.0)))  # no material: the default one
    eye, target = (0.0, 2.0, 6.0), (0.0, 0.0, 0.0)
    cam = g.perspective_camera("View", 0.6, 1.5, 0.1, 100.0)
    roots = [g.node("CubeLeft", mesh=cube, translation=(-1.5, 0.0, 0.0)),
             g.node("CubeRight", mesh=cube, translation=(1.5, 0.0, 0.0)),
             g.node("View", camera=cam, translation=eye, rotation=quat_look_at(eye, target))]
    write_json("tests/data/scenes/two_instances.gltf", g.finish("Two instances", roots))


def make_textured_quad():
    g = Gltf()
    tex = g.texture("Checker4", checker4_texture(), NEAREST, NEAREST, CLAMP_TO_EDGE)
    m = g.material("Checker", texture=tex, emissive=(0.0, 0.0, 0.0))
    quad = {"positions": [(-1.0, 1.0, 0.0), (1.0, 1.0, 0.0), (1.0, -1.0, 0.0), (-1.0, -1.0, 0.0)],
            "normals": [(0.0, 0.0, 1.0)] * 4,
            "uvs": [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
            "indices": [0, 3, 2, 0, 2, 1]}
    mesh = g.mesh("Quad", g.geometry(orient(quad), uvs=True), m)
    cam = g.orthographic_camera("Front", 1.0, 1.0, 0.1, 100.0)
    roots = [g.node("Quad", mesh=mesh),
             g.node("Front", camera=cam, translation=(0.0, 0.0, 5.0))]
    write_json("tests/data/scenes/textured_quad.gltf", g.finish("Textured quad", roots))
    write_json("tests/data/scenes/textured_quad.glint.json", {
        "render": {"width": 64, "height": 64, "spp": 4, "seed": 0, "camera": "Front",
                   "filter": {"type": "box", "radius": 0.5}, "background": [0.0, 0.0, 0.0]},
        "materials": [{"name": "Checker", "type": "eyelight"}],
    })


def make_vertex_colors():
    g = Gltf()
    positions = [(-1.0, -1.0, 0.0), (1.0, -1.0, 0.0), (0.0, 1.0, 0.0)]
    colors = [(1.0, 0.0, 0.0, 1.0), (0.0, 1.0, 0.0, 1.0), (0.0, 0.0, 1.0, 1.0)]
    # Interleaved: position (12 bytes) then colour (16 bytes) per vertex, stride 28.
    data = b"".join(struct.pack("<3f4f", *p, *c) for p, c in zip(positions, colors))
    view = g.buffer_view(data, ARRAY_BUFFER, stride=28)
    pos = g.accessor(view, FLOAT, 3, "VEC3", 0, g.minmax(positions))
    col = g.accessor(view, FLOAT, 3, "VEC4", 12)
    idx = g.indices([0, 1, 2], UNSIGNED_BYTE)
    m = g.material("Triangle", (1.0, 1.0, 1.0, 1.0))
    mesh = g.mesh("Triangle", {"attributes": {"POSITION": pos, "COLOR_0": col}, "indices": idx}, m)
    cam = g.orthographic_camera("Front", 1.0, 1.0, 0.1, 100.0)
    roots = [g.node("Triangle", mesh=mesh),
             g.node("Front", camera=cam, translation=(0.0, 0.0, 5.0))]
    write_json("tests/data/scenes/vertex_colors.gltf", g.finish("Vertex colours", roots))
    write_json("tests/data/scenes/vertex_colors.glint.json", {
        "render": {"width": 64, "height": 64, "spp": 4, "seed": 0, "camera": "Front",
                   "filter": {"type": "box", "radius": 0.5}, "background": [0.0, 0.0, 0.0]},
        "materials": [{"name": "Triangle", "type": "eyelight"}],
    })

# ---------------------------------------------------------------------------------------------
# Validation: re-reads every written .gltf and checks what glTF 2.0 requires of it
# ---------------------------------------------------------------------------------------------

def decode_data_uri(uri, mime):
    prefix = "data:%s;base64," % mime
    assert uri.startswith(prefix), uri[:40]
    return base64.b64decode(uri[len(prefix):], validate=True)


def decode_png(data):
    """Returns (width, height, channels, rows) of an 8-bit non-interlaced PNG; checks CRCs."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "PNG signature"
    pos, idat, ihdr = 8, b"", None
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        (crc,) = struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])
        assert crc == zlib.crc32(kind + body) & 0xFFFFFFFF, "PNG CRC of %r" % kind
        if kind == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
        if kind == b"IEND":
            break
    w, h, depth, ctype, _, _, interlace = ihdr
    assert depth == 8 and ctype == 2 and interlace == 0, ihdr
    raw = zlib.decompress(idat)
    assert len(raw) == h * (1 + 3 * w), "PNG data size"
    rows = [raw[y * (1 + 3 * w) + 1:(y + 1) * (1 + 3 * w)] for y in range(h)]
    assert all(raw[y * (1 + 3 * w)] == 0 for y in range(h))
    return w, h, 3, rows


def read_accessor(doc, buf, index):
    acc = doc["accessors"][index]
    view = doc["bufferViews"][acc["bufferView"]]
    ctype, kind, count = acc["componentType"], acc["type"], acc["count"]
    ncomp, csize = COMPONENTS[kind], COMPONENT_SIZE[ctype]
    elem = ncomp * csize
    stride = view.get("byteStride", elem)
    offset = acc.get("byteOffset", 0)
    assert (view["byteOffset"] + offset) % csize == 0, "accessor %d misaligned" % index
    assert stride % 4 == 0 and 4 <= stride <= 252 or "byteStride" not in view
    assert offset + stride * (count - 1) + elem <= view["byteLength"], \
        "accessor %d overflows its bufferView" % index
    fmt = "<%d%s" % (ncomp, {FLOAT: "f", UNSIGNED_BYTE: "B", UNSIGNED_SHORT: "H",
                             UNSIGNED_INT: "I"}[ctype])
    base = view["byteOffset"] + offset
    return [struct.unpack_from(fmt, buf, base + i * stride) for i in range(count)]


def validate_gltf(relpath):
    with open(os.path.join(ROOT, relpath), encoding="ascii") as f:
        doc = json.load(f)
    assert doc["asset"]["version"] == "2.0"
    assert len(doc["buffers"]) == 1
    buf = decode_data_uri(doc["buffers"][0]["uri"], "application/octet-stream")
    assert len(buf) == doc["buffers"][0]["byteLength"]
    users = {}
    for acc in doc["accessors"]:
        users[acc["bufferView"]] = users.get(acc["bufferView"], 0) + 1
    for i, view in enumerate(doc["bufferViews"]):
        assert view["buffer"] == 0 and view["byteOffset"] % 4 == 0
        assert view["byteOffset"] + view["byteLength"] <= len(buf)
        assert view["target"] in (ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER)
        if users.get(i, 0) > 1:
            assert "byteStride" in view, "shared bufferView %d needs byteStride" % i
        assert users.get(i, 0) >= 1, "unused bufferView %d" % i
    for mesh in doc["meshes"]:
        for prim in mesh["primitives"]:
            attrs = prim["attributes"]
            pos = read_accessor(doc, buf, attrs["POSITION"])
            acc = doc["accessors"][attrs["POSITION"]]
            assert acc["type"] == "VEC3" and acc["componentType"] == FLOAT
            mins = [min(p[k] for p in pos) for k in range(3)]
            maxs = [max(p[k] for p in pos) for k in range(3)]
            assert [f32(v) for v in acc["min"]] == mins and [f32(v) for v in acc["max"]] == maxs, \
                "POSITION min/max of %s" % mesh["name"]
            for name, index in attrs.items():
                a = doc["accessors"][index]
                assert a["count"] == len(pos), name
                assert doc["bufferViews"][a["bufferView"]]["target"] == ARRAY_BUFFER
                values = read_accessor(doc, buf, index)
                assert all(math.isfinite(c) for v in values for c in v)
                if name == "NORMAL":
                    assert all(abs(length(n) - 1) < 1e-5 for n in values), "unit normals"
                if name == "COLOR_0":
                    assert a["type"] in ("VEC3", "VEC4")
                    assert all(0 <= c <= 1 for v in values for c in v)
            ia = doc["accessors"][prim["indices"]]
            assert ia["type"] == "SCALAR" and ia["componentType"] in (UNSIGNED_BYTE, UNSIGNED_SHORT,
                                                                       UNSIGNED_INT)
            iview = doc["bufferViews"][ia["bufferView"]]
            assert iview["target"] == ELEMENT_ARRAY_BUFFER and "byteStride" not in iview
            idx = [i[0] for i in read_accessor(doc, buf, prim["indices"])]
            assert len(idx) % 3 == 0 and all(0 <= i < len(pos) for i in idx)
            if "NORMAL" in attrs:  # counter-clockwise fronts agree with the shading normals
                nrm = read_accessor(doc, buf, attrs["NORMAL"])
                for t in range(0, len(idx), 3):
                    a, b, c = idx[t:t + 3]
                    fn = cross(sub(pos[b], pos[a]), sub(pos[c], pos[a]))
                    assert length(fn) > 0, "degenerate triangle"
                    assert dot(fn, add(add(nrm[a], nrm[b]), nrm[c])) > 0, "winding"
            if "material" in prim:
                assert 0 <= prim["material"] < len(doc["materials"])
    for mat in doc.get("materials", []):
        tex = mat["pbrMetallicRoughness"].get("baseColorTexture")
        if tex is not None:
            assert 0 <= tex["index"] < len(doc["textures"])
    for tex in doc.get("textures", []):
        assert 0 <= tex["sampler"] < len(doc["samplers"])
        image = doc["images"][tex["source"]]
        w, h, _, _ = decode_png(decode_data_uri(image["uri"], "image/png"))
        assert w > 0 and h > 0
    parents = {}
    for i, node in enumerate(doc["nodes"]):
        for c in node.get("children", []):
            assert c not in parents and c != i, "node %d has two parents" % c
            parents[c] = i
        if "rotation" in node:
            assert abs(length(node["rotation"]) - 1) < 1e-6
        if "mesh" in node:
            assert 0 <= node["mesh"] < len(doc["meshes"])
        if "camera" in node:
            assert 0 <= node["camera"] < len(doc["cameras"])
    for root in doc["scenes"][0]["nodes"]:
        assert root not in parents
    for cam in doc.get("cameras", []):
        p = cam[cam["type"]]
        if cam["type"] == "perspective":
            assert 0 < p["yfov"] < math.pi and p["znear"] > 0 and p.get("zfar", 1e30) > p["znear"]
        else:
            assert p["xmag"] != 0 and p["ymag"] != 0 and p["zfar"] > p["znear"] >= 0
    return doc


def validate_all():
    for rel in ("scenes/demo/demo.gltf", "tests/data/scenes/lambert_plane.gltf",
                "tests/data/scenes/two_instances.gltf", "tests/data/scenes/textured_quad.gltf",
                "tests/data/scenes/vertex_colors.gltf"):
        validate_gltf(rel)
        print("valid", rel)


def main():
    make_demo()
    make_lambert_plane()
    make_two_instances()
    make_textured_quad()
    make_vertex_colors()
    validate_all()


if __name__ == "__main__":
    main()
