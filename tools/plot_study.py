#!/usr/bin/env python3
"""Plots a cosim study: peak stress against the swept value, and every run's curve.

usage: plot_study.py STUDY_CSV OUT_PNG X_COLUMN [SERIES_COLUMN ...]

Left: peak_stress_MPa against X_COLUMN (numeric axis when every value is a number, else one tick
per value), one line per combination of the SERIES_COLUMNs, the reference strength (reference_MPa)
dashed in the same colour. Right: each run's curve from <folder>/history.csv next to the csv
(stress-strain for UCS/CTCS, stress-displacement for BTS).
Exit status 3 with one line on stderr when matplotlib is missing.
"""
import csv
import os
import sys


def as_float(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def main(argv):
    if len(argv) < 4:
        print("usage: plot_study.py STUDY_CSV OUT_PNG X_COLUMN [SERIES_COLUMN ...]", file=sys.stderr)
        return 2
    study, png, x_col, series_cols = argv[1], argv[2], argv[3], argv[4:]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("python3-matplotlib is not installed", file=sys.stderr)
        return 3
    with open(study, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        print("study.csv has no rows", file=sys.stderr)
        return 1
    xs = [r[x_col] for r in rows]
    numeric = all(as_float(x) == as_float(x) for x in xs)
    categories = list(dict.fromkeys(xs))
    position = (lambda x: as_float(x)) if numeric else (lambda x: categories.index(x))

    series = {}
    for r in rows:
        label = ", ".join(f"{c.split('/')[-1]}={r[c]}" for c in series_cols)
        series.setdefault(label, []).append(r)

    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.8), dpi=130)
    for i, (label, members) in enumerate(series.items()):
        members = sorted(members, key=lambda r: position(r[x_col]))
        px = [position(r[x_col]) for r in members]
        ax.plot(px, [as_float(r["peak_stress_MPa"]) for r in members], "o-", color=f"C{i % 10}",
                label=label or "simulated")
        ref = [as_float(r["reference_MPa"]) for r in members]
        if any(v == v for v in ref):
            ax.plot(px, ref, "s--", color=f"C{i % 10}", alpha=0.5, markerfacecolor="none",
                    label=(label + ": " if label else "") + members[0]["reference"])
        for r in members:
            if r["status"] != "ok":
                ax.annotate("unstable", (position(r[x_col]), as_float(r["reference_MPa"])), fontsize=7)
    if numeric:
        values = [as_float(x) for x in xs]
        if min(values) > 0 and max(values) / min(values) >= 20:
            ax.set_xscale("log")  # rates and the like span decades
    else:
        ax.set_xticks(range(len(categories)))
        ax.set_xticklabels(categories, rotation=30 if len(categories) > 6 else 0)
    ax.set_xlabel(x_col)
    test = rows[0]["test"].upper()
    ax.set_ylabel("peak tensile stress 2P/(\u03c0Dt) [MPa]" if test == "BTS" else "peak axial stress [MPa]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)

    base = os.path.dirname(os.path.abspath(study))
    for i, r in enumerate(rows):
        history = os.path.join(base, r["folder"], "history.csv")
        if r["status"] != "ok" or not os.path.exists(history):
            continue
        with open(history, newline="") as f:
            h = list(csv.DictReader(f))
        stress = [as_float(q["stress_MPa"]) for q in h]
        if test == "BTS":
            x = [as_float(q["displacement_mm"]) for q in h]
        else:
            x = [100 * as_float(q["strain"]) for q in h]
        label = ", ".join(f"{c.split('/')[-1]}={r[c]}" for c in [x_col] + series_cols)
        ax2.plot(x, stress, color=f"C{i % 10}", lw=1, label=label)
    ax2.set_xlabel("platen displacement [mm]" if test == "BTS" else "nominal axial strain [%]")
    ax2.set_ylabel(ax.get_ylabel().replace("peak ", ""))
    ax2.grid(True, alpha=0.3)
    if len(rows) <= 12:
        ax2.legend(fontsize=6)
    fig.suptitle(f"{test}: {x_col}" + (f" \u00d7 {', '.join(series_cols)}" if series_cols else ""))
    fig.tight_layout()
    fig.savefig(png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
