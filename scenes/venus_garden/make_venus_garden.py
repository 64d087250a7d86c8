#!/usr/bin/env python3
"""Generates the "Venus Garden" showcase scene (after Torsten Gruendel's 2007/2008 rendering
competition animation).

    /usr/bin/python3 scenes/venus_garden/make_venus_garden.py     # from anywhere

Writes, beside this script:
  venus_garden.gltf  the generated meshes: the Venus stand-in (a lathed figure with arms on a
                     lathed pedestal), the instanced lamp posts and the two gate leaves, whose
                     opening is a glTF animation (rotation about each hinge)
  venus_garden.json  the glint scene: the glTF above, the two Stanford dragons, analytic
                     objects (ground, sidewalk, walls, columns), fog and lamp-glow media, lights
                     (lamps, the projective cloud light, a dim moon), marble / bump materials,
                     the keyframed camera and the render settings

Deterministic (same bytes on every run), standard library only; the glTF helpers (buffers,
accessors, short float formatting) come from scripts/make_scenes.py.
"""

import json
import math
import os
import re
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "scripts"))

from make_scenes import (FLOAT, Gltf, add, box, cross, length, normalize, orient,  # noqa: E402
                         quat_axis_angle, scale, sub, tidy, uv_sphere)

FPS = 24
DURATION = 15.0          # seconds: frames 0 .. 360

# ---------------------------------------------------------------------------------------------
# Layout (metres, +Y up). The sidewalk runs along +Z towards the gate in the front wall (z = 0);
# the walled garden lies behind it (z < 0) with the statue at its centre.
# ---------------------------------------------------------------------------------------------

GATE_HALF = 1.5                 # the opening spans x in [-1.5, 1.5]
GATE_HEIGHT = 2.5
GATE_Z = -0.2                   # hinge line (middle of the 0.4 m thick front wall)
WALL_HEIGHT = 3.2
GARDEN_HALF = 12.0              # garden interior x in [-12, 12]
GARDEN_DEPTH = 22.0             # garden interior z in [-22, -0.4]
STATUE = (0.0, 0.0, -10.0)
LAMP_ZS = (25.0, 18.2, 11.4, 4.6)
LAMP_X = 2.1
LAMP_LIGHT_Y = 3.0
DRAGON_X = 2.5
DRAGON_Z = 1.1

# Timeline (seconds).
T_ARRIVE = 5.5                  # the camera stops in front of the gate
T_GATE_OPEN = (5.8, 8.8)        # the gate leaves swing open
T_ENTER = 12.2                  # through the gate, facing the statue
T_END = DURATION
HERO_TIME = 7.75                # frame 186: the gate opening, dragons, shafts beyond


# ---------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------

def lathe(profile, segments=48, smooth=True, squash_z=1.0, offset=(0.0, 0.0, 0.0)):
    """Surface of revolution of `profile`, a list of (radius, y) from bottom to top, about +Y.
    smooth: normals averaged across profile vertices (organic shapes); otherwise each profile
    segment gets its own rings (crisp mouldings). squash_z scales the section's z (an ellipse)."""
    pos, nrm, uv, idx = [], [], [], []

    def seg_normal(i):
        (r0, y0), (r1, y1) = profile[i], profile[i + 1]
        dr, dy = r1 - r0, y1 - y0
        n = (dy, -dr)  # outward normal of the profile segment in (r, y)
        l = math.hypot(*n)
        return (n[0] / l, n[1] / l) if l > 0 else (0.0, 1.0)

    def ring(r, y, n2, v):
        base = len(pos)
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            c, s = math.cos(phi), -math.sin(phi)
            pos.append((offset[0] + r * c, offset[1] + y, offset[2] + r * s * squash_z))
            # The normal of an ellipse-section surface: scale the section normal's z by 1/squash.
            nn = normalize((n2[0] * c, n2[1], n2[0] * s / squash_z))
            nrm.append(nn)
            uv.append((j / segments, v))
        return base

    n = len(profile)
    if smooth:
        bases = []
        for i, (r, y) in enumerate(profile):
            ns = [seg_normal(k) for k in (i - 1, i) if 0 <= k < n - 1]
            avg = (sum(a for a, _ in ns), sum(b for _, b in ns))
            l = math.hypot(*avg)
            bases.append(ring(r, y, (avg[0] / l, avg[1] / l), i / (n - 1)))
        for i in range(n - 1):
            for j in range(segments):
                a, b = bases[i] + j, bases[i] + j + 1
                c, d = bases[i + 1] + j, bases[i + 1] + j + 1
                idx += [a, c, d, a, d, b]
    else:
        for i in range(n - 1):
            n2 = seg_normal(i)
            b0 = ring(profile[i][0], profile[i][1], n2, i / (n - 1))
            b1 = ring(profile[i + 1][0], profile[i + 1][1], n2, (i + 1) / (n - 1))
            for j in range(segments):
                idx += [b0 + j, b1 + j, b1 + j + 1, b0 + j, b1 + j + 1, b0 + j + 1]
    return orient({"positions": pos, "normals": nrm, "uvs": uv, "indices": idx})


def transformed(mesh, m):
    """Mesh under the 3x4 affine matrix m (rows); normals by the inverse transpose."""
    a = [row[:3] for row in m]
    det = (a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
           - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
           + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]))
    cof = [[a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3]
            - a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3] for j in range(3)]
           for i in range(3)]  # cofactor matrix = det * inverse transpose
    pos = [tuple(sum(m[r][k] * p[k] for k in range(3)) + m[r][3] for r in range(3))
           for p in mesh["positions"]]
    nrm = [normalize(tuple(sum(cof[r][k] * q[k] for k in range(3)) * (1 if det > 0 else -1)
                           for r in range(3))) for q in mesh["normals"]]
    return orient({"positions": pos, "normals": nrm, "uvs": list(mesh["uvs"]),
                   "indices": list(mesh["indices"])})


def merge(*meshes):
    out = {"positions": [], "normals": [], "uvs": [], "indices": []}
    for m in meshes:
        base = len(out["positions"])
        out["positions"] += m["positions"]
        out["normals"] += m["normals"]
        out["uvs"] += m["uvs"]
        out["indices"] += [i + base for i in m["indices"]]
    return out


def translated(mesh, t):
    return transformed(mesh, [[1, 0, 0, t[0]], [0, 1, 0, t[1]], [0, 0, 1, t[2]]])


def venus_figure():
    """A draped standing figure, 2.25 m: robe, hips, waist, bust, shoulders, neck, head, with
    two arms (stretched spheres) hanging at the sides and a bun of hair."""
    body = lathe([
        (0.001, 0.0), (0.40, 0.0), (0.41, 0.06), (0.37, 0.22), (0.32, 0.45), (0.27, 0.70),
        (0.235, 0.92), (0.225, 1.05), (0.245, 1.20), (0.25, 1.30), (0.225, 1.42), (0.18, 1.55),
        (0.175, 1.62), (0.20, 1.70), (0.205, 1.76), (0.215, 1.84), (0.20, 1.90), (0.13, 1.95),
        (0.065, 1.98), (0.06, 2.03), (0.075, 2.06), (0.105, 2.11), (0.112, 2.17), (0.10, 2.23),
        (0.065, 2.27), (0.001, 2.29)], segments=56, smooth=True, squash_z=0.72)
    arm = uv_sphere(1.0, segments=24, rings=16)

    def arm_at(side):
        # A limb 0.85 long and 0.06 thick, tilted outward a little, from the shoulder down.
        tilt = math.radians(8 * side)
        c, s = math.cos(tilt), math.sin(tilt)
        sx, sy, sz = 0.062, 0.43, 0.07
        # scale, then rotate about z, then move to the shoulder joint's mid-limb point
        cx, cy = side * 0.235, 1.47
        return transformed(arm, [[c * sx, -s * sy, 0, cx], [s * sx, c * sy, 0, cy],
                                 [0, 0, sz, 0.02]])

    bun = transformed(uv_sphere(1.0, segments=20, rings=12),
                      [[0.075, 0, 0, 0], [0, 0.065, 0, 2.2], [0, 0, 0.075, -0.085]])
    return merge(body, arm_at(-1), arm_at(1), bun)


def pedestal():
    """A moulded stone pedestal, 1.1 m tall: plinth, torus-like base, shaft, cornice."""
    return lathe([
        (0.0, 0.0), (0.78, 0.0), (0.78, 0.16), (0.68, 0.16), (0.68, 0.24), (0.6, 0.30),
        (0.55, 0.36), (0.52, 0.40), (0.52, 0.88), (0.56, 0.92), (0.62, 0.96), (0.66, 0.96),
        (0.66, 1.1), (0.0, 1.1)], segments=48, smooth=False)


def lamp_post():
    """Cast-iron lamp post with a hood; the lamp's light sits under the hood at y = 3.0, above
    the post's thin tip (so the post shadows only a small disk around its foot)."""
    post = lathe([
        (0.0, 0.0), (0.17, 0.0), (0.17, 0.25), (0.12, 0.30), (0.09, 0.42), (0.065, 0.55),
        (0.05, 0.8), (0.04, 2.55), (0.055, 2.6), (0.055, 2.66), (0.025, 2.7), (0.018, 2.8),
        (0.0, 2.84)], segments=24, smooth=False)
    hood = lathe([
        (0.0, 3.12), (0.06, 3.14), (0.22, 3.16), (0.26, 3.13), (0.24, 3.19), (0.08, 3.32),
        (0.03, 3.42), (0.0, 3.46)], segments=24, smooth=False)
    # Four thin struts from the post's collar up to the hood's rim.
    struts = []
    for k in range(4):
        a = math.pi / 4 + k * math.pi / 2
        c, s = math.cos(a), math.sin(a)
        strut = box(0.016, 0.55, 0.016)
        # tilt outward: from (0.055, 2.63) to (0.22, 3.15) in the post's radial plane
        dr, dy = 0.165, 0.52
        ang = math.atan2(dr, dy)
        ca, sa = math.cos(ang), math.sin(ang)
        # rotate about the tangent axis so +y leans towards the radial direction (c, 0, -s)
        rx, rz = c, -s
        # y axis -> (sa * rx, ca, sa * rz); radial axis -> (ca * rx, -sa, ca * rz); tangent kept
        tx, tz = -rz, rx
        m = [[ca * rx, sa * rx, tx, 0.1375 * rx], [-sa, ca, 0, 2.89],
             [ca * rz, sa * rz, tz, 0.1375 * rz]]
        struts.append(transformed(strut, m))
    return merge(post, hood, *struts)


def gate_leaf(side):
    """One wrought-iron gate leaf in its hinge frame: the hinge at the origin, the leaf
    extending along +x (side = -1, the left leaf) or -x (side = +1), bars along y."""
    w = GATE_HALF - 0.02
    parts = []
    sgn = -side  # direction from the hinge towards the opening's centre

    def piece(cx, cy, sx, sy, sz):
        parts.append(translated(box(sx, sy, sz), (sgn * cx, cy, 0.0)))

    piece(0.03, GATE_HEIGHT / 2 + 0.05, 0.06, GATE_HEIGHT - 0.1, 0.07)      # hinge stile
    piece(w - 0.03, GATE_HEIGHT / 2, 0.06, GATE_HEIGHT - 0.2, 0.07)         # meeting stile
    for y in (0.22, 1.05, GATE_HEIGHT - 0.35):                              # rails
        piece(w / 2, y, w, 0.06, 0.06)
    nbars = 9
    for k in range(nbars):
        x = 0.06 + (w - 0.12) * (k + 0.5) / nbars
        top = GATE_HEIGHT - 0.1 + 0.3 * math.sin(0.5 * math.pi * x / w)  # rising to the middle
        piece(x, (0.1 + top) / 2, 0.025, top - 0.1, 0.025)
        # a small finial on each bar
        parts.append(transformed(uv_sphere(1.0, segments=10, rings=6),
                                 [[0.035, 0, 0, sgn * x], [0, 0.05, 0, top], [0, 0, 0.035, 0]]))
    return merge(*parts)


# ---------------------------------------------------------------------------------------------
# glTF
# ---------------------------------------------------------------------------------------------

def smoothstep(x):
    x = min(1.0, max(0.0, x))
    return x * x * (3 - 2 * x)


def make_gltf():
    g = Gltf()
    g.doc["asset"]["generator"] = "glint scenes/venus_garden/make_venus_garden.py"
    g.doc["animations"] = []
    marble = g.material("VenusMarble", base_color=(0.85, 0.83, 0.8, 1))
    stone = g.material("PedestalStone", base_color=(0.5, 0.48, 0.45, 1))
    iron = g.material("Iron", base_color=(0.05, 0.05, 0.05, 1))
    lamp_iron = g.material("LampIron", base_color=(0.04, 0.04, 0.045, 1))

    venus = g.mesh("Venus", g.geometry(venus_figure()), marble)
    ped = g.mesh("Pedestal", g.geometry(pedestal()), stone)
    post = g.mesh("LampPost", g.geometry(lamp_post()), lamp_iron)
    leaves = [g.mesh("GateLeafLeft", g.geometry(gate_leaf(-1)), iron),
              g.mesh("GateLeafRight", g.geometry(gate_leaf(1)), iron)]

    roots = []
    roots.append(g.node("Pedestal", mesh=ped, translation=STATUE))
    roots.append(g.node("Venus", mesh=venus, translation=add(STATUE, (0, 1.1, 0)),
                        rotation=quat_axis_angle((0, 1, 0), 12)))
    for k, z in enumerate(LAMP_ZS):
        for side in (-1, 1):
            roots.append(g.node("Lamp%d%s" % (k, "L" if side < 0 else "R"), mesh=post,
                                translation=(side * LAMP_X, 0.0, z)))

    # Gate leaves: hinge nodes at x = -/+1.5; the opening swings them into the garden (-z):
    # +angle about +y for the left leaf (its +x turns towards -z), -angle for the right one.
    t0, t1 = T_GATE_OPEN
    n = 13
    times = [t0 + (t1 - t0) * i / (n - 1) for i in range(n)]
    opening = 105.0
    for side, mesh in zip((-1, 1), leaves):
        node = g.node("GateLeaf%s" % ("Left" if side < 0 else "Right"), mesh=mesh,
                      translation=(side * GATE_HALF, 0.0, GATE_Z),
                      rotation=quat_axis_angle((0, 1, 0), 0.0))
        roots.append(node)
        quats = [quat_axis_angle((0, 1, 0), -side * opening * smoothstep(i / (n - 1)))
                 for i in range(n)]
        inp = g.accessor(g.buffer_view(struct.pack("<%df" % n, *times), None), FLOAT, n,
                         "SCALAR", minmax=([min(times)], [max(times)]))
        out = g.accessor(g.buffer_view(b"".join(struct.pack("<4f", *q) for q in quats), None),
                         FLOAT, n, "VEC4")
        g.doc["animations"].append({
            "name": "OpenGate%s" % ("Left" if side < 0 else "Right"),
            "samplers": [{"input": inp, "output": out, "interpolation": "LINEAR"}],
            "channels": [{"sampler": 0, "target": {"node": node, "path": "rotation"}}]})
    doc = g.finish("VenusGarden", roots)
    # Animation data views carry no target (they are not vertex data).
    for view in doc["bufferViews"]:
        if view.get("target") is None:
            view.pop("target", None)
    return doc


# ---------------------------------------------------------------------------------------------
# The glint scene
# ---------------------------------------------------------------------------------------------

def keys(pairs, interpolation=None):
    k = {"keys": [[t, v] for t, v in pairs]}
    if interpolation:
        k["interpolation"] = interpolation
    return k


def make_scene():
    S = STATUE
    head = (S[0], 2.35, S[2])  # the camera looks here in the garden (and focuses here)
    cam_pos = [
        (0.0, (0.0, 1.75, 29.0)),
        (2.75, (0.05, 1.72, 17.5)),
        (T_ARRIVE, (0.0, 1.7, 8.2)),
        (7.0, (0.0, 1.68, 7.9)),
        (8.8, (0.0, 1.66, 7.0)),
        (10.8, (0.15, 1.63, -0.6)),
        (T_ENTER, (0.25, 1.6, -2.2)),
        (T_END, (-0.9, 1.5, -3.4)),
    ]
    cam_look = [
        (0.0, (0.0, 1.5, 0.0)),
        (2.75, (0.0, 1.55, 0.0)),
        (T_ARRIVE, (0.0, 1.55, 0.0)),
        (7.0, (0.0, 1.75, -6.0)),
        (8.8, head),
        (T_END, head),
    ]
    scene = {
        "render": {
            "width": 800, "height": 600, "spp": 8, "seed": 2008, "fps": FPS,
            "time": HERO_TIME,
            "camera": "Walk",
            "integrator": {"type": "whitted", "max_depth": 4, "volume": "single",
                           "volume_estimator": "march", "volume_step": 0.4},
            "filter": {"type": "gaussian", "radius": 1.5},
            "background": [0.004, 0.006, 0.012],
            "tonemap": {"operator": "ward", "exposure": 0.5,
                        "ward": {"display_max": 100, "scene_luminance": 6}},
        },
        "gltf": [
            "venus_garden.gltf",
            {"file": "$GLINT_ASSETS/stanford/dragon_vrip_res2.glb",
             "transform": [{"translate": [0.006, -0.0527, 0.0]}, {"scale": 8.5},
                           {"rotate": {"axis": [0, 1, 0], "degrees": 90}},
                           {"translate": [-DRAGON_X, 1.0, DRAGON_Z]}]},
            {"file": "$GLINT_ASSETS/stanford/dragon_vrip_res2.glb",
             "transform": [{"translate": [0.006, -0.0527, 0.0]}, {"scale": 8.5},
                           {"rotate": {"axis": [0, 1, 0], "degrees": 90}},
                           {"translate": [DRAGON_X, 1.0, DRAGON_Z]}]},
        ],
        "cameras": [{
            "name": "Walk", "yfov_degrees": 50, "znear": 0.05,
            "position": keys(cam_pos, "smooth"),
            "look_at": keys(cam_look, "smooth"),
            # A small aperture only in the garden: it softens the light shafts (focus: the
            # statue, the look_at point).
            "aperture": keys([(6.5, 0.0), (HERO_TIME, 0.015), (11.0, 0.035)]),
        }],
        "textures": [
            {"name": "Clouds", "type": "clouds", "octaves": 3, "gain": 0.4, "seed": 11,
             "colors": [[0.0, 0.0, 0.0], [2.0, 2.0, 2.0]],
             "mapping": {"space": "uv", "scale": 5.0,
                         "offset": keys([(0.0, [0.0, 0.0, 0.0]), (T_END, [0.9, 0.35, 0.0])])}},
            {"name": "DragonMarble", "type": "marble", "seed": 3, "octaves": 5,
             "frequency": 4.0, "distortion": 5.0,
             "colors": [[0.76, 0.78, 0.8], [0.16, 0.3, 0.38]],
             "mapping": {"space": "world", "scale": 1.3}},
            {"name": "VenusMarble", "type": "marble", "seed": 8, "octaves": 5,
             "frequency": 3.0, "distortion": 4.0,
             "colors": [[0.8, 0.78, 0.74], [0.42, 0.38, 0.36]],
             "mapping": {"space": "object", "scale": 2.5}},
            {"name": "StoneBump", "type": "fbm", "seed": 5, "octaves": 5,
             "mapping": {"space": "world", "scale": 3.0}},
            {"name": "PavingBump", "type": "turbulence", "seed": 6, "octaves": 4,
             "mapping": {"space": "world", "scale": 1.6}},
            {"name": "GrassBump", "type": "fbm", "seed": 7, "octaves": 4,
             "mapping": {"space": "world", "scale": 9.0}},
            {"name": "WallColor", "type": "fbm", "seed": 9, "octaves": 4,
             "colors": [[0.16, 0.14, 0.12], [0.42, 0.38, 0.33]],
             "mapping": {"space": "world", "scale": 0.7}},
        ],
        "lights": [],
        "materials": [
            {"name": "material", "type": "phong", "diffuse": "DragonMarble",
             "specular": [0.2, 0.2, 0.2], "shininess": 60},
            {"name": "VenusMarble", "type": "phong", "diffuse": "VenusMarble",
             "specular": [0.15, 0.15, 0.15], "shininess": 40},
            {"name": "PedestalStone", "type": "phong", "diffuse": [0.42, 0.4, 0.37],
             "specular": [0.05, 0.05, 0.05], "shininess": 10,
             "bump": {"texture": "StoneBump", "strength": 0.02}},
            {"name": "Iron", "type": "phong", "diffuse": [0.03, 0.03, 0.03],
             "specular": [0.35, 0.35, 0.35], "shininess": 50},
            {"name": "LampIron", "type": "phong", "diffuse": [0.03, 0.03, 0.035],
             "specular": [0.3, 0.3, 0.3], "shininess": 40},
            {"name": "Grass", "type": "lambert", "diffuse": [0.05, 0.09, 0.035],
             "bump": {"texture": "GrassBump", "strength": 0.03}},
            {"name": "Paving", "type": "phong", "diffuse": [0.3, 0.29, 0.27],
             "specular": [0.06, 0.06, 0.06], "shininess": 20,
             "bump": {"texture": "PavingBump", "strength": 0.03}},
            {"name": "Gravel", "type": "lambert", "diffuse": [0.36, 0.34, 0.31],
             "bump": {"texture": "StoneBump", "strength": 0.015}},
            {"name": "Wall", "type": "lambert", "diffuse": "WallColor",
             "bump": {"texture": "StoneBump", "strength": 0.15}},
            {"name": "Column", "type": "phong", "diffuse": [0.55, 0.53, 0.5],
             "specular": [0.08, 0.08, 0.08], "shininess": 20,
             "bump": {"texture": "StoneBump", "strength": 0.02}},
            {"name": "Hedge", "type": "lambert", "diffuse": [0.03, 0.07, 0.03],
             "bump": {"texture": "GrassBump", "strength": 0.12}},
        ],
        "objects": [],
        "media": [],
    }

    lights, objects, media = scene["lights"], scene["objects"], scene["media"]

    # --- Lamps: a warm point light under each hood (range-limited, so far lamps cost no
    # shadow rays), and a small emission-only glow around it (the original's lamp glow).
    for k, z in enumerate(LAMP_ZS):
        for side in (-1, 1):
            p = [side * LAMP_X, LAMP_LIGHT_Y, z]
            lights.append({"name": "lamp%d%s" % (k, "L" if side < 0 else "R"), "type": "point",
                           "position": p, "color": [1.0, 0.78, 0.5], "intensity": 6.0,
                           "range": 8.0})
            media.append({"name": "glow%d%s" % (k, "L" if side < 0 else "R"),
                          "region": {"type": "sphere", "center": p, "radius": 0.16},
                          "sigma_a": 0.3, "emission": [9.0, 6.5, 3.6]})
    # --- The sky: light from above through moving clouds (a slide projector), its direction
    # drifting and its cloud attenuation easing off as the camera walks in.
    lights.append({
        "name": "cloud light", "type": "projective",
        "position": [S[0] - 8.0, 18.0, S[2] + 1.0],
        "direction": keys([(6.0, [0.36, -1.0, -0.1]), (T_END, [0.5, -1.0, 0.02])], "smooth"),
        "up": [0, 0, -1], "fov_degrees": 30, "texture": "Clouds",
        "color": [0.75, 0.85, 1.0], "intensity": 900.0,
        "attenuation": keys([(6.0, 0.3), (HERO_TIME, 1.0), (T_END, 0.7)])})
    # A faint moon: no shadow rays (cheap), just enough to show silhouettes.
    lights.append({"name": "moon", "type": "directional", "direction": [0.3, -1.0, 0.5],
                   "color": [0.55, 0.65, 1.0], "intensity": 0.04, "cast_shadows": False})

    # --- Ground, sidewalk, walls.
    objects.append({"name": "ground", "type": "plane", "material": "Grass"})
    objects.append({"name": "sidewalk", "type": "box", "min": [-1.4, -0.1, 0.0],
                    "max": [1.4, 0.04, 32.0], "material": "Paving"})
    objects.append({"name": "garden path", "type": "box", "min": [-1.2, -0.1, -7.2],
                    "max": [1.2, 0.03, -0.4], "material": "Gravel"})
    objects.append({"name": "plaza", "type": "cylinder", "radius": 3.4, "height": 0.035,
                    "material": "Gravel", "transform": [{"translate": [S[0], 0, S[2]]}]})
    wall_t = 0.4
    objects += [
        {"name": "front wall L", "type": "box", "min": [-GARDEN_HALF - wall_t, 0, -wall_t],
         "max": [-GATE_HALF - 0.35, WALL_HEIGHT, 0], "material": "Wall"},
        {"name": "front wall R", "type": "box", "min": [GATE_HALF + 0.35, 0, -wall_t],
         "max": [GARDEN_HALF + wall_t, WALL_HEIGHT, 0], "material": "Wall"},
        {"name": "side wall L", "type": "box", "min": [-GARDEN_HALF - wall_t, 0, -GARDEN_DEPTH],
         "max": [-GARDEN_HALF, WALL_HEIGHT, -wall_t], "material": "Wall"},
        {"name": "side wall R", "type": "box", "min": [GARDEN_HALF, 0, -GARDEN_DEPTH],
         "max": [GARDEN_HALF + wall_t, WALL_HEIGHT, -wall_t], "material": "Wall"},
        {"name": "back wall", "type": "box",
         "min": [-GARDEN_HALF - wall_t, 0, -GARDEN_DEPTH - wall_t],
         "max": [GARDEN_HALF + wall_t, WALL_HEIGHT, -GARDEN_DEPTH], "material": "Wall"},
    ]
    for side in (-1, 1):
        x0 = side * (GATE_HALF + 0.175)
        objects.append({"name": "gate pier %s" % ("L" if side < 0 else "R"), "type": "box",
                        "min": [x0 - 0.2, 0, -0.5], "max": [x0 + 0.2, 3.6, 0.1],
                        "material": "Wall"})
        objects.append({"name": "pier cap %s" % ("L" if side < 0 else "R"), "type": "box",
                        "min": [x0 - 0.27, 3.6, -0.57], "max": [x0 + 0.27, 3.75, 0.17],
                        "material": "Column"})
        # The dragons' plinths in front of the wall.
        objects.append({"name": "plinth %s" % ("L" if side < 0 else "R"), "type": "box",
                        "min": [side * DRAGON_X - 0.55, 0, DRAGON_Z - 0.85],
                        "max": [side * DRAGON_X + 0.55, 1.0, DRAGON_Z + 0.85],
                        "material": "Column"})
    # A ring of columns around the statue: they catch the light and cast volumetric shadows.
    for k in range(8):
        a = 2 * math.pi * (k + 0.5) / 8
        cx, cz = S[0] + 5.2 * math.sin(a), S[2] + 5.2 * math.cos(a)
        objects.append({"name": "column %d" % k, "type": "cylinder", "radius": 0.24,
                        "height": 3.4, "material": "Column",
                        "transform": [{"translate": [cx, 0, cz]}]})
        objects.append({"name": "column cap %d" % k, "type": "box", "min": [-0.34, 3.4, -0.34],
                        "max": [0.34, 3.58, 0.34], "material": "Column",
                        "transform": [{"translate": [cx, 0, cz]}]})
    # A pergola on the columns: an architrave ring and parallel beams along z. Seen from the
    # path, the beams' shadow sheets in the mist are the light shafts, dappled by the clouds.
    for k in range(8):
        a0 = 2 * math.pi * (k + 0.5) / 8
        a1 = 2 * math.pi * (k + 1.5) / 8
        x0, z0 = 5.2 * math.sin(a0), 5.2 * math.cos(a0)
        x1, z1 = 5.2 * math.sin(a1), 5.2 * math.cos(a1)
        chord = math.hypot(x1 - x0, z1 - z0)
        ang = math.degrees(math.atan2(-(z1 - z0), x1 - x0))
        objects.append({"name": "architrave %d" % k, "type": "box",
                        "min": [-chord / 2 - 0.3, 3.58, -0.16], "max": [chord / 2 + 0.3, 3.8, 0.16],
                        "material": "Column",
                        "transform": [{"rotate": {"axis": [0, 1, 0], "degrees": ang}},
                                      {"translate": [S[0] + (x0 + x1) / 2, 0,
                                                     S[2] + (z0 + z1) / 2]}]})
    nbeams = 8
    for k in range(nbeams):
        x = -4.2 + 8.4 * k / (nbeams - 1)
        half = math.sqrt(max(0.0, 5.05 ** 2 - x * x)) + 0.25
        objects.append({"name": "pergola beam %d" % k, "type": "box",
                        "min": [S[0] + x - 0.07, 3.8, S[2] - half],
                        "max": [S[0] + x + 0.07, 4.05, S[2] + half], "material": "Column"})
    # Hedges along the garden's side walls.
    for side in (-1, 1):
        objects.append({"name": "hedge %s" % ("L" if side < 0 else "R"), "type": "box",
                        "min": [side * (GARDEN_HALF - 0.5) - 0.5, 0, -GARDEN_DEPTH + 0.5],
                        "max": [side * (GARDEN_HALF - 0.5) + 0.5, 1.6, -2.0],
                        "material": "Hedge"})

    # --- Fog: one homogeneous box over the sidewalk, one over the garden (kept apart so each
    # ray marches only the part it crosses). Both glow faintly (the emission-only volume).
    media.insert(0, {"name": "street fog",
                     "region": {"type": "box", "min": [-9, 0, 0], "max": [9, 6, 34]},
                     "sigma_a": 0.015, "sigma_s": 0.07, "g": 0.35,
                     "emission": [0.0008, 0.001, 0.0016]})
    media.insert(1, {"name": "garden mist",
                     "region": {"type": "box", "min": [-GARDEN_HALF, 0, -GARDEN_DEPTH],
                                "max": [GARDEN_HALF, 9, -0.4]},
                     "sigma_a": 0.01, "sigma_s": 0.06, "g": 0.55,
                     "emission": [0.0006, 0.0008, 0.0013]})
    return scene


# ---------------------------------------------------------------------------------------------

def dumps(doc, indent):
    text = json.dumps(tidy(doc), indent=indent, ensure_ascii=True) + "\n"
    # Short lists of numbers on one line.
    text = re.sub(r"\[\s+(-?[\d.e+-]+(?:,\s+-?[\d.e+-]+){0,15})\s+\]",
                  lambda m: "[" + re.sub(r",\s+", ", ", m.group(1)) + "]", text)
    return text


def write(name, text):
    path = os.path.join(HERE, name)
    with open(path, "w", encoding="ascii", newline="\n") as f:
        f.write(text)
    print("wrote", os.path.relpath(path, ROOT), "(%d bytes)" % len(text))


def main():
    write("venus_garden.gltf", dumps(make_gltf(), None))
    write("venus_garden.json", dumps(make_scene(), 1))


if __name__ == "__main__":
    main()
