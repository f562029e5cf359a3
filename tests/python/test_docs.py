"""docs/python.md's reference against the module: every public name documented, each with its
docstring as the text under its heading."""

import pathlib
import re

import granular

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def documented():
    """{name: text} of the reference's headings ("### granular.X"), whitespace normalised."""
    text = DOC.read_text()
    reference = text[text.index("## Reference") :]
    parts = re.split(r"^### (granular\.[\w.]+)\s*$", reference, flags=re.M)
    return {name: " ".join(body.split()) for name, body in zip(parts[1::2], parts[2::2])}


def public_names():
    names = {f"granular.{n}": getattr(granular, n) for n in granular.__all__}
    for cls in (granular.Scene, granular.Simulation):
        for attr in dir(cls):
            if not attr.startswith("_"):
                names[f"granular.{cls.__name__}.{attr}"] = getattr(cls, attr)
    return names


def docstring(obj):
    """The docstring without pybind11's signature line."""
    doc = obj.__doc__ or ""
    lines = doc.strip().splitlines()
    if lines and re.match(r"^\w+\(.*\)( -> .*)?$", lines[0]):
        lines = lines[1:]
    return " ".join(" ".join(lines).split())


def test_every_public_name_is_documented_with_its_docstring():
    docs = documented()
    for name, obj in public_names().items():
        assert name in docs, f"{name} has no heading in docs/python.md"
        assert docstring(obj), f"{name} has no docstring"
        assert docs[name] == docstring(obj), name


def test_every_documented_name_exists():
    names = public_names()
    for name in documented():
        assert name in names, f"docs/python.md documents {name}, which the module lacks"
