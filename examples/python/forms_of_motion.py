#!/usr/bin/env python3
"""The paper's forms of motion of the triple pendulum (section 6.6) from Python: the
Poincare section (Abb. 6.8) and the spectral density of phi_3 (Abb. 6.9) for a weak
(regular) and a strong (chaotic) excitation, in one matplotlib figure.

Equal masses and lengths, both started at rest with the arms deflected in a zigzag
phi = (s, -s, s) to the energy E = epsilon m g l; epsilon = 0.01 and 1.5 as in the paper.

    PYTHONPATH=build/python python3 examples/python/forms_of_motion.py [--out FILE.png]
        [--section-time SECONDS]
"""

import argparse
import os
import tempfile

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import npend  # noqa: E402

SAMPLES, DT = 2**14, 1e-3  # the paper's series: 2^14 samples at dt = 0.001
OMEGA_MAX = 15.0  # rad/s: the three modes and a little beyond


def excitation(chain, epsilon):
    energy = npend.energy_from_epsilon(chain, epsilon)
    return npend.deflected_state(chain, energy, direction=[1.0, -1.0, 1.0])


def spectrum_of_phi3(chain, x0):
    _, states = npend.simulate(chain, x0, (SAMPLES - 1) * DT, dt=DT)
    return npend.spectrum(states[:, 2], DT, window="hann")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="forms_of_motion.png", help="the figure (PNG)")
    parser.add_argument("--section-time", type=float, default=600.0,
                        help="how long to integrate for the Poincare sections (s)")
    args = parser.parse_args()

    chain = npend.Chain(3)
    mode_frequencies = npend.modes(chain).frequencies
    figure, axes = plt.subplots(2, 2, figsize=(10, 8), constrained_layout=True)
    for column, (name, epsilon) in enumerate([("weak", 0.01), ("strong", 1.5)]):
        x0 = excitation(chain, epsilon)
        section = npend.poincare(chain, x0, "phi1=0", args.section_time)
        points = section.states
        top = axes[0, column]
        top.plot(points[:, 2], points[:, 5], ".", markersize=2)
        top.set(title=f"{name} excitation, $\\varepsilon$ = {epsilon}\n"
                      f"section $\\varphi_1 = 0$: {len(points)} points",
                xlabel="$\\varphi_3$ (rad)", ylabel="$p_3$ (kg m$^2$/s)")
        spectrum = spectrum_of_phi3(chain, x0)
        shown = spectrum.omega <= OMEGA_MAX
        power = spectrum.power[shown]
        bottom = axes[1, column]
        bottom.semilogy(spectrum.omega[shown], power)
        for omega in mode_frequencies:
            bottom.axvline(omega, color="grey", linestyle=":", linewidth=1)
        bottom.set(title="spectral density of $\\varphi_3$ (dotted: the normal modes)",
                   xlabel="$\\omega$ (rad/s)", ylabel="$\\rho(\\omega)$", xlim=(0, OMEGA_MAX),
                   ylim=(power.max() * 1e-8, power.max() * 10))
    # Written next to its destination and renamed, so no half-written figure is left behind.
    folder = os.path.dirname(os.path.abspath(args.out))
    with tempfile.NamedTemporaryFile(dir=folder, suffix=".png", delete=False) as partial:
        figure.savefig(partial.name, dpi=100)
    os.replace(partial.name, args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
