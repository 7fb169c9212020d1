#!/usr/bin/env python3
"""`cmake --install` into a temporary prefix, then the installed raplas run
from an empty directory elsewhere: it must find its shipped configs and scenes
in PREFIX/share/raplas.

  tests/install_check.py CMAKE BUILD_DIR SOURCE_DIR

Checks: the binary, every configs/*.toml and scenes/*.toml and the docs are
installed where README.md says; `simulate --config paper -q --json` runs with
config "paper" and functional_match true; --dump-config works; a config and a
scene that exist only in the prefix are found by name (so the prefix is
searched, not only the source tree the build came from); a PNG is written with
the image module installed in PREFIX/lib, not the build tree's."""
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import Checks


check = Checks()


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    cmake, build, source = sys.argv[1:]
    tmp = tempfile.mkdtemp(prefix="raplas_install_")
    try:
        prefix = os.path.join(tmp, "prefix")
        work = os.path.join(tmp, "work")
        os.mkdir(work)
        r = subprocess.run([cmake, "--install", build, "--prefix", prefix], capture_output=True, text=True)
        check(r.returncode == 0, f"cmake --install {build} --prefix {prefix}: {r.stderr.strip()}")
        if r.returncode != 0:
            return 1

        exe = os.path.join(prefix, "bin", "raplas")
        data = os.path.join(prefix, "share", "raplas")
        doc = os.path.join(prefix, "share", "doc", "raplas")
        check(os.access(exe, os.X_OK), "bin/raplas is installed")
        for kind in ("configs", "scenes"):
            want = sorted(os.path.basename(p) for p in glob.glob(os.path.join(source, kind, "*.toml")))
            got = sorted(os.listdir(os.path.join(data, kind))) if os.path.isdir(os.path.join(data, kind)) else []
            check(want and got == want, f"share/raplas/{kind} holds {want} (has {got})")
        want_docs = ["README.md"] + sorted(os.path.basename(p) for p in glob.glob(os.path.join(source, "docs", "*.md")))
        missing = [d for d in want_docs if not os.path.isfile(os.path.join(doc, d))]
        check(not missing, f"share/doc/raplas holds README.md and docs/*.md (missing: {missing})")

        env = {k: v for k, v in os.environ.items() if not k.startswith("RAPLAS_")}

        def raplas(*args):
            return subprocess.run([exe, *args], cwd=work, env=env, capture_output=True, text=True)

        r = raplas("simulate", "--config", "paper", "-q", "--json", "out.json")
        check(r.returncode == 0 and r.stderr == "", f"simulate --config paper -q --json out.json: exit {r.returncode} {r.stderr.strip()}")
        out = os.path.join(work, "out.json")
        j = json.load(open(out)) if os.path.isfile(out) else {}
        check(j.get("config") == "paper", f"JSON config is \"paper\" (is {j.get('config')!r})")
        check(j.get("functional_match") is True and j.get("functional_checked") is True,
              f"JSON functional_match is true (is {j.get('functional_match')!r})")

        r = raplas("simulate", "--config", "paper", "--dump-config")
        check(r.returncode == 0 and 'name = "paper"' in r.stdout and "psi_pipes = 32" in r.stdout,
              f"simulate --config paper --dump-config: exit {r.returncode} {r.stderr.strip()}")

        # Files only the prefix holds: found by name from the empty directory.
        with open(os.path.join(data, "configs", "paper.toml")) as f:
            text = f.read().replace('name = "paper"', 'name = "prefix_only"')
        with open(os.path.join(data, "configs", "prefix_only.toml"), "w") as f:
            f.write(text)
        r = raplas("simulate", "--config", "prefix_only", "--dump-config")
        check(r.returncode == 0 and 'name = "prefix_only"' in r.stdout,
              f"--config prefix_only (only in the prefix) is found: exit {r.returncode} {r.stderr.strip()}")
        with open(os.path.join(data, "scenes", "prefix_scene.toml"), "w") as f:
            f.write('name = "prefix_scene"\n[image]\nwidth = 8\nheight = 8\n')
        r = raplas("render", "--scene", "prefix_scene", "-q", "--out", "p.png")
        check(r.returncode == 0 and os.path.isfile(os.path.join(work, "p.png")),
              f"--scene prefix_scene (only in the prefix) renders: exit {r.returncode} {r.stderr.strip()}")
        # The image module is loaded from the prefix, not from the build tree.
        modules = glob.glob(os.path.join(prefix, "lib*", "**", "raplas_oiio.so"), recursive=True)
        check(len(modules) == 1, f"the image module raplas_oiio.so is installed under PREFIX/lib (found {modules})")
        module = os.path.realpath(modules[0]) if modules else None
        r = subprocess.run([exe, "render", "-q", "--out", "m.png"], cwd=work, env={**env, "LD_DEBUG": "files"},
                           capture_output=True, text=True)
        loaded = [line.split("file=")[1].split()[0] for line in r.stderr.splitlines()
                  if "file=" in line and "raplas_oiio.so" in line and "dynamically loaded" in line]
        check(r.returncode == 0 and loaded and os.path.realpath(loaded[0]) == module,
              f"render --out m.png loads the installed image module (loaded {loaded}, exit {r.returncode})")
        r = raplas("render", "--scene", "cornell", "--dump-scene")
        check(r.returncode == 0 and 'mesh = "cornell/CornellBox-Original.obj"' in r.stdout,
              f"--scene cornell --dump-scene: exit {r.returncode} {r.stderr.strip()}")
        r = raplas("simulate", "--config", "papr")
        check(r.returncode == 2 and "(fpga, paper, prefix_only); did you mean 'paper'?" in r.stderr,
              f"--config papr lists the prefix's configs: {r.stderr.strip()}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"{check.failures} failed" if check.failures else "installed raplas finds its configs and scenes")
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
