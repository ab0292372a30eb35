"""The course programs' first import: numpy, matplotlib, the kincal module and the kincal program, or one
line saying what is missing and how to get it (a program run before `scripts/setup` or before a build
would otherwise end in a Python traceback).

The module comes from PYTHONPATH, an installed copy (`scripts/demo` installs it) or the build tree
(build/python of this repository); the program from KINCAL_CLI or build/apps/kincal."""
import importlib
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
HOW = "run `scripts/setup && scripts/demo` in the repository's root"


def _stop(what):
    print(f"{pathlib.Path(sys.argv[0]).name}: {what}: {HOW}", file=sys.stderr)
    sys.exit(2)


for _module in ("numpy", "matplotlib"):
    try:
        importlib.import_module(_module)
    except ImportError:
        _stop(f"the Python module {_module} is not installed")
try:
    import kincal  # noqa: E402
except ImportError:
    sys.path.insert(0, str(ROOT / "build" / "python"))
    try:
        import kincal  # noqa: F811
    except ImportError:
        sys.path.pop(0)
        _stop("the kincal Python module is not built (nor on PYTHONPATH)")


def cli():
    """The kincal program: KINCAL_CLI, or this repository's build/apps/kincal."""
    path = os.environ.get("KINCAL_CLI", str(ROOT / "build" / "apps" / "kincal"))
    if not os.access(path, os.X_OK):
        _stop(f"no kincal program at {path} (KINCAL_CLI names another)")
    return path
