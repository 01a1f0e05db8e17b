#!/usr/bin/env python3
"""Plots of `cosim diagnose`: envelope.png (strength envelope per group, baseline vs extended vs
data, compression positive) and curves.png (pre-peak force-displacement points, measured vs the
baseline and extended surrogate) and, after coupled runs, simulations.png (each simulated
specimen's measured curve against the coupled simulator's baseline and extended cases).
Usage: plot_diagnosis.py OUTDIR (reads envelope.csv, points.csv, simulations/curves.csv)."""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(x):
    return float(x) if x not in ("", None) else None


def main():
    out = sys.argv[1]
    env = rows(os.path.join(out, "envelope.csv"))
    pts = rows(os.path.join(out, "points.csv"))
    groups = list(dict.fromkeys(r["group"] for r in env))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]

    fig, ax = plt.subplots(figsize=(7, 5))
    for i, g in enumerate(groups):
        c = colours[i % len(colours)]
        er = [r for r in env if r["group"] == g]
        b = sorted((num(r["sigma3_MPa"]), num(r["baseline_sigma1_MPa"])) for r in er if r["baseline_sigma1_MPa"])
        e = sorted((num(r["sigma3_MPa"]), num(r["extended_sigma1_MPa"])) for r in er if r["extended_sigma1_MPa"])
        ax.plot([p[0] for p in b], [p[1] for p in b], "--", color=c, lw=1,
                label="baseline" if i == 0 else None)
        ax.plot([p[0] for p in e], [p[1] for p in e], "-", color=c, lw=1.5,
                label="extended" if i == 0 else None)
        sp = [r for r in pts if r["group"] == g and r["kind"] == "strength"]
        xs = [(-num(r["measured"]) if r["test"] == "BTS" else num(r["sigma3_MPa"])) for r in sp]
        ys = [(0.0 if r["test"] == "BTS" else num(r["measured"])) for r in sp]
        ax.plot(xs, ys, "o", color=c, ms=4, label=g if len(groups) <= 10 else None)
    ax.set_xlabel("sigma3 [MPa] (compression +; BTS at sigma3 = -BTS)")
    ax.set_ylabel("sigma1 at failure [MPa]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    ax.set_title("Strength envelope: baseline (dashed), extended (solid), data (dots)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "envelope.png"), dpi=120)
    plt.close(fig)

    cp = [r for r in pts if r["kind"] == "curve"]
    if cp:
        fig, ax = plt.subplots(figsize=(7, 5))
        sources = list(dict.fromkeys(r["source"] for r in cp))
        for i, s in enumerate(sources):
            c = colours[i % len(colours)]
            rr = [r for r in cp if r["source"] == s]
            f = [num(r["force_kN"]) for r in rr]
            ax.plot([num(r["measured"]) for r in rr], f, "o", color=c, ms=3,
                    label="measured" if i == 0 else None)
            ax.plot([num(r["baseline"]) for r in rr], f, "--", color=c, lw=1,
                    label="baseline" if i == 0 else None)
            ax.plot([num(r["extended"]) for r in rr], f, "-", color=c, lw=1.5,
                    label="extended" if i == 0 else None)
        ax.set_xlabel("displacement [mm]")
        ax.set_ylabel("force [kN]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title("Pre-peak curves: measured, baseline, extended")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "curves.png"), dpi=120)
        plt.close(fig)

    sim = os.path.join(out, "simulations", "curves.csv")
    if os.path.exists(sim):
        plot_simulations(rows(sim), os.path.join(out, "simulations.png"),
                         simulation_titles(os.path.join(out, "diagnosis.json")))


def simulation_titles(path):
    """Panel titles by case-file stem (s1, s2, ...): test, size, confinement, from diagnosis.json."""
    try:
        with open(path, encoding="utf-8") as f:
            sims = json.load(f).get("simulations", [])
    except (OSError, ValueError):
        return {}
    titles = {}
    for i, m in enumerate(sims):
        # the measured peak as a force, for specimens without a measured curve [kN]
        peak, d, l = m.get("measured_peak_MPa"), m.get("diameter_mm", 0), m.get("length_mm", 0)
        if isinstance(peak, (int, float)):
            if m.get("test") == "BTS":
                force = peak * 3.141592653589793 * d * l / 2 / 1e3
            else:
                force = (peak - m.get("confining_MPa", 0)) * 3.141592653589793 * d * d / 4 / 1e3
            titles["peak s%d" % (i + 1)] = force
        t = "s%d: %s %g x %g mm" % (i + 1, m.get("test", ""), m.get("diameter_mm", 0), m.get("length_mm", 0))
        if m.get("test") == "CTCS":
            t += ", sigma3 %g MPa" % m.get("confining_MPa", 0)
        titles["s%d" % (i + 1)] = t
    return titles


def plot_simulations(sr, path, titles):
    """One panel a simulated specimen: measured, baseline and extended coupled runs."""
    names = list(dict.fromkeys(r["specimen"] for r in sr))
    n = len(names)
    cols = min(n, 3)
    nrows = (n + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(4 * cols, 3.2 * nrows), squeeze=False)
    style = {"measured": ("o", "k", 2), "baseline": ("--", "tab:blue", 1.2),
             "extended": ("-", "tab:red", 1.5)}
    for k, name in enumerate(names):
        ax = axes[k // cols][k % cols]
        for source, (ls, colour, w) in style.items():
            rr = [r for r in sr if r["specimen"] == name and r["source"] == source]
            if not rr:
                continue
            x = [num(r["displacement_mm"]) for r in rr]
            f = [num(r["force_kN"]) for r in rr]
            if ls == "o":
                ax.plot(x, f, ls, color=colour, ms=w, label=source)
            else:
                ax.plot(x, f, ls, color=colour, lw=w, label=source)
        if not any(r["specimen"] == name and r["source"] == "measured" for r in sr) \
                and ("peak " + name) in titles:
            ax.axhline(titles["peak " + name], color="k", ls=":", lw=1, label="measured peak")
        ax.set_title(titles.get(name, name), fontsize=8)
        ax.set_xlabel("displacement [mm]", fontsize=8)
        ax.set_ylabel("force [kN]", fontsize=8)
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=7)
    for k in range(n, nrows * cols):
        axes[k // cols][k % cols].axis("off")
    fig.suptitle("Coupled simulator on held-out specimens: measured, baseline, extended", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
