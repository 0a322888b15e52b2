#!/usr/bin/env python3
"""Load an exported ccrkit URDF in MuJoCo and compare its forward kinematics with the solved disks.

usage: urdf_mujoco.py ROBOT.urdf EXPECTED.json [--srdf ROBOT.srdf --state NAME] [--tol 1e-9]

EXPECTED.json is a list of {"link", "position" [m], "rotation" (row-major 3x3)} in the frame of
base_link (the solved disk frames). First the URDF is loaded exactly as written (MuJoCo's own
checks: masses and inertias of moving bodies, unique names). Then, to keep every link as a
body (MuJoCo fuses links joined by fixed joints by default), a copy with
`<mujoco><compiler fusestatic="false"/></mujoco>` is loaded, qpos is set to the SRDF group_state
NAME (none: fixed mode, no joints) and mj_kinematics gives each disk body's pose.
Prints the largest position and rotation errors; exits 1 when either exceeds the tolerance,
2 on bad input.
"""
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

import mujoco
import numpy as np

from urdf_common import arguments, expected_disks, joint_values, rotation_angle


def unfused_copy(urdf_path):
    tree = ET.parse(urdf_path)
    root = tree.getroot()
    ext = ET.SubElement(root, "mujoco")
    ET.SubElement(ext, "compiler", {"fusestatic": "false", "discardvisual": "false"})
    fd, path = tempfile.mkstemp(suffix=".urdf", dir=os.path.dirname(os.path.abspath(urdf_path)))
    os.close(fd)
    tree.write(path)
    return path


def main():
    args = arguments(__doc__)

    # 1. The file as exported loads (raises on zero-mass moving bodies, repeated names).
    mujoco.MjModel.from_xml_path(args.urdf)
    # 2. Every link a body, for the kinematics.
    copy = unfused_copy(args.urdf)
    try:
        model = mujoco.MjModel.from_xml_path(copy)
    finally:
        os.remove(copy)
    data = mujoco.MjData(model)
    cfg = joint_values(args)
    names = [model.joint(j).name for j in range(model.njnt)]
    if set(names) != set(cfg):
        print(f"joints differ: MuJoCo {sorted(set(names) - set(cfg))}, SRDF {sorted(set(cfg) - set(names))}")
        return 2
    for j in range(model.njnt):
        data.qpos[model.jnt_qposadr[j]] = cfg[model.joint(j).name]
    mujoco.mj_kinematics(model, data)

    expected = expected_disks(args)
    base = model.body("base_link").id
    rb = data.xmat[base].reshape(3, 3)
    pb = data.xpos[base]
    max_p = max_r = 0.0
    total_mass = float(np.sum(model.body_mass))
    for e in expected:
        b = model.body(e["link"]).id
        # Pose relative to base_link (MuJoCo's world may hold the root elsewhere).
        p = rb.T @ (data.xpos[b] - pb)
        r = rb.T @ data.xmat[b].reshape(3, 3)
        max_p = max(max_p, float(np.linalg.norm(p - np.array(e["position"]))))
        max_r = max(max_r, rotation_angle(r, np.array(e["rotation"])))
    ok = max_p <= args.tol and max_r <= args.tol
    print(
        f"MuJoCo {mujoco.__version__} vs ccrkit over {len(expected)} disks, {model.njnt} joints, "
        f"{model.nbody} bodies, mass {total_mass:.6g} kg: position {max_p:.2e} m, "
        f"rotation {max_r:.2e} rad ({'ok' if ok else 'FAIL'}, tol {args.tol:g})"
    )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
