#!/usr/bin/env python3
"""Redraw a forma plot from the CSV written beside it, with matplotlib.

Every chart forma writes (convergence.png, coverage.png, material_E.png, ...)
has `<stem>.plot.csv` beside it with exactly the plotted numbers; its `# key:
value` lines say what kind of plot it is, its title, labels, ranges and
scales. This script turns such a file back into a figure, for a paper or a
different style:

    python3 contrib/plot/redraw.py run/coverage.plot.csv coverage.pdf
    python3 contrib/plot/redraw.py run/convergence.plot.csv   # -> run/convergence_redrawn.png
    python3 contrib/plot/redraw.py doc/data/rhombic_disk_fine_scale.csv.gz

Debian: python3-matplotlib.
"""
import csv
import gzip
import re
import sys
from collections import OrderedDict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402


def read(file_name):
    """The `# key: value` lines and the rows (dicts) of a plot's CSV."""
    meta, lines = {}, []
    opener = gzip.open if file_name.endswith(".gz") else open
    with opener(file_name, "rt", newline="", encoding="utf-8") as f:
        for line in f:
            if line.startswith("# ") and not lines:
                key, _, value = line[2:].rstrip("\n").partition(": ")
                meta[key] = value
            else:
                lines.append(line)
    return meta, list(csv.DictReader(lines))


def tex(label):
    """forma's subscripts (E_b, Delta_{R}) as matplotlib mathtext."""
    def subscript(m):
        text = m.group(1) if m.group(1) is not None else m.group(2)
        return "$_{%s}$" % text if text else ""
    return re.sub(r"_\{([^{}]*)\}|_([^{])", subscript, label)


def grouped(rows, key):
    groups = OrderedDict()
    for r in rows:
        groups.setdefault(r[key], []).append(r)
    return groups


def xy(meta, rows, ax):
    for _, series in grouped(rows, "series").items():
        first = series[0]
        x = [float(r["x"]) for r in series]
        y = [float(r["y"]) for r in series]
        label = tex(first["label"]) or None
        if first["style"] == "line":
            ax.plot(x, y, color=first["color"], lw=1.5, label=label)
        else:
            ax.plot(x, y, "o", color=first["color"], label=label,
                    ms=1.5 * (int(first["size"]) + 0.5))
    ax.set_xlim(*map(float, meta["x range"].split()))
    ax.set_ylim(*map(float, meta["y range"].split()))
    ax.set_xscale("log" if "x" in meta.get("logarithmic", "") else "linear")
    ax.set_yscale("log" if "y" in meta.get("logarithmic", "") else "linear")
    ax.set_xlabel(tex(meta.get("x label", "")))
    ax.set_ylabel(tex(meta.get("y label", "")))
    ax.grid(True, color="0.9")
    if any(r["label"] for r in rows):
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1), frameon=False)


def polygons(rows, key):
    return [[(float(r["x"]), float(r["y"])) for r in group]
            for group in grouped(rows, key).values()]


def polygon_field(meta, rows, ax):
    groups = grouped(rows, "polygon")
    values = [float(g[0]["value"]) for g in groups.values()]
    lo, hi = map(float, meta["range"].split())
    cells = PolyCollection(polygons(rows, "polygon"), array=values,
                           cmap="jet", edgecolors="0.35", linewidths=0.3)
    cells.set_clim(lo, hi)
    ax.add_collection(cells)
    ax.autoscale()
    ax.set_aspect("equal")
    ax.axis("off")
    plt.colorbar(cells, ax=ax)


def overlay(meta, rows, ax):
    for name, style in (("filled", dict(facecolors="0.43", edgecolors="none")),
                        ("outlined", dict(facecolors="none", edgecolors="r",
                                          linewidths=0.6))):
        part = [r for r in rows if r["set"] == name]
        if part:
            ax.add_collection(PolyCollection(polygons(part, "polygon"), **style))
    ax.autoscale()
    ax.set_aspect("equal")
    ax.axis("off")


def field_panels(meta, rows, ax):
    """Each panel on its own axes, over its own range, as forma draws them."""
    import numpy as np
    n_rows, n_columns = map(int, meta["grid"].split())
    per_row = int(meta["per row"])
    x0, x1 = map(float, meta["x range"].split())
    y0, y1 = map(float, meta["y range"].split())
    count = int(meta["panels"])
    grids = [np.full((n_rows, n_columns), np.nan) for _ in range(count)]
    for r in rows:
        grids[int(r["panel"])][int(r["row"]), int(r["column"])] = float(r["value"])
    fig = ax.figure
    fig.clear()
    lines = (count + per_row - 1) // per_row
    axes = fig.subplots(lines, min(per_row, count), squeeze=False)
    for k, grid in enumerate(grids):
        a = axes[k // per_row][k % per_row]
        a.imshow(grid, extent=(x0, x1, y0, y1), aspect="auto", cmap="jet")
        a.set_title(tex(meta["panel %d" % k]))
    for a in axes[-1]:
        a.set_xlabel(tex(meta.get("x label", "")))
    for line in axes:
        line[0].set_ylabel(tex(meta.get("y label", "")))
    fig.suptitle(tex(meta.get("title", "")))


def main(argv):
    if len(argv) not in (2, 3):
        sys.stderr.write(__doc__)
        return 2
    meta, rows = read(argv[1])
    kinds = {"xy": xy, "polygon field": polygon_field, "overlay": overlay,
             "field panels": field_panels}
    kind = meta.get("forma plot")
    if kind not in kinds:
        sys.stderr.write("error: '%s' is not a forma plot's data file\n" % argv[1])
        return 1
    fig, ax = plt.subplots(figsize=(8, 6), layout="constrained")
    kinds[kind](meta, rows, ax)
    if kind != "field panels":
        ax.set_title(tex(meta.get("title", "")))
    stem = argv[1][:-3] if argv[1].endswith(".gz") else argv[1]
    for suffix in (".plot.csv", ".csv"):
        if stem.endswith(suffix):
            stem = stem[:-len(suffix)]
            break
    out = argv[2] if len(argv) == 3 else stem + "_redrawn.png"
    fig.savefig(out, dpi=150)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
