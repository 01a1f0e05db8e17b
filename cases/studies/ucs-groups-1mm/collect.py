#!/usr/bin/env python3
"""Collects the ten 1 mm UCS runs (one `cosim run` per group, see README.md next to this file)
into docs/results/studies/ucs-groups-1mm/study.csv, with the columns of `cosim study`, and copies
each run's history.csv into <folder>/ there so that tools/plot_study.py can draw the curves.

usage: collect.py RUN_DIR_PATTERN   e.g. collect.py '/work/runs/ucs1mm-{group}'
The fitted UCS of each group (the reference) is read from cases/data/table3_fitted_parameters.csv.
"""
import csv
import json
import os
import shutil
import sys

# M1 at 1 mm was run on its own (cases/ucs/README.md: `/usr/bin/time -v cosim run
# cases/ucs/ucs.prm --set "SPH/Particle spacing=0.001"`, two idle cores); its run folder was not
# kept, so its row is the summary recorded then, without a curve.
RECORDED = {"M1": {"test": "UCS", "peak_stress_MPa": 282.83, "youngs_modulus_GPa": 97.37,
                   "platen_modulus_GPa": float("nan"), "poissons_ratio": 0.281,
                   "strain_at_peak": float("nan"), "peak_force_kN": float("nan"),
                   "n_particles": 197600, "n_steps": 4881, "wall_seconds": 727.0,
                   "max_kinetic_to_internal_energy": float("nan"),
                   "max_force_imbalance": float("nan"), "quasi_static": True,
                   "stop_reason": "post-peak drop"}}

here = os.path.dirname(os.path.abspath(__file__))
root = os.path.abspath(os.path.join(here, "..", "..", ".."))
out = os.path.join(root, "docs", "results", "studies", "ucs-groups-1mm")


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
        folder = "%02d-Group=%s" % (k, group)
        status = "ok"
        if os.path.exists(os.path.join(run, "summary.json")):
            with open(os.path.join(run, "summary.json")) as f:
                s = json.load(f)
            os.makedirs(os.path.join(out, folder), exist_ok=True)
            shutil.copy(os.path.join(run, "history.csv"), os.path.join(out, folder, "history.csv"))
        else:
            s = RECORDED[group]  # no curve: plot_study.py draws the runs whose history.csv is here
            print("%s: the recorded summary (no run folder)" % group)
        err = 100.0 * (s["peak_stress_MPa"] / reference[group] - 1.0)
        errors.append(err)
        rows.append([folder, group, s["test"], "%.6g" % s["peak_stress_MPa"], reference[group],
                     "%.3f" % err, "Table 3 UCS", "%.6g" % s["youngs_modulus_GPa"],
                     "%.6g" % s["platen_modulus_GPa"], "%.6g" % s["poissons_ratio"],
                     "%.6g" % s["strain_at_peak"], "%.6g" % s["peak_force_kN"], s["n_particles"],
                     s["n_steps"], "%.1f" % s["wall_seconds"],
                     "%.3g" % s["max_kinetic_to_internal_energy"],
                     "%.3g" % s["max_force_imbalance"], str(s["quasi_static"]).lower(),
                     s["stop_reason"], status])
    with open(os.path.join(out, "study.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(columns)
        w.writerows(rows)
    mean = sum(abs(e) for e in errors) / len(errors)
    print("mean |error| %.3f %%, largest %.3f %%" % (mean, max(abs(e) for e in errors)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
