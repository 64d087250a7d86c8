"""glint from Python: load scenes, render them into numpy arrays, write and compare images.

    import glint
    scene = glint.load("scenes/first_image/first_image.gltf")
    image = scene.render(spp=16, seed=1)
    image.beauty            # (height, width, 3) float32, scene-linear
    image.save("out.exr")   # with glint's metadata, as `glint render` writes it

docs/python.md has the whole module. Errors are glint.InputError (bad input: the file and the
JSON pointer as attributes) and glint.RenderError (a render or write that failed); Ctrl-C stops
a render and raises glint.RenderInterrupted, a KeyboardInterrupt carrying the passes done.
"""

import math
import numbers
import os

from glint._errors import Error, InputError, RenderError, RenderInterrupted
from glint import _glint

__all__ = ["Error", "Image", "InputError", "RenderError", "RenderInterrupted", "Scene", "diff",
           "load", "read"]


def _to_json(value, where, pointer=""):
    """`value` as JSON text, checked on the way: a dict with string keys, lists (or tuples and
    numpy arrays), strings, finite numbers (numpy's too), booleans and None. Anything else is
    an InputError naming `where` and the JSON pointer of the value."""
    import json

    def convert(v, at):
        if v is None or isinstance(v, (bool, str)):
            return v
        if isinstance(v, numbers.Integral):
            return int(v)
        if isinstance(v, numbers.Real):
            f = float(v)
            if not math.isfinite(f):
                raise InputError(f"{where}: {at or '/'}: must be finite, got {f}", where,
                                 at or "/", f"must be finite, got {f}")
            return f
        if isinstance(v, dict):
            out = {}
            for k, item in v.items():
                if not isinstance(k, str):
                    raise InputError(f"{where}: {at or '/'}: keys must be strings, got {k!r}",
                                     where, at or "/", f"keys must be strings, got {k!r}")
                out[k] = convert(item, at + "/" + k.replace("~", "~0").replace("/", "~1"))
            return out
        if isinstance(v, (list, tuple)):
            return [convert(item, f"{at}/{i}") for i, item in enumerate(v)]
        if hasattr(v, "tolist") and hasattr(v, "dtype"):  # a numpy array or scalar
            items = v.tolist()
            if not isinstance(items, list):
                return convert(items, at) if not hasattr(items, "dtype") else items
            return [convert(item, f"{at}/{i}") for i, item in enumerate(items)]
        what = f"expected a JSON value (dict, list, str, number, bool or None), got {type(v).__name__}"
        raise InputError(f"{where}: {at or '/'}: {what}", where, at or "/", what)

    return json.dumps(convert(value, pointer))


class Image:
    """A rendered or read image. Its planes are numpy arrays sharing the image's memory:
    `beauty` and `variance` (height, width, 3) float32 (the variance of each pixel's mean),
    `alpha` (height, width), `samples` (height, width) uint32, and with AOVs `albedo`, `normal`
    (height, width, 3) and `depth` (height, width). `spp` is the samples per pixel reached,
    `error` the estimated relative error, `stop` why the render stopped ("spp", "time-limit",
    "noise-target", "interrupted")."""

    def __init__(self, native=None, **arrays):
        """Image(beauty=array, variance=..., alpha=..., ...) makes an image of arrays (copied),
        to save or compare them."""
        if native is None:
            native = _glint.image_from_arrays(arrays)
        self._native = native
        self.arrays = native.arrays

    beauty = property(lambda self: self.arrays["beauty"])
    variance = property(lambda self: self.arrays["variance"])
    alpha = property(lambda self: self.arrays["alpha"])
    samples = property(lambda self: self.arrays["samples"])
    albedo = property(lambda self: self.arrays.get("albedo"))
    normal = property(lambda self: self.arrays.get("normal"))
    depth = property(lambda self: self.arrays.get("depth"))
    spp = property(lambda self: self._native.spp)
    error = property(lambda self: self._native.error)
    stop = property(lambda self: self._native.stop)
    passes = property(lambda self: self._native.passes)
    stats = property(lambda self: self._native.stats)
    metadata = property(lambda self: self._native.metadata)

    @property
    def shape(self):
        return self.beauty.shape[:2]

    def save(self, path):
        """Writes the image to `path`: .exr scene-linear (with the variance and AOVs), .png,
        .jpg or .tif through the render's tone mapping; atomically, with glint's metadata."""
        self._native.save(os.fspath(path))

    def tonemap(self, **options):
        """The image as a display shows it: a (height, width, 3) float32 array in [0, 1],
        display-encoded. Options are the sidecar's render.tonemap keys over the render's own:
        exposure (stops), operator ("none" or "ward", with ward={"display_max": ...,
        "scene_luminance": ...}), display and view (an OpenColorIO display and view of
        glint's config)."""
        return self._native.display(_to_json(options, "tonemap()"))

    def _repr_png_(self):
        """The image in Jupyter: PNG through the render's display transform."""
        import tempfile
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "image.png")
            self._native.save(path)
            with open(path, "rb") as f:
                return f.read()

    def __repr__(self):
        h, w = self.shape
        return f"<glint.Image {w}x{h}, {self.spp} spp, stop {self.stop!r}>"


def read(path):
    """Reads an image glint wrote (an EXR with its variance and AOVs), or any scene-linear EXR."""
    return Image(_glint.read_image(os.fspath(path)))


def diff(a, b, **options):
    """Compares image `a` against reference `b` (each an Image or a file) as `glint diff` does
    and returns the figures `glint diff --json` prints, as a dict ("verdict", "pass", "rmse",
    "psnr", ... ; with statistical=True the z-tests' "pass_percent", "global_z", ...; with
    flip=True a "flip" dict). Options are glint diff's, named fail, fail_percent, warn,
    warn_percent, statistical, significance, min_pass, max_error, spp_a, spp_b, heatmap, flip,
    ppd, flip_max, flip_map. An Image is compared as the float EXR its save() writes (its
    variance included, which the statistical test reads from the reference)."""
    import json
    import tempfile
    with tempfile.TemporaryDirectory() as folder:
        paths = []
        for name, image in (("a", a), ("b", b)):
            if isinstance(image, Image):
                path = os.path.join(folder, name + ".exr")
                image._native.save(path)
                paths.append(path)
            else:
                paths.append(os.fspath(image))
        result = json.loads(_glint.compare(_to_json(dict(options, a=paths[0], b=paths[1]),
                                                    "diff()")))
    for name, image in (("a", a), ("b", b)):
        result[name] = repr(image) if isinstance(image, Image) else os.fspath(image)
    return result


class Scene:
    """A loaded scene: its files are read once, and a render scene built from it is kept between
    renders that do not change what it depends on (`builds` counts them)."""

    def __init__(self, native):
        self._native = native

    file = property(lambda self: self._native.file, doc="the scene file (names it in errors)")
    cameras = property(lambda self: self._native.cameras, doc="the scene's camera names")
    warnings = property(lambda self: self._native.warnings)
    builds = property(lambda self: self._native.builds,
                      doc="render scenes built so far (a render that reuses one builds none)")

    refreshes = property(lambda self: self._native.refreshes,
                         doc="render scenes brought up to date without a build: a camera or the "
                             "lights changed, and the geometry, its accelerator, the materials "
                             "and the textures stayed")
    timings = property(lambda self: self._native.timings,
                       doc="load_seconds (the files), build_seconds and accelerator_seconds "
                           "(the last build of the render scene)")

    def update(self, patch):
        """Changes the scene with `patch`, a dict in the sidecar schema, as a second sidecar
        would: a camera or material named like an existing one changes (only the keys given:
        {"materials": [{"name": "Plane", "diffuse": [0.8, 0.2, 0.2]}]}; a camera given
        "position" and "look_at" is placed anew), render keys replace the scene's, lights and
        objects are added. The files are not read again."""
        self._native.update(_to_json(patch, "update()"))

    def set_light(self, name, *, intensity=None, color=None):
        """Sets the intensity and/or colour of the light named `name`."""
        self._native.set_light(name, intensity, None if color is None else tuple(color))

    def info(self):
        """What `glint info` prints, as a dict: meshes, nodes, objects, materials, textures,
        cameras, lights, bounds, the image settings and the integrator, animation, motion and
        the effects the scene calls for (docs/python.md lists the keys)."""
        return self._native.info()

    def render(self, **options):
        """Renders the scene and returns an Image.

        Options: any key of the sidecar's render block (spp, seed, threads, width, height,
        camera, integrator, accel, adaptive, filter, max depth through integrator={...}, ...),
        and time (scene seconds), time_limit (seconds), noise_target (relative error, e.g.
        0.02), crop ([x0, y0, x1, y1]), aovs (bool). Without spp, a budget has no spp cap, as
        on the command line. The GIL is released while rendering; Ctrl-C raises
        RenderInterrupted with the passes done."""
        image, interrupt = self._native.render(_to_json(options, "render()"))
        if interrupt is not None:
            if isinstance(interrupt, KeyboardInterrupt):
                raise RenderInterrupted(None if image is None else Image(image)) from None
            raise interrupt
        return Image(image)

    def render_progressive(self, **options):
        """Renders pass by pass (1, 2, 4, 8, 16 spp, then 16 more each) and yields the Image
        after each pass: a copy, so it stays as it was. Takes render()'s options; the image
        after a pass is render()'s image at its spp. `stop` is None on every image but the
        last. Ctrl-C raises RenderInterrupted with the last image yielded."""
        session = self._native.progressive(_to_json(options, "render_progressive()"))
        last = None
        while True:
            image, interrupt = session.next()
            if interrupt is not None:
                if isinstance(interrupt, KeyboardInterrupt):
                    raise RenderInterrupted(last) from None
                raise interrupt
            if image is None:
                return
            last = Image(image)
            yield last

    def __repr__(self):
        return f"<glint.Scene {self.file!r}>"


def load(scene, sidecar=None, *, time=None, name="<dict>", base_dir=None):
    """Loads a scene: a .gltf/.glb, .ply/.obj or glint .json file, or a dict in the glint .json
    scene schema. `sidecar` is a sidecar file or a dict in the sidecar schema (default: the file
    NAME.glint.json beside the scene, when there is one). `time` is the scene time in seconds
    (default: the sidecar's render.time, else 0). A dict is named `name` in errors, and the
    relative paths in it resolve against `base_dir` (default: the scene's folder for a sidecar,
    the current folder for a scene)."""
    if time is not None and not isinstance(time, numbers.Real):
        raise TypeError(f"load(): time must be a number of seconds, got {type(time).__name__}")
    if isinstance(scene, dict):
        if sidecar is not None:
            raise InputError("load(): a dict scene takes no sidecar; put its keys in the dict")
        file = name if base_dir is None else os.path.join(os.fspath(base_dir), name)
        return Scene(_glint.Scene(_to_json(scene, file), file, None, time))
    scene = os.fspath(scene)
    if isinstance(sidecar, dict):
        folder = os.fspath(base_dir) if base_dir is not None else os.path.dirname(scene)
        file = os.path.join(folder, name)
        return Scene(_glint.Scene(_to_json(sidecar, file), file, scene, time))
    if sidecar is not None:
        sidecar = os.fspath(sidecar)
    return Scene(_glint.Scene(scene, sidecar, time))
