#!/usr/bin/env python3
"""What a force algorithm written in Python costs per haptic frame (docs/python.md).

Steps the default scene with its block made rigid (so the frame itself is cheap and the call
shows) and the default scene itself, each with no Python algorithm and with one returning a
constant, alternately; prints the medians over the runs [µs per frame].

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python/force_algorithm_cost.py [RUNS]
"""
import re
import statistics
import sys
import time

import tactus


def rigid_default():
    """The default scene with its block rigid: no simulation, a proxy on a box."""
    text = tactus.default_scene().text
    text = text.replace('kind = "fem"', 'kind = "rigid"').replace("cells = [10, 10, 4]", "cells = 4")
    text = re.sub(r"\[\[bodies\.block\.fixed\]\][^\[]*", "", text)
    text = re.sub(r"(material|integrator|time_step) = .*\n", "", text)
    return tactus.parse_scene(text, "default_rigid.toml")


def per_frame(model, algorithms, frames):
    sim = tactus.Simulation(model, force_algorithms=algorithms)
    sim.step(100)
    start = time.perf_counter()
    sim.step(frames)
    return (time.perf_counter() - start) / frames * 1e6


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    constant = {"hand": lambda t, position, velocity, contact_force, touching: (0.0, 0.0, 0.0)}
    for name, model, frames in (("rigid block", rigid_default(), 20000), ("default scene", tactus.default_scene(), 5000)):
        plain, python = [], []
        for _ in range(runs):
            plain.append(per_frame(model, {}, frames))
            python.append(per_frame(model, constant, frames))
        print(f"{name}: {statistics.median(plain):.2f} µs per frame without, {statistics.median(python):.2f} with a "
              f"Python algorithm (medians of {runs} runs of {frames} frames)")


if __name__ == "__main__":
    main()
