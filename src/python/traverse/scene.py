"""traverse.Scene: a scene file or text with its overrides, read by the program's own parser."""

import math
import numbers
import os

from . import _traverse


def _value_text(value):
    """The text of `value` after `key=` in a --set string."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        # repr of a float reads back as the same double; the scene refuses nan and inf itself.
        v = float(value)
        return repr(v) if math.isfinite(v) else str(v).replace("inf", ".inf").replace("nan", ".nan")
    if isinstance(value, str):
        return value
    if isinstance(value, (list, tuple)) or (hasattr(value, "tolist") and hasattr(value, "ndim")):
        items = value.tolist() if hasattr(value, "tolist") else value
        return "[" + ", ".join(_value_text(v) for v in items) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_value_text(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"traverse.Scene.set: a value of type {type(value).__name__} cannot be set "
                    "(numbers, booleans, strings, lists and dicts of them can)")


class Scene:
    """A scene: a YAML file or text and the overrides applied to it, in order.

    Nothing is kept but the source and the overrides (the `--set key=value` strings): every
    use reads the scene again with the program's parser, so that each message is the one the
    command line prints. Make one with Scene.load(path), Scene.from_yaml(text) or
    Scene.from_dict(d); each is read once on creation (SceneError if it is bad).
    """

    def __init__(self, source, *, is_file, name, overrides=()):
        self._source = source
        self._is_file = is_file
        self._name = name
        self._overrides = list(overrides)
        self._read()

    @classmethod
    def load(cls, path, overrides=()):
        """The scene of the file `path` (as `traverse run PATH`), with `overrides` (strings
        "key.path=value", as --set) applied."""
        path = os.fspath(path)
        return cls(path, is_file=True, name=path, overrides=overrides)

    @classmethod
    def from_yaml(cls, text, name="<yaml>", overrides=()):
        """The scene of the YAML `text`; messages name it `name`."""
        return cls(str(text), is_file=False, name=name, overrides=overrides)

    @classmethod
    def from_dict(cls, d, name="<dict>", overrides=()):
        """The scene of the nested dict `d` (as YAML would read into one); it is written as
        YAML and read as a file would be, so the lines in messages are lines of that text
        (Scene.yaml)."""
        import yaml

        text = yaml.safe_dump(d, sort_keys=False, default_flow_style=None)
        return cls(text, is_file=False, name=name, overrides=overrides)

    def _src(self, overrides=None):
        return _traverse.Source(self._is_file, self._source, self._name,
                                self._overrides if overrides is None else overrides)

    def _read(self, overrides=None):
        _traverse.validate(self._src(overrides))

    @property
    def name(self):
        """The file's path, or the name given to text or a dict."""
        return self._name

    @property
    def yaml(self):
        """The scene's text before the overrides (None for a file: read it from `name`)."""
        return None if self._is_file else self._source

    @property
    def overrides(self):
        """The --set strings applied, in order."""
        return tuple(self._overrides)

    def set(self, key, value):
        """Sets `key` (a dotted path, "loads.F.speed") to `value` as `--set key=value` does,
        checked at once: SceneError with the program's message when the scene refuses it (the
        scene is then left as it was). Returns the scene."""
        entry = f"{key}={_value_text(value)}"
        self._read(self._overrides + [entry])
        self._overrides.append(entry)
        return self

    def __setitem__(self, key, value):
        self.set(key, value)

    def __getitem__(self, key):
        """The value of `key` ("loads.F.speed") in the complete scene (defaults filled in)."""
        node = self.check()
        for part in key.split("."):
            if not isinstance(node, dict) or part not in node:
                raise KeyError(f"{self._name}: the complete scene has no key {key!r}")
            node = node[part]
        return node

    def copy(self):
        """An independent scene with the same source and overrides."""
        return Scene(self._source, is_file=self._is_file, name=self._name, overrides=self._overrides)

    def check(self):
        """The complete scene, every default filled in, as a dict: the YAML `traverse check`
        prints, after the same checks (SceneError when one fails)."""
        import yaml

        _, text = _traverse.check(self._src(), False)
        return yaml.safe_load(text)

    def describe(self):
        """What `traverse check` prints for the scene after its first line: the complete
        scene as YAML, every key documented in a comment."""
        return _traverse.check(self._src(), True)[1]

    def plan(self):
        """The plan `traverse check` prints on its first line (nodes, steps, memory)."""
        return _traverse.check(self._src(), False)[0]

    def __repr__(self):
        src = self._name if self._is_file else f"{self._name} ({len(self._source)} characters)"
        return f"traverse.Scene({src!r}, overrides={self._overrides!r})"
