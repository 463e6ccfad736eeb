"""The exceptions Candela raises in Python. A SceneError carries the ``file:line: message`` the
command line prints (for a dictionary scene, the key path instead of file:line)."""


class SceneError(ValueError):
    """A scene that cannot be loaded or rendered as written: `file`, `line` and `message` say where
    and why; str() is the whole ``file:line: message``."""

    def __init__(self, text: str, file: str = "", line: int = 0, message: str = ""):
        super().__init__(text)
        self.file, self.line, self.message = file, line, message or text


class InputError(ValueError):
    """Bad input that is not a scene file line: an argument, an image file, an output path."""


class InternalError(RuntimeError):
    """A broken internal contract: a bug in Candela (please report it with what caused it)."""
