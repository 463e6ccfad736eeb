#!/usr/bin/env python3
"""Re-rendering from Python after a parameter change, against rendering the loaded scene again.

Issue 29's goal: after a material or light change (traverse, assign, update()), a render costs at
most 5% more than a render of the already-loaded, unchanged scene. Both are timed alternately in
one run (median of ROUNDS each), whole calls from Python, on the validation Cornell box.

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py [--res 128] [--spp 16] [--rounds 9]
"""

import argparse
import os
import statistics
import sys
import time

import candela

here = os.path.dirname(os.path.abspath(__file__))
scene_path = os.path.join(here, "..", "scenes", "validation", "cbox.xml")

parser = argparse.ArgumentParser()
parser.add_argument("--res", type=int, default=128)
parser.add_argument("--spp", type=int, default=16)
parser.add_argument("--rounds", type=int, default=9)
args = parser.parse_args()

scene = candela.load_file(scene_path, res=args.res, spp=args.spp)
params = candela.traverse(scene)
colour_key = next(k for k in params.keys() if k.endswith("reflectance.value"))
light_key = next(k for k in params.keys() if k.endswith("emitter.radiance.value"))
base_colour, base_light = params[colour_key], params[light_key]

candela.render(scene, seed=0)  # warm-up: threads, caches
plain, changed, updates = [], [], []
for i in range(args.rounds):
    t0 = time.perf_counter()
    candela.render(scene, seed=i)
    plain.append(time.perf_counter() - t0)

    t0 = time.perf_counter()
    params[colour_key] = base_colour * (0.5 + 0.05 * i)
    params[light_key] = base_light * (0.9 + 0.02 * i)
    params.update()
    t1 = time.perf_counter()
    candela.render(scene, seed=i)
    changed.append(time.perf_counter() - t0)
    updates.append(t1 - t0)

p, c = statistics.median(plain), statistics.median(changed)
print(f"scene {os.path.relpath(scene_path)} {args.res}x{args.res}, {args.spp} spp, {args.rounds} rounds, changing {colour_key} and {light_key}")
print(f"render of the loaded scene:           median {p * 1e3:8.1f} ms")
print(f"update() + render after the change:   median {c * 1e3:8.1f} ms (update alone {statistics.median(updates) * 1e3:.2f} ms)")
print(f"ratio changed / unchanged: {c / p:.3f} (goal <= 1.05)")
sys.exit(0)
