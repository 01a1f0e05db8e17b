#!/usr/bin/env python3
"""Plots the main curve of a cosim run: stress-strain (UCS, CTCS), stress-displacement (BTS) or
the cutter forces against travel / depth (linear-cutting, indentation).

usage: plot_curve.py HISTORY_CSV TEST OUT_PNG [--group M1] [--spacing-mm 2.5]
                     [--ucs-MPa 282.18] [--E-GPa 97.07] [--bts-MPa 15.43] [--source "Table 3"]

UCS / CTCS: axial stress against the axial gauge strain (middle half, compression +), the platen
strain, the lateral (radial, mid-height) strain drawn negative and the volumetric strain
(axial + 2 lateral). The group's measured values, where given, are drawn over the simulated
curve: UCS as a horizontal line, E as the line of that slope through the origin (on the gauge
strain); BTS as a horizontal line. Without them the plot shows the simulation alone.
Exit status 3 with one line on stderr when matplotlib is missing.
"""
import argparse
import csv
import math
import sys


def arguments(argv):
    p = argparse.ArgumentParser(prog="plot_curve.py", description="curve.png of a cosim run")
    p.add_argument("history")
    p.add_argument("test")
    p.add_argument("png")
    p.add_argument("--group", default="", help="rock group, shown in the title")
    p.add_argument("--spacing-mm", type=float, default=0.0, help="particle spacing [mm]")
    p.add_argument("--ucs-MPa", dest="ucs", type=float, default=0.0, help="measured UCS [MPa]")
    p.add_argument("--E-GPa", dest="youngs", type=float, default=0.0, help="measured E [GPa]")
    p.add_argument("--bts-MPa", dest="bts", type=float, default=0.0, help="measured BTS [MPa]")
    p.add_argument("--source", default="", help="where the measured values come from")
    return p.parse_args(argv[1:])


def title(a, test):
    parts = [test]
    if a.group:
        parts.append(f"group {a.group}")
    if a.spacing_mm > 0:
        parts.append(f"particle spacing {a.spacing_mm:g} mm")
    return ", ".join(parts)


def measured(a, what):
    return f"{a.group + ' ' if a.group else ''}measured {what}" + (f" ({a.source})" if a.source else "")


def main(argv):
    a = arguments(argv)
    test = a.test.upper()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("python3-matplotlib is not installed", file=sys.stderr)
        return 3
    with open(a.history, newline="") as f:
        rows = list(csv.DictReader(f))

    def col(name):
        return [float(r[name]) if r.get(name) not in (None, "", "null") else float("nan") for r in rows]

    def finite_max(values):
        v = [x for x in values if x == x]
        return max(v) if v else 0.0

    fig, ax = plt.subplots(figsize=(7, 5), dpi=150)
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
        stress, force = col("stress_MPa"), col("force_kN")
        ax.plot(col("displacement_mm"), stress, color="C0", label="simulated")
        if a.bts > 0:
            ax.axhline(a.bts, color="k", ls="--", lw=1, label=measured(a, f"BTS {a.bts:.2f} MPa"))
        peak = finite_max(stress)
        ax.set_xlabel("platen displacement [mm]")
        ax.set_ylabel("tensile stress 2P/(\u03c0Dt) [MPa]")
        ax.legend(loc="lower right", fontsize=8)
        # the force axis on the right, to the same scale as the stress axis (force / stress is fixed)
        if peak > 0:
            ratio = finite_max(force) / peak
            ax2 = ax.twinx()
            lo, hi = ax.get_ylim()
            ax2.set_ylim(lo * ratio, hi * ratio)
            ax2.set_ylabel("force [kN]")
    else:
        stress = col("stress_MPa")
        platen = [100 * e for e in col("strain")]
        gauge = [100 * e for e in col("axial_gauge_strain")]
        radial = [100 * e for e in col("radial_strain")]  # extension +
        has_gauge = any(abs(e) > 0 for e in gauge if e == e)
        has_radial = any(abs(e) > 0 for e in radial if e == e)
        axial = gauge if has_gauge else platen
        ax.plot(axial, stress, color="C0", label="axial (gauge, middle half)" if has_gauge else "axial (platens)")
        if has_gauge:
            ax.plot(platen, stress, color="C0", ls=":", lw=1, label="axial (platen displacement / length)")
        if has_radial:
            lateral = [-e for e in radial]  # lateral extension drawn negative, as a gauge shows it
            ax.plot(lateral, stress, color="C1", label="lateral (radial, mid-height)")
            volumetric = [e - 2 * r for e, r in zip(axial, radial)]
            ax.plot(volumetric, stress, color="C2", label="volumetric (axial + 2 lateral)")
        peak = finite_max(stress)
        if a.ucs > 0:
            ax.axhline(a.ucs, color="k", ls="--", lw=1, label=measured(a, f"UCS {a.ucs:.1f} MPa"))
        if a.youngs > 0:
            # the measured modulus as a line through the origin, up to the measured UCS (or the
            # simulated peak when no UCS is given)
            top = a.ucs if a.ucs > 0 else peak
            if top > 0:
                e_top = 100 * top / (a.youngs * 1e3)  # [%]
                ax.plot([0, e_top], [0, top], color="k", ls="-.", lw=1,
                        label=measured(a, f"E {a.youngs:.2f} GPa"))
        ax.axvline(0, color="0.6", lw=0.6)
        ax.set_xlabel("strain [%] (compression +; lateral extension \u2212)")
        ax.set_ylabel("axial stress [MPa] (compression +)")
        ax.legend(loc="lower right", fontsize=7)
    ax.set_title(title(a, test), fontsize=10)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.png)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
