"""Checks README.md's library snippets against the examples that the tests build and run.

A fenced code block preceded by a line `<!-- from examples/FILE -->` must be a verbatim excerpt
of examples/FILE, and every example file must have at least one such snippet.
Usage: readme_snippets.py README.md EXAMPLES_DIR"""
import os
import re
import sys

readme, examples = sys.argv[1], sys.argv[2]
text = open(readme).read()
snippets = re.findall(r"<!-- from examples/(\S+) -->\n```[a-z0-9+]*\n(.*?)```", text, re.S)
failures = []
for name, body in snippets:
    source = open(os.path.join(examples, name)).read()
    if body not in source:
        failures.append(f"README snippet from examples/{name} is not an excerpt of it:\n{body}")
expected = {"CMakeLists.txt", "cpp/simplify.cpp", "c/simplify.c", "fortran/simplify.f90", "python/simplify.py"}
missing = expected - {name for name, _ in snippets}
if missing:
    failures.append("README has no snippet from " + ", ".join(sorted(missing)))
for f in failures:
    print(f)
print(f"{len(snippets)} README snippets checked")
sys.exit(1 if failures else 0)
