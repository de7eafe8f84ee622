"""Rewrites the stubs stubgen writes for the compiled module into types mypy accepts.

pybind11 2.10 names an argument taken as py::handle `handle` and a float64 array
`numpy.ndarray[numpy.float64]`; neither is a type mypy knows. Both become numpy.typing's
ArrayLike (what the bindings convert) and NDArray[numpy.float64].

Usage: python3 fix_stubs.py STUB.pyi (rewritten in place)
"""
import re
import sys


def fixed(text: str) -> str:
    text = re.sub(r"\bhandle\b", "numpy.typing.ArrayLike", text)
    text = text.replace("numpy.ndarray[numpy.float64]", "numpy.typing.NDArray[numpy.float64]")
    if "numpy.typing." in text and "import numpy.typing" not in text:
        text = text.replace("import numpy\n", "import numpy\nimport numpy.typing\n", 1)
    return text


if __name__ == "__main__":
    path = sys.argv[1]
    with open(path) as stub:
        text = stub.read()
    with open(path, "w") as stub:
        stub.write(fixed(text))
