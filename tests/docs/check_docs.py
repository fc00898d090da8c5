#!/usr/bin/env python3
"""The documentation against the code: docs/passes.md is what `framepass passes --markdown`
prints, docs/config.md's cvar table (between its GENERATED markers) what `framepass passes
--cvars --markdown` prints, docs/schema/*.schema.json what `framepass schema` prints; every option of every command appears in docs/commands.md; the README stays under 20 KB;
every relative link in README.md and docs/ names a file that exists; every section the code
cites (`algorithms §N.M`, or a bare `§N.M`) is a heading of docs/algorithms.md, and no file
cites a document outside the repository.

    check_docs.py FRAMEPASS SOURCE_DIR [--write]

--write rewrites the generated documents (the pass reference, the cvar table, the schemas)
from FRAMEPASS instead of reporting them stale.
"""
import os
import re
import subprocess
import sys

fp, src = sys.argv[1], sys.argv[2]
write = "--write" in sys.argv[3:]
failures = []


def run(*args):
    return subprocess.run([fp, *args], capture_output=True, text=True, check=True).stdout


# 1. The pass reference is generated, never edited by hand.
committed = open(os.path.join(src, "docs/passes.md")).read()
if write:
    open(os.path.join(src, "docs/passes.md"), "w").write(run("passes", "--markdown"))
elif run("passes", "--markdown") != committed:
    failures.append("docs/passes.md differs from `framepass passes --markdown` "
                    "(regenerate: framepass passes --markdown > docs/passes.md)")

# 1a. So is docs/config.md's cvar table, every cvar framepass knows: the text between its markers.
config_path = os.path.join(src, "docs/config.md")
config_md = open(config_path).read()
section = re.search(r"(<!-- BEGIN GENERATED: framepass passes --cvars --markdown[^\n]*-->\n)(.*?)"
                    r"(<!-- END GENERATED -->)", config_md, re.S)
cvar_table = run("passes", "--cvars", "--markdown")
if not section:
    failures.append("docs/config.md has no generated cvar table (<!-- BEGIN GENERATED: framepass "
                    "passes --cvars --markdown … --> … <!-- END GENERATED -->)")
elif write:
    open(config_path, "w").write(config_md[:section.end(1)] + cvar_table + config_md[section.start(3):])
elif section.group(2) != cvar_table:
    failures.append("docs/config.md's cvar table differs from `framepass passes --cvars --markdown` "
                    "(regenerate: python3 tests/docs/check_docs.py build/cli/framepass . --write)")

# 1b. The JSON Schemas of configs and scenes are generated too.
for document in ("config", "scene"):
    path = os.path.join(src, f"docs/schema/{document}.schema.json")
    if write:
        open(path, "w").write(run("schema", document))
    elif not os.path.exists(path) or run("schema", document) != open(path).read():
        failures.append(f"docs/schema/{document}.schema.json differs from `framepass schema {document}` "
                        f"(regenerate: framepass schema {document} > docs/schema/{document}.schema.json)")

# 1c. Every config and scene the repository ships is valid under those schemas (checked by an
# independent validator, Debian's python3-jsonschema), so the schemas say what the readers accept.
import glob
import json

import jsonschema


def load_json_with_comments(path):
    # framepass reads JSON with // comments (the presets have them); none of their strings
    # contains "//" after a comma or brace, so whole-line comments are all there is to drop.
    text = "\n".join(line for line in open(path).read().split("\n")
                     if not line.lstrip().startswith("//"))
    return json.loads(text)


schemas = {d: json.load(open(os.path.join(src, f"docs/schema/{d}.schema.json")))
           for d in ("config", "scene")
           if os.path.exists(os.path.join(src, f"docs/schema/{d}.schema.json"))}
shipped = [f for f in glob.glob(os.path.join(src, "configs/*.json")) +
           glob.glob(os.path.join(src, "examples/**/*.json"), recursive=True)]
checked = 0
for path in sorted(shipped):
    doc = load_json_with_comments(path)
    kind = "scene" if "geometry" in doc else "config" if "version" in doc or "passes" in doc else None
    if kind not in schemas:
        continue
    checked += 1
    for e in jsonschema.Draft202012Validator(schemas[kind]).iter_errors(doc):
        failures.append(f"{os.path.relpath(path, src)}: not valid under docs/schema/{kind}.schema.json "
                        f"at /{'/'.join(map(str, e.path))}: {e.message}")
if len(schemas) == 2 and checked < 10:
    failures.append(f"only {checked} shipped configs and scenes were checked against the schemas")

# 2. Every option a user can type is documented.
commands_md = open(os.path.join(src, "docs/commands.md")).read()
top = run("--help")
subcommands = re.findall(r"^  (\w+)\s", top.split("Subcommands:")[1], re.M)
for sub in subcommands:
    helptext = run(sub, "--help")
    # The options' own names, at the start of their help lines ("  -o,--output-dir TEXT").
    options = set(re.findall(r"^\s+(?:-\w,)?(--[a-z][a-z0-9-]*)", helptext, re.M)) - {"--help"}
    if f"framepass {sub}" not in commands_md:
        failures.append(f"docs/commands.md has no section for `framepass {sub}`")
    for o in sorted(options):
        if o not in commands_md:
            failures.append(f"docs/commands.md does not mention {sub}'s option {o}")

# 3. The README is the short way in.
size = os.path.getsize(os.path.join(src, "README.md"))
if size > 20 * 1024:
    failures.append(f"README.md is {size} bytes; keep it under 20 KB and move detail to docs/")

# 4. Links between the documents resolve.
documents = ["README.md"] + [os.path.join(d, f) for d, _, fs in os.walk(os.path.join(src, "docs"))
                             for f in fs if f.endswith(".md")]
for doc in documents:
    path = doc if os.path.isabs(doc) else os.path.join(src, doc)
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", open(path).read()):
        if re.match(r"^[a-z]+://", target):
            continue
        if not os.path.exists(os.path.normpath(os.path.join(os.path.dirname(path), target))):
            failures.append(f"{os.path.relpath(path, src)}: link to {target}, which does not exist")

# 5. Every section the code cites is in docs/algorithms.md; nothing cites a document that does
# not ship (the design brief, the reference notes, the style guide of the team's own folder).
headings = set(re.findall(r"^#{2,3} §(\d+(?:\.\d+)*) ", open(os.path.join(src, "docs/algorithms.md")).read(), re.M))
tracked = subprocess.run(["git", "-C", src, "ls-files"], capture_output=True, text=True).stdout.split()
outside = re.compile(r"DESIGN §|DESIGN\.md|STYLE\.md|ue_algorithms|ue_raytracing|users_and_conventions|"
                     r"architecture_anchors|\breference §|\.\./shared/")
for f in tracked:
    if not re.search(r"\.(cpp|h|cu|cuh|json|py|sh|md|txt)$|^Makefile$", f) or f == "tests/docs/check_docs.py":
        continue
    text = open(os.path.join(src, f), errors="replace").read()
    for m in outside.finditer(text):
        failures.append(f"{f}: cites '{m.group(0)}', a document outside the repository")
    if f.startswith("docs/") or f.endswith(".md"):
        continue
    for m in re.finditer(r"(?<!glTF )(?<!glTF 2\.0 )§(\d+(?:\.\d+)*)", text):
        if m.group(1).rstrip(".") not in headings:
            failures.append(f"{f}: cites §{m.group(1)}, which docs/algorithms.md does not have")

for f in failures:
    print("FAIL", f)
print(f"{len(failures)} problem(s)")
sys.exit(1 if failures else 0)
