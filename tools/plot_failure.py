#!/usr/bin/env python3
"""Pictures of where a UCS / CTCS cylinder or a BTS disc fails: damage in sections through the
specimen (reference positions, one lattice layer thick), where the damage started (the first
snapshot holding a damaged particle) and at the end of the run; below, in the same sections at the
end, how each particle failed (the failure_mode field: one colour per mode, counts in the legend).

usage: plot_failure.py RESULTS_H5 TEST OUT_PNG
UCS/CTCS: the vertical sections x-z and y-z through the axis and the mid-height section, at the end;
BTS: the disc plane (x-z, largest damage through the thickness) at the onset and at the end.
Exit status 3 with one line on stderr when matplotlib, numpy or h5py is missing.
"""
import json
import os
import sys


def layer(values, spacing):
    """Mask of the particles in the one layer nearest to 0 (on the + side): a lattice layer, or
    of body-fitted rings those within half a spacing of it."""
    import numpy as np

    target = np.min(np.abs(values))
    return np.abs(values - target) < 0.5 * spacing


def particle_spacing(x0):
    """The particle spacing: a lattice's cell (the step between its x coordinates); for
    body-fitted rings, whose x coordinates take many values, the edge of the cube each particle
    fills in the round specimen (pi/4 of its bounding box)."""
    import numpy as np

    coords = np.unique(np.round(x0[:, 0], 9))
    step = np.min(np.diff(coords)) if len(coords) > 1 else 1.0
    box = np.prod(np.ptp(x0, axis=0))
    rings = (0.25 * np.pi * box / len(x0)) ** (1.0 / 3.0)
    return step if step > 0.5 * rings else rings


def grid(a, b, c, spacing):
    """Values c at cell-centred (a, b) as an image (NaN outside the specimen), with its extent;
    where several particles share a cell (a projection), the largest value."""
    import numpy as np

    ia = np.rint((a - a.min()) / spacing).astype(int)
    ib = np.rint((b - b.min()) / spacing).astype(int)
    img = np.full((ib.max() + 1, ia.max() + 1), -np.inf)
    np.maximum.at(img, (ib, ia), c)
    img[np.isinf(img)] = np.nan
    h = 0.5 * spacing
    extent = [(a.min() - h) * 1e3, (a.max() + h) * 1e3, (b.min() - h) * 1e3, (b.max() + h) * 1e3]
    return img, extent


# failure_mode values (sph::FailureMode) and their colours
MODES = [(0, "none", "#e6e6e6"), (1, "tensile", "#2b6cb0"), (2, "shear", "#dd8a1e"),
         (3, "crushed", "#9b2226")]


def grid_mode(a, b, mode, damage, spacing):
    """Failure modes at cell-centred (a, b) as an image (NaN outside); where several particles
    share a cell (a projection), the mode of the most damaged one."""
    import numpy as np

    order = np.argsort(damage, kind="stable")  # the most damaged written last
    ia = np.rint((a - a.min()) / spacing).astype(int)[order]
    ib = np.rint((b - b.min()) / spacing).astype(int)[order]
    img = np.full((ib.max() + 1, ia.max() + 1), np.nan)
    img[ib, ia] = mode[order]
    h = 0.5 * spacing
    extent = [(a.min() - h) * 1e3, (a.max() + h) * 1e3, (b.min() - h) * 1e3, (b.max() + h) * 1e3]
    return img, extent


def main(argv):
    if len(argv) != 4:
        print("usage: plot_failure.py RESULTS_H5 TEST OUT_PNG", file=sys.stderr)
        return 2
    path, test, png = argv[1], argv[2].upper(), argv[3]
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
        import h5py
    except ImportError as e:
        print(f"{e.name} is not installed (python3-matplotlib, python3-numpy, python3-h5py)",
              file=sys.stderr)
        return 3
    with h5py.File(path, "r") as f:
        snaps = f["snapshots"]
        keys = sorted(snaps.keys())
        if not keys:
            print(f"{path}: no snapshots", file=sys.stderr)
            return 2
        x0 = snaps[keys[0]]["particles/position"][:] - snaps[keys[0]]["particles/displacement"][:]
        damage = {k: snaps[k]["particles/damage"][:] for k in keys}
        last_particles = snaps[keys[-1]]["particles"]
        mode = last_particles["failure_mode"][:] if "failure_mode" in last_particles else None
        times = {k: snaps[k].attrs.get("time_s", float("nan")) for k in keys}
    last = keys[-1]
    onset = next((k for k in keys if np.any(damage[k] > 0)), None)
    spacing = particle_spacing(x0)
    centre = x0.mean(axis=0)
    cmap = plt.get_cmap("inferno_r").copy()
    cmap.set_bad("white")

    def section(ax, mask, a, b, k, title, scale=1.0):
        img, extent = grid(x0[mask, a], x0[mask, b], damage[k][mask] / scale, spacing)
        im = ax.imshow(img, origin="lower", extent=extent, cmap=cmap, vmin=0, vmax=1,
                       interpolation="nearest")
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("xyz"[a] + " [mm]")
        ax.set_ylabel("xyz"[b] + " [mm]")
        ax.set_aspect("equal")
        return im

    if test == "BTS":
        # projected along the disc axis: the largest damage through the thickness (the first
        # damage appears at the disc's flat faces, around the centre)
        mid = np.ones(len(x0), dtype=bool)
        # the onset is shown relative to its own largest damage (the first yield is small)
        panels = [(last, "damage at the end", 1.0)]
        if onset:
            first = max(float(np.max(damage[onset])), 1e-12)
            panels.insert(0, (onset, f"damage at onset / {first:.2g}", first))
        # the failure modes in a last panel of the same row
        cols = len(panels) + (1 if mode is not None else 0)
        fig, axes = plt.subplots(1, cols, figsize=(4.2 * cols, 4.2), dpi=150, squeeze=False)
        fig.subplots_adjust(wspace=0.35)
        for ax, (k, what, scale) in zip(axes[0], panels):
            im = section(ax, mid, 0, 2, k, f"{what}, t = {times[k] * 1e3:.3f} ms\n"
                                           "largest through the thickness; load along z", scale)
        mode_sections = [(axes[0][-1], mid, 0, 2, "failure mode at the end, of the most\n"
                          "damaged particle through the thickness")] if mode is not None else []
        axes = [axes[0][:len(panels)]]
    else:
        xz = layer(x0[:, 1] - centre[1], spacing)
        yz = layer(x0[:, 0] - centre[0], spacing)
        xy = layer(x0[:, 2] - centre[2], spacing)
        rows = 2 if mode is not None else 1
        fig, axes = plt.subplots(rows, 3, figsize=(11, 5 * rows), dpi=150, squeeze=False,
                                 gridspec_kw={"width_ratios": [1, 1, 1.6]})
        fig.subplots_adjust(wspace=0.45, hspace=0.3)
        t = f"t = {times[last] * 1e3:.3f} ms"
        im = section(axes[0][0], xz, 0, 2, last, f"x-z section through the axis\n{t}")
        section(axes[0][1], yz, 1, 2, last, f"y-z section through the axis\n{t}")
        section(axes[0][2], xy, 0, 1, last, f"mid-height section\n{t}")
        mode_sections = [(axes[1][0], xz, 0, 2, "failure mode, x-z section"),
                         (axes[1][1], yz, 1, 2, "failure mode, y-z section"),
                         (axes[1][2], xy, 0, 1, "failure mode, mid-height")] if rows == 2 else []
    fig.colorbar(im, ax=list(axes[0]), shrink=0.8, label="damage (1 = residual strength)")
    if mode_sections:
        from matplotlib.colors import ListedColormap, BoundaryNorm
        from matplotlib.patches import Patch

        mcmap = ListedColormap([c for _, _, c in MODES])
        mcmap.set_bad("white")
        norm = BoundaryNorm([-0.5, 0.5, 1.5, 2.5, 3.5], mcmap.N)
        for ax, mask, a, b, title in mode_sections:
            img, extent = grid_mode(x0[mask, a], x0[mask, b], mode[mask].astype(float),
                                    damage[last][mask], spacing)
            ax.imshow(img, origin="lower", extent=extent, cmap=mcmap, norm=norm,
                      interpolation="nearest")
            ax.set_title(title, fontsize=9)
            ax.set_xlabel("xyz"[a] + " [mm]")
            ax.set_ylabel("xyz"[b] + " [mm]")
            ax.set_aspect("equal")
        counts = {v: int(np.sum(mode == v)) for v, _, _ in MODES}
        handles = [Patch(facecolor=c, edgecolor="black", linewidth=0.5,
                         label=f"{name} ({counts[v]} particles)") for v, name, c in MODES]
        mode_sections[-1][0].legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                                    fontsize=8, title="failure mode", title_fontsize=8)
    title = f"{test}: failure pattern"
    summary = os.path.join(os.path.dirname(os.path.abspath(path)), "summary.json")
    if os.path.exists(summary):
        with open(summary) as f:
            peak = json.load(f).get("peak_stress_MPa")
        if isinstance(peak, (int, float)):
            title += f", peak {peak:.1f} MPa"
    fig.suptitle(title, fontsize=10)
    fig.savefig(png, bbox_inches="tight")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
