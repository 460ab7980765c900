"""Example: a virtual system of your own, an isolated two-storey frame (docs/virtual.md).

The vessel of the report (3600 lbf) stands on the roof of a base-isolated
two-storey frame.  The script prints the modes, compares the roof
acceleration the table would have to imitate with the basemat acceleration
of the report's LR1 isolator under the built-in El Centro record, and
optionally writes isolator force against the displacement under the article
(for the frame: roof displacement).

Run:  .venv/bin/python examples/virtual_two_storey.py [loops.png]
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from impedance_mil.report.vs_plots import plot_loops, save_figure
from impedance_mil.signals import builtin_motion
from impedance_mil.units import G0, in_s2_to_g
from impedance_mil.virtual import TEST_ARTICLE_WEIGHT, presets
from impedance_mil.virtual.excitation import rigid_article_response

# The frame is a user-defined VS type, defined in its own file (examples/vs_types/two_storey.py).
sys.path.insert(0, str(Path(__file__).resolve().parent / "vs_types"))
from two_storey import example_two_storey, modes  # noqa: E402


def main(figure: str | None = None) -> None:
    frame = example_two_storey(isolation_period=2.0, isolation_damping=0.15, storey_frequency=5.0)
    print("Isolated two-storey frame (article on the roof):")
    for k, (f, zeta) in enumerate(modes(frame), start=1):
        print(f"  mode {k}: {f:6.2f} Hz, damping {zeta:5.1%}")
    lp = frame.linear_part()
    print(f"  H_zw is order {lp.H_zw.order}, H_zag order {lp.H_zag.order}; no nonlinear input")

    motion = builtin_motion("elcentro")
    substeps = int(np.ceil(motion.time_step / 0.0005))
    dt = motion.time_step / substeps
    a_g = np.repeat(motion.accel, substeps)  # held over each record sample, like the lab loop
    m_article = TEST_ARTICLE_WEIGHT / G0

    results = {
        "ISO2 roof": rigid_article_response(frame, a_g, dt, m_article),
        "LR1 basemat": rigid_article_response(presets.get("LR1"), a_g, dt, m_article),
    }
    print(f"\n{motion.name}: PGA {motion.pga_g:.3f} g, dt {dt * 1e3:.3g} ms")
    for name, r in results.items():
        print(
            f"  {name:12s} peak z_vs {in_s2_to_g(np.abs(r.z_vs).max()):.3f} g, "
            f"peak displacement under the article {np.abs(r.displacement).max():.2f} in, "
            f"peak isolator force {np.abs(r.force).max():.0f} lbf"
        )
    if figure:
        fig = plot_loops(list(results.values()), list(results), title=motion.name)
        print(f"wrote {save_figure(fig, figure)}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
