#!/usr/bin/python3
"""The plot scripts' shared conventions: headless matplotlib, one dpi, the common axis labels.

Every figure of tools/beta.py and studies/dart/ (and whatever script imports it) is drawn with
the Agg backend (no display needed: runs on the build machines and in CI), saved at DPI dots per
inch after tight_layout, and labels its common axes with the names in LABELS, so that the same
quantity reads the same in every figure:

    import plot_common as pc
    fig, ax = pc.subplots(figsize=(6.5, 4.5))
    ax.loglog(q, m)
    pc.label(ax, "v_over_U", "M_over_m")
    pc.legend(ax)
    pc.save(fig, "figure.png")

Run directly with --demo FILE.png it draws a small figure with each convention (a check that
matplotlib is importable headless here); without arguments it lists the labels.
"""

import argparse

DPI = 120  # dots per inch of every saved figure
LEGEND_FONTSIZE = 8

# The common axes: key -> label. A key not listed is used as the label itself.
LABELS = {
    "t_ms": "time (ms)",
    "beta": "beta",
    "beta_launch": "beta_launch",
    "dt": "dt (s)",
    "v_over_U": "launch speed v / U",
    "M_over_m": "M(>v) / m_imp",
    "friction": "coefficient of internal friction f",
    "porosity": "porosity (%)",
    "cohesion": "cohesion Ydam0 (Pa)",
}


def pyplot():
    """matplotlib.pyplot on the Agg backend (headless)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def subplots(*args, **kwargs):
    """pyplot().subplots(...) on the Agg backend: (figure, axes)."""
    return pyplot().subplots(*args, **kwargs)


def label(ax, x=None, y=None):
    """Set the axes' labels from LABELS (or the text given when it is not a key)."""
    if x is not None:
        ax.set_xlabel(LABELS.get(x, x))
    if y is not None:
        ax.set_ylabel(LABELS.get(y, y))


def legend(ax, fontsize=LEGEND_FONTSIZE, **kwargs):
    return ax.legend(fontsize=fontsize, **kwargs)


def save(fig, path, dpi=DPI):
    """tight_layout, write the figure to path at DPI, and close it."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    pyplot().close(fig)


def write_csv(path, comment, rows, keys=None):
    """Writes rows (dicts) to path as CSV after one '# comment' line; floats with 5 significant
    digits; keys: the columns (default: every key, in first-seen order)."""
    import csv
    if keys is None:
        keys = []
        for r in rows:
            keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as f:
        f.write(f"# {comment}\n")
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.5g}" if isinstance(v, float) else v) for k, v in r.items()})


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--demo", metavar="FILE.png", help="draw a small figure with the conventions")
    a = ap.parse_args()
    if a.demo:
        fig, ax = subplots(figsize=(4, 3))
        ax.plot([0.0, 1.0, 2.0], [1.0, 2.0, 2.5], label="beta_launch")
        label(ax, "t_ms", "beta")
        legend(ax)
        save(fig, a.demo)
        print(f"wrote {a.demo} at {DPI} dpi")
    else:
        for key, text in LABELS.items():
            print(f"{key}: {text}")


if __name__ == "__main__":
    main()
