#!/usr/bin/env python3
"""Plots the force traces `tactus bench SCENE --trace DIR` writes (seed 003 Figs. 7-8).

    plot_forces.py DIR NAME

reads DIR/NAME_forces.csv (t, device, force magnitude, contact), DIR/NAME_ruptures.csv
(needle ruptures) and DIR/NAME_states.csv (two-finger contact states, seed 002 Table I) and
writes DIR/NAME_forces.png: one panel per device, the force magnitude sent to it over time,
each rupture marked with its layer, the force sent just before it gave (shaft friction
included) and, in brackets, the layer's own spring force; and for a finger of a pair, its
contact state I-IX as a step line on the right axis. Needs matplotlib (Debian:
python3-matplotlib).
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
    states = read(os.path.join(folder, name + "_states.csv"))
    numerals = ["I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX"]
    end = max(float(r["t"]) for r in frames)
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
        changes = [r for r in states if r["device"] == device]
        if changes:
            # The state as a step line: each change holds until the next one.
            right = ax.twinx()
            ts = [float(r["t"]) for r in changes] + [end]
            levels = [numerals.index(r["state"]) + 1 for r in changes]
            right.step(ts, levels + levels[-1:], where="post", lw=0.6, color="tab:orange")
            right.set_yticks(range(1, 10))
            right.set_yticklabels(numerals, fontsize=7)
            right.set_ylim(0.5, 9.5)
            right.set_ylabel("state (Table I)", color="tab:orange")
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(f"{name}: force magnitude sent to each device")
    fig.tight_layout()
    out = os.path.join(folder, name + "_forces.png")
    fig.savefig(out, dpi=110)
    print(f"plot: {out}")


if __name__ == "__main__":
    main()
