#!/usr/bin/env python3
"""Plots the force traces `tactus bench SCENE --trace DIR` writes (seed 003 Figs. 7-8).

    plot_forces.py DIR NAME

reads DIR/NAME_forces.csv (t, device, force magnitude, contact) and DIR/NAME_ruptures.csv
(needle ruptures) and writes DIR/NAME_forces.png: one panel per device, the force magnitude
sent to it over time, each rupture marked with its layer, the force sent just before it
gave (shaft friction included) and, in brackets, the layer's own spring force. Needs
matplotlib (Debian: python3-matplotlib).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    folder, name = sys.argv[1], sys.argv[2]
    frames = read(os.path.join(folder, name + "_forces.csv"))
    if not frames:
        sys.exit(f"plot_forces.py: {folder}/{name}_forces.csv holds no frame")
    ruptures = read(os.path.join(folder, name + "_ruptures.csv"))
    devices = list(dict.fromkeys(r["device"] for r in frames))
    fig, axes = plt.subplots(len(devices), 1, figsize=(9, 2.6 * len(devices)), sharex=True, squeeze=False)
    for ax, device in zip(axes[:, 0], devices):
        rows = [r for r in frames if r["device"] == device]
        ax.plot([float(r["t"]) for r in rows], [float(r["force"]) for r in rows], lw=0.6, color="tab:blue")
        for r in ruptures:
            if r["device"] != device:
                continue
            t = float(r["t"])
            # Label what is plotted: the force sent just before the layer gave, which holds the
            # shaft's friction on top of the layer's own spring (given in brackets).
            near = [float(f["force"]) for f in rows if t - 0.005 <= float(f["t"]) <= t + 0.0005]
            peak = max(near) if near else float(r["force"])
            ax.axvline(t, color="tab:red", lw=0.6, ls="--")
            ax.annotate(f"{r['layer']} {peak:.2f} N (layer {float(r['force']):.2f} N)", (t, peak), fontsize=7,
                        color="tab:red", xytext=(3, 3), textcoords="offset points")
        ax.set_ylabel(f"{device}: |F| [N]")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(f"{name}: force magnitude sent to each device")
    fig.tight_layout()
    out = os.path.join(folder, name + "_forces.png")
    fig.savefig(out, dpi=110)
    print(f"plot: {out}")


if __name__ == "__main__":
    main()
