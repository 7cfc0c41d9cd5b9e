"""The tiny centre crack from Python: one FE run, its crack-tip history, and a sweep of the
friction coefficient over three values.

    pip install ./python matplotlib
    python examples/center_crack.py [--out DIR]

Prints, for each friction coefficient, when the right tip first moved and where it ended, and
writes tip_history.png and friction_sweep.png into DIR (default out/examples).
"""

import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt
import numpy as np

import cohesive_contact as cc

REPO = pathlib.Path(__file__).resolve().parents[1]
SCENE = REPO / "scenes" / "tiny-fem-center-crack.toml"


def first_motion(tips, a):
    """Time [s] at which the right tip first left the pre-crack's end a [m] (NaN if never)."""
    moved = np.nonzero(tips["tip_right"] > a * (1 + 1e-9))[0]
    return tips["t"][moved[0]] if len(moved) else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=REPO / "out" / "examples")
    out = parser.parse_args().out
    out.mkdir(parents=True, exist_ok=True)

    scene = cc.Scene.from_file(SCENE)
    a = scene.crack.half_length  # m

    # one run, as `fem scenes/tiny-fem-center-crack.toml` runs it
    result = cc.fem.run(scene)
    print(result)
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(result.tips["t"] * 1e3, result.tips["tip_right"] * 1e3, label="right tip")
    ax.plot(result.tips["t"] * 1e3, -result.tips["tip_left"] * 1e3, "--", label="left tip (mirrored)")
    ax.set(xlabel="t [ms]", ylabel="tip position [mm]", title=f"μ = {scene.friction.friction_coeff}")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "tip_history.png", dpi=120)

    # the friction coefficient over three values
    fig, ax = plt.subplots(figsize=(5, 3.5))
    print(f"{'mu':>5} {'first motion [ms]':>18} {'final tip [mm]':>15}")
    for mu in (0.0, 0.3, 0.6):
        s = scene.copy()
        s.friction.friction_coeff = mu
        tips = cc.fem.run(s, progress=False).tips
        print(f"{mu:>5} {first_motion(tips, a) * 1e3:>18.4f} {tips['tip_right'][-1] * 1e3:>15.3f}")
        ax.plot(tips["t"] * 1e3, tips["tip_right"] * 1e3, label=f"μ = {mu}")
    ax.set(xlabel="t [ms]", ylabel="right tip [mm]", title="friction delays the crack")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "friction_sweep.png", dpi=120)
    print(f"wrote {out / 'tip_history.png'} and {out / 'friction_sweep.png'}")


if __name__ == "__main__":
    main()
