#!/usr/bin/env python3
"""Plots the CSV files `tactus curves` writes (docs/scenes.md, tissues.toml).

    plot_curves.py DIR

reads DIR/force_indentation.csv, force_curvature.csv, creep.csv and relaxation.csv (those
present) and writes DIR/tissues_force_indentation.png, tissues_force_curvature.png and
tissues_viscoelastic.png: seed 000's Fig. 3 (left, right) and Fig. 5. Needs matplotlib
(Debian: python3-matplotlib).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def by_tissue(rows):
    groups = {}
    for r in rows:
        groups.setdefault(r["tissue"], []).append(r)
    return groups


def number(r, key):
    v = float(r[key])
    return v if math.isfinite(v) else None


def force_indentation(directory):
    rows = read(os.path.join(directory, "force_indentation.csv"))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    for i, (tissue, rs) in enumerate(by_tissue(rows).items()):
        colour = f"C{i}"
        d = [1e3 * float(r["indentation_m"]) for r in rs]
        h = [1e3 * float(r["penetration_m"]) for r in rs]
        f = [float(r["force_n"]) for r in rs]
        left.plot(d, f, color=colour, label=f"{tissue} ({rs[0]['nodes']}/{rs[0]['tets']})")
        left.plot(d, [float(r["hertz_at_indentation_n"]) for r in rs], color=colour, linestyle="--", linewidth=1)
        right.plot(h, f, color=colour, label=tissue)
        right.plot(h, [float(r["hertz_at_penetration_n"]) for r in rs], color=colour, linestyle=":", linewidth=2)
    left.set_title("force vs indentation (dashed: Hertz)")
    left.set_xlabel("indentation below the undeformed surface [mm]")
    right.set_title("force vs penetration h, eq. 2 (dotted: Hertz)")
    right.set_xlabel("penetration h [mm]")
    for ax in (left, right):
        ax.set_ylabel("palpation force [N]")
        ax.grid(alpha=0.3)
    left.legend(fontsize=8, title="tissue (nodes/tets)", title_fontsize=8)
    fig.tight_layout()
    out = os.path.join(directory, "tissues_force_indentation.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def force_curvature(directory):
    rows = read(os.path.join(directory, "force_curvature.csv"))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    markers = {"plane": "s", "sphere": "o", "cylinder": "^"}
    for kind in ("plane", "sphere", "cylinder"):
        rs = [r for r in rows if r["surface"] == kind]
        if not rs:
            continue
        ax.plot([float(r["estimated_mean_curvature_per_m"]) for r in rs], [float(r["force_n"]) for r in rs],
                marker=markers[kind], linestyle="none", label=f"{kind} (simulated)")
    exact = sorted(rows, key=lambda r: float(r["exact_mean_curvature_per_m"]))
    ax.plot([float(r["exact_mean_curvature_per_m"]) for r in exact], [float(r["hertz_force_n"]) for r in exact],
            color="k", linewidth=1, label="Hertz, 1/R = 1/R_f + k_mean")
    depth = 1e3 * float(rows[0]["depth_m"])
    ax.set_title(f"force at equal depth {depth:.2g} mm vs local mean curvature")
    ax.set_xlabel("estimated mean curvature of the touched surface [1/m]")
    ax.set_ylabel("palpation force [N]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = os.path.join(directory, "tissues_force_curvature.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def viscoelastic(directory):
    creep = by_tissue(read(os.path.join(directory, "creep.csv")))
    relax = by_tissue(read(os.path.join(directory, "relaxation.csv")))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    for i, tissue in enumerate(creep):
        colour = f"C{i}"
        rs = creep[tissue]
        u_end = abs(float(rs[-1]["displacement_m"])) or 1.0
        t = [float(r["time_s"]) for r in rs]
        left.plot(t, [float(r["displacement_m"]) / u_end for r in rs], color=colour, label=f"{tissue} (dt {rs[0]['time_step_s']} s)")
        a = [(float(r["time_s"]), number(r, "analytic_m")) for r in rs]
        a = [(x, y / u_end) for x, y in a if y is not None]
        if a:
            left.plot(*zip(*a), color=colour, linestyle="--", linewidth=1)
        rs = relax.get(tissue, [])
        if not rs:
            continue
        f_end = abs(float(rs[-1]["force_n"])) or 1.0
        right.plot([float(r["time_s"]) for r in rs], [float(r["force_n"]) / f_end for r in rs], color=colour, label=tissue)
        a = [(float(r["time_s"]), number(r, "analytic_n")) for r in rs]
        a = [(x, y / f_end) for x, y in a if y is not None]
        if a:
            right.plot(*zip(*a), color=colour, linestyle="--", linewidth=1)
    left.set_title("creep under a constant load (dashed: SLS)")
    left.set_ylabel("displacement / final displacement")
    right.set_title("relaxation at a held displacement (dashed: SLS)")
    right.set_ylabel("force / final force")
    for ax in (left, right):
        ax.set_xlabel("time [s]")
        ax.set_xscale("symlog", linthresh=1.0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    out = os.path.join(directory, "tissues_viscoelastic.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print("usage: plot_curves.py DIR (a folder written by 'tactus curves')", file=sys.stderr)
        return 1
    directory = argv[1]
    plots = [("force_indentation.csv", force_indentation), ("force_curvature.csv", force_curvature),
             ("creep.csv", viscoelastic)]
    for csv_name, plot in plots:
        if os.path.exists(os.path.join(directory, csv_name)):
            print(f"plot_curves: wrote {plot(directory)}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
