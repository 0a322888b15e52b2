#!/usr/bin/env python3
"""Forward kinematics of an exported ccrkit URDF with yourdfpy, compared with ccrkit's own.

usage: urdf_fk.py ROBOT.urdf EXPECTED.json [--srdf ROBOT.srdf --state NAME] [--tol 1e-9]

EXPECTED.json is a list of {"link", "position" [m], "rotation" (row-major 3x3)} in the frame of
base_link. The joint values are the SRDF group_state NAME (none: all joints fixed). Prints the
largest position and rotation errors; exits 1 when either exceeds the tolerance, 2 on bad input.
"""
import sys

import numpy as np
import yourdfpy

from urdf_common import arguments, expected_disks, joint_values, rotation_angle


def main():
    args = arguments(__doc__)

    robot = yourdfpy.URDF.load(
        args.urdf, build_scene_graph=True, load_meshes=False, build_collision_scene_graph=False
    )
    cfg = joint_values(args)
    unknown = set(cfg) - set(robot.actuated_joint_names)
    if unknown:
        print(f"joints in the SRDF but not actuated in the URDF: {sorted(unknown)}")
        return 2
    missing = set(robot.actuated_joint_names) - set(cfg)
    if missing:
        print(f"actuated joints without a value in the SRDF: {sorted(missing)}")
        return 2
    robot.update_cfg(cfg)

    expected = expected_disks(args)
    max_p = max_r = 0.0
    for e in expected:
        t = robot.get_transform(frame_to=e["link"], frame_from="base_link")
        max_p = max(max_p, float(np.linalg.norm(t[:3, 3] - np.array(e["position"]))))
        max_r = max(max_r, rotation_angle(t[:3, :3], np.array(e["rotation"])))
    ok = max_p <= args.tol and max_r <= args.tol
    print(
        f"yourdfpy vs ccrkit FK over {len(expected)} disks, {len(cfg)} joints: "
        f"position {max_p:.2e} m, rotation {max_r:.2e} rad ({'ok' if ok else 'FAIL'}, tol {args.tol:g})"
    )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
