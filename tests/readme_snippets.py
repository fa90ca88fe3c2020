"""Checks the code snippets of README.md and docs/*.md against the examples that the tests build and run.

A fenced code block preceded by a line `<!-- from examples/FILE -->` must be a verbatim excerpt
of examples/FILE, and every example file must have at least one such snippet in one of the
checked files (README.md and every docs/*.md beside it, taken together).
Usage: readme_snippets.py README.md EXAMPLES_DIR [MARKDOWN...]
(the docs/*.md files next to README.md are always checked; further MARKDOWN files may be named.)"""
import glob
import os
import re
import sys

readme, examples = sys.argv[1], sys.argv[2]
docs = sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(readme)), "docs", "*.md")))
files = [readme] + [f for f in docs + sys.argv[3:] if os.path.abspath(f) != os.path.abspath(readme)]
failures = []
found = set()
count = 0
for path in dict.fromkeys(files):
    text = open(path).read()
    snippets = re.findall(r"<!-- from examples/(\S+) -->\n```[a-z0-9+]*\n(.*?)```", text, re.S)
    # A marker that is not directly followed by a fenced block would silently check nothing.
    markers = len(re.findall(r"^<!-- from examples/\S+ -->$", text, re.M))
    if markers != len(snippets):
        failures.append(f"{path}: {markers - len(snippets)} marker(s) <!-- from examples/FILE --> "
                        "not directly followed by a fenced code block")
    for name, body in snippets:
        example = os.path.join(examples, name)
        if not os.path.isfile(example):
            failures.append(f"{path}: snippet from examples/{name}, which does not exist")
            continue
        if body not in open(example).read():
            failures.append(f"{path}: snippet from examples/{name} is not an excerpt of it:\n{body}")
        found.add(name)
    count += len(snippets)
expected = {"CMakeLists.txt", "cpp/simplify.cpp", "cpp/convert_vtk.cpp", "c/simplify.c", "fortran/simplify.f90",
            "python/simplify.py"}
missing = expected - found
if missing:
    failures.append("README.md and docs/ have no snippet from " + ", ".join(sorted(missing)))
for f in failures:
    print(f)
print(f"{count} snippets checked in {len(dict.fromkeys(files))} files (README.md and docs/*.md)")
sys.exit(1 if failures else 0)
