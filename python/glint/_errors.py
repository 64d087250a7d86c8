"""glint's errors, as the command line sorts them: bad input (exit code 2 there) and a render,
write or comparison that failed on valid input (exit code 1)."""


class Error(Exception):
    """Base of the errors glint raises."""

    def __init__(self, message, file=None, pointer=None, detail=None):
        super().__init__(message)
        #: The file the error is about (a scene, sidecar or image), or None.
        self.file = file
        #: The JSON pointer into that file ("/render/spp"), or None.
        self.pointer = pointer
        #: The message without its location ("must be >= 1, got 0").
        self.message = detail if detail is not None else message


class InputError(Error, ValueError):
    """Bad input: a scene, sidecar, option or image that cannot work. Carries the file and the
    JSON pointer, as the command line's one-line message does."""


class RenderError(Error, RuntimeError):
    """A render, write or comparison that failed on valid input."""


class RenderInterrupted(KeyboardInterrupt):
    """Ctrl-C stopped a render: `image` holds the passes done (None when the first pass had
    not finished). A KeyboardInterrupt, so it stops a script or a notebook cell as one does."""

    def __init__(self, image):
        super().__init__("render interrupted" if image is None else
                         f"render interrupted at {image.spp} spp")
        self.image = image
