"""The exceptions of the package traverse (raised by its compiled part with the program's
own messages)."""


class SceneError(ValueError):
    """A scene, a key or a value that traverse refuses: the message is the one `traverse check`
    and `traverse run` print after "bad scene:" (file, line, key, what was expected, what was
    found). Nothing was run."""


class OutputError(OSError):
    """An output path that cannot be written (an existing file without overwrite=True, a
    missing directory): the message `traverse run` prints after "bad output path:"."""

    def __init__(self, message):
        super().__init__(message)


class RunError(RuntimeError):
    """A run whose numerics failed (the command line's exit code 3), with its message.
    `output` is the path of the file the run wrote up to the failure (status "failed"),
    readable with traverse.read(output, allow_incomplete=True); None when the run failed
    before it wrote anything (e.g. its initial state)."""

    output = None
