"""What the scripts that run Mitsuba 3 as a peer share (efficiency.py, meters.py, sunsky.py)."""
import argparse, os

import numpy as np

NOT_FOUND = "bench/peers/README.md says how to unpack the peer build"


def peer_environment(mitsuba):
    """The environment to run the peer binary `mitsuba` in: its folder, where the build keeps its
    libraries, first on LD_LIBRARY_PATH. None when there is no executable at that path."""
    if not (os.path.isfile(mitsuba) and os.access(mitsuba, os.X_OK)):
        return None
    env = dict(os.environ)
    folder = os.path.dirname(os.path.abspath(mitsuba))
    env["LD_LIBRARY_PATH"] = folder + (":" + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else "")
    return env


def peer_command_line(spp, seeds, add_arguments=None):
    """The command line of a script comparing Candela with the peer (--candela, --mitsuba, --spp,
    --seeds, and what add_arguments(parser) adds), and the peer's environment; None for it, with
    a note printed, when the peer is not there."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--candela", default="build/candela")
    ap.add_argument("--mitsuba", default="/tmp/mitsuba3/mitsuba")
    ap.add_argument("--spp", type=int, default=spp)
    ap.add_argument("--seeds", type=int, default=seeds)
    if add_arguments:
        add_arguments(ap)
    a = ap.parse_args()
    env = peer_environment(a.mitsuba)
    if env is None:
        print(f"note: Mitsuba 3 not found at {a.mitsuba} ({NOT_FOUND})")
    return a, env


def print_seed_means(label, candela, mitsuba, width=16, number="{:.5f}+-{:.5f}"):
    """Each renderer's mean over independent seeds (arrays: one row per seed, one column per
    channel) with its standard error from the spread over the seeds, and the difference in units
    of the combined error (z), on two lines headed by `label`."""
    stats = []
    for values in (np.asarray(candela), np.asarray(mitsuba)):
        stats.append((values.mean(0), values.std(0, ddof=1) / np.sqrt(len(values))))
    (mc, ec), (mm, em) = stats
    z = (mc - mm) / np.sqrt(ec ** 2 + em ** 2)
    fmt = lambda m, e: " ".join(number.format(x, y) for x, y in zip(m, e))
    print(f"{label:{width}s} candela {fmt(mc, ec)}")
    print(f"{'':{width}s} mitsuba {fmt(mm, em)}   z {' '.join(f'{x:+.2f}' for x in z)}")
