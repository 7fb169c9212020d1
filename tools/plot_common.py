"""What the plotting tools (plot_sweep.py, plot_anatomy.py) share: matplotlib
with the Agg backend, or the tool run again with the system interpreter,
which has Debian's python3-matplotlib when the python3 first on PATH (a
virtualenv, pyenv) does not."""
import os
import sys

SYSTEM_PYTHON = "/usr/bin/python3"


def need_matplotlib(fail):
    """matplotlib.pyplot with the Agg backend; else the running tool (sys.argv)
    executed again by the system interpreter, once; else fail(message, code=1)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        return plt
    except ImportError:
        here = os.path.realpath(sys.executable or "")
        if os.path.exists(SYSTEM_PYTHON) and here != os.path.realpath(SYSTEM_PYTHON) \
                and not os.environ.get("RAPLAS_PLOT_REEXEC"):
            os.environ["RAPLAS_PLOT_REEXEC"] = "1"
            os.execv(SYSTEM_PYTHON, [SYSTEM_PYTHON, os.path.abspath(sys.argv[0])] + sys.argv[1:])
        fail(f"matplotlib is missing for {sys.executable} (Debian: apt-get install python3-matplotlib, "
             f"or run tools/install-deps.sh)", code=1)
