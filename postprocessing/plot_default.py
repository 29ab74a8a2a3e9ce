#!/usr/bin/env python3
"""Figure of the default scene's run (dispatches on the run's model).

Usage: plot_default.py RUN.h5 [-o FIGURE.png]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        raise SystemExit(__doc__)
    model = traverse_io.load(argv[0]).attrs.get("model")
    if model == "beam":
        import plot_beam

        plot_beam.main(argv)
    elif model == "rod":
        import plot_rod

        plot_rod.main(argv)
    else:
        raise SystemExit(f"plot_default: no figure for model '{model}'")


if __name__ == "__main__":
    main()
