#!/usr/bin/env python3
"""examples/embed_icc built and run against an installed raplas: `cmake
--install` of the build tree into a temporary prefix, the example copied out of
the source tree, configured with CMake (find_package(raplas CONFIG) through
CMAKE_PREFIX_PATH = the prefix), built and run.

  tests/embed_example.py CMAKE CXX BUILD_DIR SOURCE_DIR

Checks: the package config, the static libraries and the headers the example
includes are installed; the example's build finds raplas in the prefix and
names no file of the source or build tree; it builds; it runs, prints PASS and
exits 0 (its own check of the ICC's nearest hits)."""
import os
import shutil
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testlib import Checks


check = Checks()


def run(cmd, **kw):
    t = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    return r, time.monotonic() - t


def tail(r, n=40):
    lines = (r.stdout + r.stderr).strip().splitlines()
    return "\n".join(lines[-n:])


def main():
    if len(sys.argv) != 5:
        print(__doc__)
        return 2
    cmake, cxx, build, source = sys.argv[1:]
    build, source = os.path.realpath(build), os.path.realpath(source)
    tmp = tempfile.mkdtemp(prefix="raplas_embed_")
    try:
        prefix = os.path.join(tmp, "prefix")
        r, s = run([cmake, "--install", build, "--prefix", prefix])
        if not check(r.returncode == 0, f"cmake --install {build} --prefix {prefix} ({s:.1f} s)"):
            print(tail(r))
            return 1
        for f in ("lib/cmake/raplas/raplasConfig.cmake", "lib/cmake/raplas/raplasConfigVersion.cmake",
                  "lib/cmake/raplas/raplasTargets.cmake", "lib/libraplas_models.a", "lib/libraplas_frontend.a",
                  "lib/libraplas_util.a", "lib/libraplas_core.a", "include/raplas/models/netlist/icc_module.hpp",
                  "include/raplas/models/icc.hpp", "include/raplas/frontend/raygroups.hpp",
                  "include/raplas/core/intersect.hpp"):
            check(os.path.isfile(os.path.join(prefix, f)), f"PREFIX/{f} is installed")

        # The example outside the source tree: nothing but the prefix to build from.
        src = os.path.join(tmp, "embed_icc")
        shutil.copytree(os.path.join(source, "examples", "embed_icc"), src)
        out = os.path.join(tmp, "build")
        gen = ["-G", "Ninja"] if shutil.which("ninja") else []
        r, s = run([cmake, "-S", src, "-B", out, *gen, f"-DCMAKE_PREFIX_PATH={prefix}", f"-DCMAKE_CXX_COMPILER={cxx}"])
        if not check(r.returncode == 0, f"the example configures against the prefix ({s:.1f} s)"):
            print(tail(r))
            return 1
        with open(os.path.join(out, "CMakeCache.txt")) as f:
            found = [line.split("=", 1)[1].strip() for line in f if line.startswith("raplas_DIR:")]
        check(found == [os.path.join(prefix, "lib", "cmake", "raplas")],
              f"find_package(raplas) finds the prefix's ({found})")

        r, s = run([cmake, "--build", out])
        if not check(r.returncode == 0, f"the example builds ({s:.1f} s)"):
            print(tail(r))
            return 1
        # What the build ran (compile and link lines) names the prefix, never the trees it came from.
        if gen:
            commands = subprocess.run([shutil.which("ninja"), "-C", out, "-t", "commands"], capture_output=True,
                                      text=True).stdout
            check(prefix in commands and source not in commands and build not in commands,
                  "its compile and link lines name the prefix, not the source or build tree")

        exe = os.path.join(out, "embed_icc")
        env = {**os.environ, "SYSTEMC_DISABLE_COPYRIGHT_MESSAGE": "1"}
        r, s = run([exe], cwd=tmp, env=env, timeout=120)
        print(r.stdout.rstrip())
        if r.stderr.strip():
            print(r.stderr.rstrip())
        lines = r.stdout.splitlines()
        check(r.returncode == 0 and lines and lines[-1].startswith("PASS"),
              f"embed_icc exits 0 and prints PASS (exit {r.returncode}, {s:.1f} s)")
        check(sum(line.startswith("ray (") for line in lines) == 16, "it prints the 16 rays' hits")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"{check.failures} failed" if check.failures else "the example builds and passes against the installed raplas")
    return 1 if check.failures else 0


if __name__ == "__main__":
    sys.exit(main())
