"""Plan the paper's line to arrive at rest, run it through the FE transient, plot the tip.

    python3 docs/example_python.py [FIGURE.png]      (from the repository's root)
"""
import sys

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt

import elasticarm as ea

plan = ea.plan("problems/examples/paper-line-rest.yaml")  # reduced modal model, 2 modes
tr = plan.trajectory  # numpy columns, units in the names
print(f"{plan.task.name}: {plan.duration_s:.4f} s, {len(tr)} knots, "
      f"{plan.info.iterations} iterations")

sim = ea.simulate(plan)  # nonlinear FE transient, 3 s of settling after the motion
print(f"FE residual vibration: peak {1e3 * sim.residual_peak_m:.3f} mm, "
      f"rms {1e3 * sim.residual_rms_m:.3f} mm")

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
ax1.plot(sim.tip_x_m, sim.tip_y_m, label="FE tip")
ax1.plot(tr.tip_x_m, tr.tip_z_m, "--", label="planned (quasi-static)")
ax1.set(xlabel="tip x [m]", ylabel="tip y [m]", title="tip path")
ax1.legend()
ax2.plot(sim.t_s, 1e3 * (sim.tip_y_m - sim.planned_tip_y_m))
ax2.axvline(tr.t_s[-1], color="gray", lw=0.8)  # the end of the motion
ax2.set(xlabel="t [s]", ylabel="tip y - planned [mm]", title="deviation from the plan")
fig.tight_layout()
out = sys.argv[1] if len(sys.argv) > 1 else "tip.png"
fig.savefig(out, dpi=100)
print("wrote", out)
