"""Seed 004, Diagram 7.2 through ``veselov.ensemble``: 25 random initial
positions of the coupled van der Pol oscillators (examples/van_der_pol.toml,
v0 = (0, 4)), Galerkin Lobatto s = 3 (order 2s - 2 = 4 for the forced
system, Thm 7.1), error at t = 1 against a run of Galerkin Gauss s = 5 at
h = 1/1600; mean, min and max over the ensemble for each h of the errors in
q and in p (apart, as the paper draws them) and in the energy, and the
fitted slope of each mean.

The paper's box "[-4,4]x[-4,4]" is read as (q1, q2) uniform in it (no seed
is given; this script uses seed 4). With matplotlib installed and an output
path given, the diagram is drawn.

    python crates/veselov-py/examples/forced_ensemble_diagram.py [diagram.png]
"""

import sys
from pathlib import Path

import numpy as np

import veselov

SCENARIO = Path(__file__).resolve().parents[3] / "examples" / "van_der_pol.toml"
T = 1.0
STEPS = [10, 20, 40, 80]
REFERENCE_STEPS = 1600

rng = np.random.default_rng(4)
starts = rng.uniform(-4.0, 4.0, size=(25, 2))


def member(q, steps, method):
    return {"initial.q": [float(q[0]), float(q[1])], "initial.v": [0.0, 4.0],
            "time.t_end": T, "method.dt": T / steps, "output.every": steps, "method": method}


def final(results):
    rows = []
    for r in results:
        assert r.status == "ok", r.message
        rows.append([r["q1"][-1], r["q2"][-1], r["p_q1"][-1], r["p_q2"][-1], r["energy"][-1]])
    return np.array(rows)


lobatto = {"name": "galerkin-lobatto", "stages": 3}
gauss = {"name": "galerkin-gauss", "stages": 5}
reference = final(veselov.ensemble(SCENARIO, [member(q, REFERENCE_STEPS, gauss) for q in starts]))
q_err, p_err, energy_err = [], [], []
for n in STEPS:
    x = final(veselov.ensemble(SCENARIO, [member(q, n, lobatto) for q in starts], progress=False))
    q_err.append(np.linalg.norm(x[:, :2] - reference[:, :2], axis=1))
    p_err.append(np.linalg.norm(x[:, 2:4] - reference[:, 2:4], axis=1))
    energy_err.append(np.abs(x[:, 4] - reference[:, 4]))

h = T / np.array(STEPS)
panels = (("|q - q_ref|", q_err), ("|p - p_ref|", p_err), ("|E - E_ref|", energy_err))
for name, errs in panels:
    mean = np.array([e.mean() for e in errs])
    slope = np.polyfit(np.log(h), np.log(mean), 1)[0]
    print(f"{name}: fitted order of the mean {slope:.2f} (expected 4)")
    for hk, e in zip(h, errs):
        print(f"  h = {hk:.4f}: mean {e.mean():.3e}, min {e.min():.3e}, max {e.max():.3e}")

if len(sys.argv) > 1:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for ax, (title, errs) in zip(axes, panels):
        ax.loglog(h, [e.mean() for e in errs], "-o", color="k")
        ax.loglog(h, [e.min() for e in errs], ":", color="k")
        ax.loglog(h, [e.max() for e in errs], ":", color="k")
        ax.set_xlabel("h")
        ax.set_title(title)
    fig.tight_layout()
    fig.savefig(sys.argv[1])
