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
    if "link" in spec:
        return f"{md_code(name)} a symbolic link to {md_code(spec['link'])}"
    if "result" in spec:
        kind = "the whole result" if spec["result"] == "whole" else f"shard {spec['result']}'s partial result"
        args = " ".join(spec.get("args", []))
        trace = "another scene's trace" if spec.get("workload") == "other" else "a valid trace"
        edit = {"version": ", its raplas_version edited", "truncated": ", cut in half",
                "model": ", its model identity edited (made by a build of other sources)"}.get(spec.get("edit"), "")
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
        "table. A row said to hold in a build with (or without) Verilator runs only in such a build",
        "(the RTL co-simulation, `sim.rtl`; CI's builds have Verilator).",
        "",
        "Exit codes: 0 success, 2 bad input or usage (one line `raplas: error: ...` naming the file",
        "and line, or the key or option), 1 internal error. `...` in a message stands for text left",
        "out here (search paths, temporary directories). A warning",
        "(`raplas: warning: ...`) leaves the exit code at 0. A case may run commands first",
        "(`first`) and write files over before its own (`then`); every file a case makes must be",
        "unchanged after its command.",
        "",
        "## Rules",
        "",
        "What every command holds to, checked before any work is done:",
        "",
        "1. **Outputs never touch inputs.** Every output (`--out`, `--json`, `--csv`, `--vcd`, `--hits`,",
        "   `--heatmap`, `--gif`, `--update`, `--emit-jobs` with its `.traces` and `.merge` files, each",
        "   frame of a `--frames` pattern) is compared with every input (`--scene` and every mesh file",
        "   it resolves to, `--mesh`, `--config`, `--trace`, `--check`, the parts given to `merge`) and",
        "   with the other outputs: by device and inode when both exist (a link is the file it names),",
        "   by resolved path otherwise. A pair that is one file is refused, and so is an output whose",
        "   folder does not exist or cannot be written.",
        "2. **What cannot apply is refused.** With `--trace`, a scene key is refused (the trace fixes",
        "   the scene: image, groups, spheres, light), and so is a trace made with other values than",
        "   the config's `workload.group_size`, `workload.shadow_group_size` or",
        "   `workload.triangles_per_sphere` (0 follows the trace or scene). Given with `--set`, a scene",
        "   key that a workload key overrides (`groups.size` under `workload.group_size = 16`) and a",
        "   config key that applies only under another setting (`sim.sample_fraction` without",
        "   `sim.estimate = sample_passes`, `sim.fault_icc` without a fault, a `memory.*` key of a",
        "   memory system not simulated) are refused; in a sweep, when they apply to no point.",
        "3. **Results say what was simulated.** A workload key of 0 is reported as the value the",
        "   workload has, in `resolved_config`, `overrides` (against the named config resolved the",
        "   same way), `config_hash`, the area and the CSV columns `group_size`,",
        "   `shadow_group_size` and `triangles_per_sphere`: one run gives the same figures whether it",
        "   came from a scene or a trace.",
        "4. **Work is content-addressed.** Every work dir (a sweep's `sweep.json`, the `shards.json`",
        "   of `simulate --shards --emit-jobs`, the `frames.json` of `simulate --frames --emit-jobs`)",
        "   records hashes of the scene file and every mesh it resolves to, the config file, the",
        "   `--set` keys, a trace given, and the model identity: a hash of the sources of the",
        "   engines, the front end and the shipped configs, made at build time. A later run with any",
        "   of them changed is refused, naming what changed; with `--fresh` it removes the results",
        "   the change makes stale instead (in a sweep, the points of the changed inputs when nothing",
        "   else changed). Shard and frame results carry the same record (a trace by a hash of its",
        "   blocks), and `merge` refuses parts made from other inputs.",
        "5. **A failed point has no result.** A sweep point whose run failed (a functional mismatch",
        "   included) leaves its row beside it as `point-N.failed.csv`, not as a result: a rerun",
        "   simulates it again.",
        "6. **No leftovers.** `render --frames` refuses a pattern whose folder holds frames of another",
        "   run (numbers outside this run's range). Temporary files are named",
        "   `.NAME.raplas-tmp-PID.EXT`; a run that writes NAME first removes those whose process no",
        "   longer exists (a killed run's).",
    ]
    section = None
    for c in cases:
        if c["input"] != section:
            section = c["input"]
            out += ["", f"## {section}", "", "| bad input | command and files | exit | stderr |", "|---|---|---|---|"]
        cmd = md_code("raplas " + " ".join(shell_word(a) for a in c["args"]))
        files = [describe_file(n, s) for n, s in c.get("files", {}).items()]
        code = c.get("before_exit", 0)
        files += ["first " + md_code("raplas " + " ".join(shell_word(a) for a in b)) + (f" (exit {code})" if code else "")
                  for b in c.get("before", [])]
        files += ["then " + describe_file(n, s) for n, s in c.get("change", {}).items()]
        files += [f"afterwards {md_code(n)} is gone" for n in c.get("absent", [])]
        env = [md_code(f"{k}={v}") for k, v in c.get("env", {}).items()]
        notes = [c["note"]] if c.get("note") else []
        if "rtl" in c:  # run only in builds with (without) Verilator
            notes.append(f"checked only in a build {'with' if c['rtl'] else 'without'} Verilator")
        what = c["what"] + (f" ({'; '.join(notes)})" if notes else "")
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
