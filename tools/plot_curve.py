#!/usr/bin/env python3
"""Plots the main curve of a cosim run: stress-strain (UCS, CTCS), stress-displacement (BTS) or
the cutter forces against travel / depth (linear-cutting, indentation).

usage: plot_curve.py HISTORY_CSV TEST OUT_PNG
Exit status 3 with one line on stderr when matplotlib is missing.
"""
import csv
import sys


def main(argv):
    if len(argv) != 4:
        print("usage: plot_curve.py HISTORY_CSV TEST OUT_PNG", file=sys.stderr)
        return 2
    history, test, png = argv[1], argv[2].upper(), argv[3]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("python3-matplotlib is not installed", file=sys.stderr)
        return 3
    with open(history, newline="") as f:
        rows = list(csv.DictReader(f))
    col = lambda name: [float(r[name]) if r[name] not in ("", "null") else float("nan") for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4.5), dpi=150)
    if test in ("INDENTATION", "LINEAR-CUTTING"):
        # forces on the cutter against its travel (cutting) or depth (indentation)
        d = col("displacement_mm")
        ax.plot(d, col("force_kN"), color="C0", label="normal")
        if test == "LINEAR-CUTTING":
            ax.plot(d, col("rolling_force_kN"), color="C1", label="rolling")
        ax.plot(d, col("side_force_kN"), color="C2", label="side", alpha=0.7)
        ax.legend()
        ax.set_xlabel("cutter travel [mm]" if test == "LINEAR-CUTTING" else "indentation depth [mm]")
        ax.set_ylabel("force on the cutter [kN]")
    elif test == "BTS":
        ax.plot(col("displacement_mm"), col("stress_MPa"), color="C0")
        ax.set_xlabel("displacement [mm]")
        ax.set_ylabel("tensile stress 2P/(\u03c0Dt) [MPa]")
        ax2 = ax.twinx()
        ax2.plot(col("displacement_mm"), col("force_kN"), alpha=0)
        ax2.set_ylabel("force [kN]")
    else:
        strain = [100 * e for e in col("strain")]
        ax.plot(strain, col("stress_MPa"), color="C0", label="axial")
        radial = [100 * e for e in col("radial_strain")]
        if any(abs(e) > 0 for e in radial if e == e):
            ax.plot(radial, col("stress_MPa"), color="C1", label="radial")
            ax.legend()
        ax.set_xlabel("strain [%]")
        ax.set_ylabel("axial stress [MPa]")
    ax.set_title(f"{test}")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
