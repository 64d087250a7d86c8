"""The dict loader against random structures (a hypothesis-style loop, seeded so a failure
reproduces): every input either loads or raises glint.InputError naming a JSON pointer; none
crashes the process or raises anything else. A sidecar and a .json scene that render are
mutated at random places: values replaced by values of other types (NaN, huge numbers, deep
nests, sets), keys dropped, unknown keys added."""

import copy
import json
import math
import random

import pytest

import glint
from conftest import DATA, LAMBERT_PLANE, JSON_SCENE

ITERATIONS = 1600


def random_value(rng, depth=0):
    kinds = ["int", "float", "str", "bool", "none", "list", "dict", "nan", "huge", "set",
             "object"]
    if depth > 3:
        kinds = kinds[:5]
    kind = rng.choice(kinds)
    if kind == "int":
        return rng.choice([0, 1, -1, 2, 3, 64, -(2 ** 31), 2 ** 40])
    if kind == "float":
        return rng.uniform(-10, 10)
    if kind == "str":
        return rng.choice(["", "x", "point", "lambert", "Top", "path", "box", "../nope.png"])
    if kind == "bool":
        return rng.random() < 0.5
    if kind == "none":
        return None
    if kind == "list":
        return [random_value(rng, depth + 1) for _ in range(rng.randrange(5))]
    if kind == "dict":
        return {rng.choice(["type", "name", "spp", "intensity", "a", "keys"]): random_value(rng, depth + 1)
                for _ in range(rng.randrange(4))}
    if kind == "nan":
        return rng.choice([math.nan, math.inf, -math.inf])
    if kind == "huge":
        return rng.choice([1e300, -1e300, 1e-300, 2 ** 70])
    if kind == "set":
        return {1, 2}
    return object()


def places(doc, at=()):
    """Every (container, key) in `doc`."""
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield doc, k
            yield from places(v, at + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield doc, i
            yield from places(v, at + (i,))


def mutate(rng, doc):
    doc = copy.deepcopy(doc)
    for _ in range(rng.randrange(1, 4)):
        spots = list(places(doc))
        container, key = rng.choice(spots)
        action = rng.random()
        if action < 0.6:
            container[key] = random_value(rng)
        elif action < 0.8 and isinstance(container, dict):
            del container[key]
        elif isinstance(container, dict):
            container[rng.choice(["spq", "colour", "extra", "gltf"])] = random_value(rng)
    return doc


def check(load, rng_seed):
    try:
        scene = load()
    except glint.InputError as e:
        assert e.file and (e.pointer is None or e.pointer.startswith("/")), e
        return "rejected"
    try:
        scene.render(spp=1, width=8, height=8)
    except (glint.InputError, glint.RenderError):
        pass
    return "loaded"


@pytest.mark.parametrize("seed", range(4))
def test_random_sidecar_dicts_load_or_raise_input_errors(seed):
    base = json.loads((DATA / "scenes" / "lambert_plane.glint.json").read_text())
    rng = random.Random(seed)
    seen = {"rejected": 0, "loaded": 0}
    for _ in range(ITERATIONS // 4):
        doc = mutate(rng, base)
        seen[check(lambda: glint.load(LAMBERT_PLANE, sidecar=doc), seed)] += 1
    # The loop tried both sides of the loader.
    assert seen["rejected"] > 0 and seen["loaded"] > 0, seen


@pytest.mark.parametrize("seed", range(2))
def test_random_scene_dicts_load_or_raise_input_errors(seed):
    base = json.loads(JSON_SCENE.read_text())
    rng = random.Random(100 + seed)
    seen = {"rejected": 0, "loaded": 0}
    for _ in range(ITERATIONS // 4):
        doc = mutate(rng, base)
        seen[check(lambda: glint.load(doc, base_dir=JSON_SCENE.parent), seed)] += 1
    assert seen["rejected"] > 0 and seen["loaded"] > 0, seen


def test_random_render_options_load_or_raise_input_errors():
    scene = glint.load(LAMBERT_PLANE)
    rng = random.Random(7)
    keys = ["spp", "seed", "threads", "width", "height", "camera", "integrator", "crop",
            "time_limit", "noise_target", "aovs", "time", "filter", "adaptive", "spq"]
    rejected = 0
    for _ in range(ITERATIONS // 2):
        options = {rng.choice(keys): random_value(rng) for _ in range(rng.randrange(1, 3))}
        options.setdefault("spp", 1)
        options["width"], options["height"] = 8, 8
        try:
            scene.render(**options)
        except (glint.InputError, glint.RenderError):
            rejected += 1
    assert rejected > 0
