"""Completes the stub stubgen makes of framepass._framepass (python/CMakeLists.txt runs it after
stubgen at build time): the signatures stubgen leaves as (*args, **kwargs) — pybind11's
keyword-only ones, which it does not parse — are taken from the functions' own docstrings, and
pybind11's spellings become typing's (object → Any, a setting's value → Value, numpy arrays →
numpy.typing.NDArray)."""
import importlib
import os
import re
import sys

# The built package (PYTHONPATH), not its sources beside this script.
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path = [p for p in sys.path if os.path.abspath(p or ".") != HERE]


from framepass._signatures import parameters_text  # noqa: E402  (the built package's)


def python_types(text):
    text = text.replace("framepass._framepass.", "")
    text = re.sub(r"numpy\.ndarray\[numpy\.float32\]", "numpy.typing.NDArray[numpy.float32]", text)
    text = re.sub(r"\bobject\b", "Any", text)
    text = re.sub(r"\bhandle\b", "Value", text)
    return text


def stub_signature(doc, name):
    """`(args) -> result` of pybind11's first docstring line for `name`, defaults as `...`."""
    parsed = parameters_text(doc, name)
    if parsed is None:
        return None
    texts, result = parsed
    out = []
    for p in texts:
        if p.startswith("self:"):
            p = "self"
        if "=" in p:
            p = p.split("=", 1)[0].rstrip() + " = ..."
        out.append(p)
    return "({}) -> {}".format(", ".join(out), result)


def main(path):
    module = importlib.import_module("framepass._framepass")
    text = open(path).read()
    lines, owner = [], module
    for line in text.splitlines():
        cls = re.match(r"class (\w+)", line)
        if cls:
            owner = getattr(module, cls.group(1), module)
        elif line and not line.startswith(" "):
            owner = module
        m = re.match(r"(\s*)def (\w+)\(.*\*args, \*\*kwargs\) -> \w+: \.\.\.", line)
        if m:
            indent, name = m.groups()
            target = getattr(owner, name, None)
            signature = stub_signature(getattr(target, "__doc__", None), name)
            if signature:
                if signature.startswith("(self") is False and isinstance(owner, type):
                    lines.append(f"{indent}@staticmethod")
                line = f"{indent}def {name}{signature}: ..."
        lines.append(line)
    text = python_types("\n".join(lines) + "\n")
    text = text.replace("import numpy\n", "import numpy\nimport numpy.typing\n", 1)
    text = re.sub(r"from typing import ([^\n]*)", lambda m: "from typing import " + ", ".join(
        sorted(set(m.group(1).split(", ")) | {"Any", "Union", "Optional", "List", "Dict"})), text, 1)
    text = text.replace("\nclass ", "\nValue = Union[bool, int, float, str]\n__version__: str\n\nclass ", 1)
    open(path, "w").write(text)


if __name__ == "__main__":
    main(sys.argv[1])
