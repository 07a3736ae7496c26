"""The plot scripts' readers: the shatterpy package (python/shatterpy), importable from the
source tree without installing it. `import shatter_plot as sp` gives every reader shatterpy
exports (read_snapshot, timeseries, fragments, ...)."""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "python"))

from shatterpy import *  # noqa: E402,F401,F403  (the package's public names, __all__)

if __name__ == "__main__":
    # Run directly, it lists the readers it gives (a check that shatterpy imports from here).
    import argparse

    import shatterpy

    argparse.ArgumentParser(description=__doc__).parse_args()
    print(" ".join(sorted(shatterpy.__all__)))
