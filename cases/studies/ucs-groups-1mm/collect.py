#!/usr/bin/env python3
"""Collects the ten 1 mm UCS runs (one `cosim run` per group, see README.md next to this file)
into study.csv, with the columns of `cosim study`, and copies each run's history.csv into
<folder>/ here so that tools/plot_study.py can draw the curves.

usage: collect.py RUN_DIR_PATTERN   e.g. collect.py '/work/runs/ucs1mm-{group}'
The fitted UCS of each group (the reference) is read from cases/data/table3_fitted_parameters.csv.
"""
import csv
import json
import os
import shutil
import sys

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.abspath(os.path.join(here, "..", "..", ".."))


def table3():
    ucs = {}
    with open(os.path.join(root, "cases", "data", "table3_fitted_parameters.csv")) as f:
        rows = (line for line in f if not line.startswith("#"))
        for row in csv.DictReader(rows):
            ucs[row["group"]] = float(row["UCS_MPa"])
    return ucs


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    reference = table3()
    columns = ["folder", "Rock/Group", "test", "peak_stress_MPa", "reference_MPa", "error_percent",
               "reference", "youngs_modulus_GPa", "platen_modulus_GPa", "poissons_ratio",
               "strain_at_peak", "peak_force_kN", "n_particles", "n_steps", "wall_seconds",
               "max_kinetic_to_internal_energy", "max_force_imbalance", "quasi_static",
               "stop_reason", "status"]
    rows, errors = [], []
    for k in range(1, 11):
        group = "M%d" % k
        run = argv[1].format(group=group)
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        folder = "%02d-Group=%s" % (k, group)
        os.makedirs(os.path.join(here, folder), exist_ok=True)
        shutil.copy(os.path.join(run, "history.csv"), os.path.join(here, folder, "history.csv"))
        err = 100.0 * (s["peak_stress_MPa"] / reference[group] - 1.0)
        errors.append(err)
        rows.append([folder, group, s["test"], "%.6g" % s["peak_stress_MPa"], reference[group],
                     "%.3f" % err, "Table 3 UCS", "%.6g" % s["youngs_modulus_GPa"],
                     "%.6g" % s["platen_modulus_GPa"], "%.6g" % s["poissons_ratio"],
                     "%.6g" % s["strain_at_peak"], "%.6g" % s["peak_force_kN"], s["n_particles"],
                     s["n_steps"], "%.1f" % s["wall_seconds"],
                     "%.3g" % s["max_kinetic_to_internal_energy"],
                     "%.3g" % s["max_force_imbalance"], str(s["quasi_static"]).lower(),
                     s["stop_reason"], "ok"])
    with open(os.path.join(here, "study.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        w.writerows(rows)
    mean = sum(abs(e) for e in errors) / len(errors)
    print("mean |error| %.3f %%, largest %.3f %%" % (mean, max(abs(e) for e in errors)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
