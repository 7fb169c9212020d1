#!/usr/bin/env python3
"""docs/BAD_INPUT.md from the bad-input table tests/bad_input/cases.toml.

  tests/bad_input.py --write-doc ROOT   regenerate docs/BAD_INPUT.md
  tests/bad_input.py --check ROOT       fail when docs/BAD_INPUT.md differs (ctest)

The cases themselves are run by tests/unit/test_bad_input.cpp.
"""
import os
import sys
import tomllib

DOC = "docs/BAD_INPUT.md"
TABLE = "tests/bad_input/cases.toml"


def load(root):
    with open(os.path.join(root, TABLE), "rb") as f:
        return tomllib.load(f)["case"]


def expected_lines(case):
    m = case.get("message", [])
    return [m] if isinstance(m, str) else list(m)


def md_code(s):
    s = s.replace("\n", "\\n").replace("|", "\\|")
    return f"`` {s} ``" if "`" in s else f"`{s}`"


def shell_word(a):
    if a and all(c.isalnum() or c in "-_./=,:+" for c in a):
        return a
    return "'" + a.replace("'", "'\\''") + "'"


def describe_file(name, spec):
    if isinstance(spec, str):
        return f"{md_code(name)} = {md_code(spec)}" if spec else f"{md_code(name)} empty"
    if spec.get("dir"):
        return f"{md_code(name)} a directory"
    if "result" in spec:
        kind = "the whole result" if spec["result"] == "whole" else f"shard {spec['result']}'s partial result"
        args = " ".join(spec.get("args", []))
        trace = "another scene's trace" if spec.get("workload") == "other" else "a valid trace"
        edit = {"version": ", its raplas_version edited", "truncated": ", cut in half"}.get(spec.get("edit"), "")
        return f"{md_code(name)} = {kind} of `simulate` on {trace}" + (f" with {md_code(args)}" if args else "") + edit
    if "garbage" in spec:
        return f"{md_code(name)} = {spec['garbage'] + 1} random bytes with NULs"
    return f"{md_code(name)} = {spec['trace']} trace"


def doc_text(cases):
    out = [
        "# Bad input: what raplas answers",
        "",
        f"Generated from `{TABLE}` by `tests/bad_input.py --write-doc .`; do not edit by hand.",
        "CI runs every row (`tests/unit/test_bad_input.cpp`, ctest `BadInputTable.*`) in a fresh",
        "directory holding the files shown, and checks the exit code, the whole of stderr and that",
        "a refused run leaves no file behind; `ctest -R bad_input_doc` checks that this page is the",
        "table.",
        "",
        "Exit codes: 0 success, 2 bad input or usage (one line `raplas: error: ...` naming the file",
        "and line, or the key or option), 1 internal error. `...` in a message stands for text left",
        "out here (search paths, temporary directories). A warning",
        "(`raplas: warning: ...`) leaves the exit code at 0.",
    ]
    section = None
    for c in cases:
        if c["input"] != section:
            section = c["input"]
            out += ["", f"## {section}", "", "| bad input | command and files | exit | stderr |", "|---|---|---|---|"]
        cmd = md_code("raplas " + " ".join(shell_word(a) for a in c["args"]))
        files = [describe_file(n, s) for n, s in c.get("files", {}).items()]
        env = [md_code(f"{k}={v}") for k, v in c.get("env", {}).items()]
        what = c["what"] + (f" ({c['note']})" if c.get("note") else "")
        msg = "<br>".join(md_code(m) for m in expected_lines(c)) or "(nothing)"
        out.append(f"| {what} | {'<br>'.join(env + [cmd] + files)} | {c['exit']} | {msg} |")
    return "\n".join(out) + "\n"


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("--write-doc", "--check"):
        print(__doc__)
        return 2
    root = sys.argv[2]
    text = doc_text(load(root))
    path = os.path.join(root, DOC)
    if sys.argv[1] == "--write-doc":
        with open(path, "w") as f:
            f.write(text)
        print(f"wrote {DOC}")
        return 0
    if not os.path.exists(path) or open(path).read() != text:
        print(f"{DOC} differs from {TABLE}: run tests/bad_input.py --write-doc .")
        return 1
    print(f"{DOC} matches {TABLE} ({len(load(root))} cases)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
