"""The planar 2R arm of examples/planar-2r.yaml, built in Python instead of read from a file,
solved, and its Cartesian stiffness at the tool printed.

    .venv/bin/python examples/python/planar_2r_arm.py

The numbers are those of `build/stiffmsa solve examples/planar-2r.yaml` (tests/python checks
that the model equals the file's).
"""

import numpy as np

import stiffmsa


def gearbox(stiffness):
    """A joint free to turn about the vertical against a torsional spring (N·m/rad), rigid in
    the other five directions."""
    return stiffmsa.Connection(stiffmsa.Kinematics.revolute([0, 0, 1]), stiffness=stiffness)


def planar_2r_arm():
    aluminium = stiffmsa.Material(E=7.0e10, nu=0.33)
    model = stiffmsa.Model("planar-2r")
    # Shoulder angle 36.87 deg, elbow +90 deg: far from the stretched-out singularity.
    model.add_point("floor", [0, 0, -0.25])
    model.add_point("shoulder", [0, 0, 0])
    model.add_point("elbow", [0.48, 0.36, 0])
    model.add_point("tip", [0.21, 0.72, 0])
    model.add_rigid_link("pedestal", "floor", "shoulder")
    model.add_beam("upper_arm", "shoulder", "elbow", aluminium, stiffmsa.Section.rect_tube(b=0.06, h=0.08, t=0.004))
    model.add_beam("forearm", "elbow", "tip", aluminium, stiffmsa.Section.rect_tube(b=0.05, h=0.06, t=0.003))
    model.add_joint("shoulder_joint", "shoulder", ["pedestal", "upper_arm"], gearbox(2.0e5))
    model.add_joint("elbow_joint", "elbow", ["upper_arm", "forearm"], gearbox(1.0e5))
    model.add_support("base", "floor")  # rigid, every link end at the floor
    model.add_load("tip", [50, -200, 0, 0, 0, 0])  # N and N·m, global axes
    model.add_end_effector("tool", "tip")
    return model


def main():
    result = stiffmsa.solve(planar_2r_arm())
    tool = result.end_effectors["tool"]
    np.set_printoptions(precision=4, linewidth=110)
    print(f"{result.model}: end effector '{tool.name}' at point '{tool.point}' (solver {result.report.solver})")
    print("stiffness [N/m, N/rad; N·m/m, N·m/rad], rows Fx..Mz, columns dx..rz:")
    print(tool.stiffness)
    principal = stiffmsa.principal_stiffness(tool.compliance)
    print("principal stiffness against a force  [N/m]:    ", principal.translational)
    print("principal stiffness against a moment [N·m/rad]:", principal.rotational)
    print("deflection under the load [m, rad]:", tool.deflection)


if __name__ == "__main__":
    main()
