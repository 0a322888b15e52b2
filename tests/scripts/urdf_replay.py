#!/usr/bin/env python3
"""Replay waypoints on one exported ccrkit URDF with a URDF client and compare every disk.

usage: urdf_replay.py ROBOT.urdf WAYPOINTS.json --tool TOOL [--tol 1e-9]

TOOL: yourdfpy, mujoco, pybullet (the chain pybullet parsed, composed in double precision) or
pybullet-engine (pybullet's own getLinkState, reported in single precision by this build).

WAYPOINTS.json is a list of {"joints": {name: value}, "disks": [{"link", "position" [m],
"rotation" (row-major 3x3)}]}: the articulated export's joint values at each waypoint (the
port's prismatic `port_insertion` and revolute `port_rotation` first) and the solved disk
frames in the frame of base_link. Each waypoint's joint values are set on the one URDF, the
client's forward kinematics gives every disk link's pose relative to base_link, and the largest
position and rotation errors over all waypoints are printed; exits 1 when either exceeds the
tolerance, 2 on bad input (a joint missing on either side).
"""
import argparse
import json
import math
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

import numpy as np

from urdf_common import rotation_angle


def yourdfpy_poses(urdf):
    import yourdfpy

    robot = yourdfpy.URDF.load(
        urdf, build_scene_graph=True, load_meshes=False, build_collision_scene_graph=False
    )
    names = set(robot.actuated_joint_names)

    def fk(cfg, links):
        robot.update_cfg(cfg)
        out = {}
        for link in links:
            t = robot.get_transform(frame_to=link, frame_from="base_link")
            out[link] = (t[:3, 3], t[:3, :3])
        return out

    return names, fk, f"yourdfpy {getattr(yourdfpy, '__version__', '')}".strip()


def pybullet_poses(urdf, parsed):
    """pybullet's forward kinematics (`parsed` False: getLinkState, which this pybullet
    reports in single precision), or (`parsed` True) the chain pybullet parsed from the URDF
    (getJointInfo's joint frames, types and axes, getDynamicsInfo's inertial frames, all in
    double precision) composed here in double precision."""
    import pybullet as p

    client = p.connect(p.DIRECT)
    body = p.loadURDF(urdf, useFixedBase=True, physicsClientId=client)
    joints, links, info = {}, {}, []
    for j in range(p.getNumJoints(body, physicsClientId=client)):
        ji = p.getJointInfo(body, j, physicsClientId=client)
        info.append(ji)
        links[ji[12].decode()] = j
        if ji[2] != p.JOINT_FIXED:
            joints[ji[1].decode()] = j

    def frame(pos, orn):
        # The rotation of a unit quaternion (x, y, z, w), in double precision here (pybullet's
        # own getMatrixFromQuaternion may round).
        x, y, z, w = np.asarray(orn, dtype=float) / np.linalg.norm(orn)
        t = np.eye(4)
        t[:3, :3] = [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
        t[:3, 3] = pos
        return t

    def inertial(j):
        d = p.getDynamicsInfo(body, j, physicsClientId=client)
        return frame(d[3], d[4])

    # base_link's frame in the world: pybullet reports the base by its centre of mass.
    base = frame(*p.getBasePositionAndOrientation(body, physicsClientId=client)) @ np.linalg.inv(
        inertial(-1)
    )

    def motion(ji, q):
        axis = np.array(ji[13], dtype=float)
        t = np.eye(4)
        if ji[2] == p.JOINT_PRISMATIC:
            t[:3, 3] = axis * q
        elif ji[2] == p.JOINT_REVOLUTE:
            c, s_, k = math.cos(q), math.sin(q), axis / np.linalg.norm(axis)
            kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            t[:3, :3] = np.eye(3) + s_ * kx + (1 - c) * kx @ kx
        return t

    def fk_engine(cfg, wanted):
        for name, j in joints.items():
            p.resetJointState(body, j, cfg[name], physicsClientId=client)
        out = {}
        for link in wanted:
            s_ = p.getLinkState(body, links[link], computeForwardKinematics=True, physicsClientId=client)
            t = np.linalg.inv(base) @ frame(s_[4], s_[5])
            out[link] = (t[:3, 3], t[:3, :3])
        return out

    def fk_parsed(cfg, wanted):
        # Link frames relative to base_link, parents first (pybullet numbers links so).
        t_link = {-1: np.eye(4)}
        for j, ji in enumerate(info):
            q = cfg[ji[1].decode()] if ji[2] != p.JOINT_FIXED else 0.0
            parent = ji[16]
            # getJointInfo reports the joint frame's orientation inverted (its parent frame seen
            # from the joint): the frame is (position, inverse of that quaternion).
            x, y, z, w = ji[15]
            orn = (-x, -y, -z, w)
            t_link[j] = t_link[parent] @ inertial(parent) @ frame(ji[14], orn) @ motion(ji, q)
        return {link: (t_link[links[link]][:3, 3], t_link[links[link]][:3, :3]) for link in wanted}

    fk = fk_parsed if parsed else fk_engine
    what = "parsed chain" if parsed else "getLinkState"
    return set(joints), fk, f"pybullet {p.getAPIVersion()} ({what})"


def mujoco_poses(urdf):
    import mujoco

    # Every link a body (MuJoCo fuses links joined by fixed joints by default).
    tree = ET.parse(urdf)
    ext = ET.SubElement(tree.getroot(), "mujoco")
    ET.SubElement(ext, "compiler", {"fusestatic": "false", "discardvisual": "false"})
    fd, path = tempfile.mkstemp(suffix=".urdf", dir=os.path.dirname(os.path.abspath(urdf)))
    os.close(fd)
    tree.write(path)
    try:
        model = mujoco.MjModel.from_xml_path(path)
    finally:
        os.remove(path)
    data = mujoco.MjData(model)
    names = {model.joint(j).name for j in range(model.njnt)}

    def fk(cfg, links):
        for j in range(model.njnt):
            data.qpos[model.jnt_qposadr[j]] = cfg[model.joint(j).name]
        mujoco.mj_kinematics(model, data)
        base = model.body("base_link").id
        rb, pb = data.xmat[base].reshape(3, 3), data.xpos[base]
        out = {}
        for link in links:
            b = model.body(link).id
            out[link] = (rb.T @ (data.xpos[b] - pb), rb.T @ data.xmat[b].reshape(3, 3))
        return out

    return names, fk, f"MuJoCo {mujoco.__version__}"


TOOLS = {
    "yourdfpy": yourdfpy_poses,
    "pybullet": lambda urdf: pybullet_poses(urdf, parsed=True),
    "pybullet-engine": lambda urdf: pybullet_poses(urdf, parsed=False),
    "mujoco": mujoco_poses,
}


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("urdf")
    ap.add_argument("waypoints")
    ap.add_argument("--tool", choices=sorted(TOOLS), required=True)
    ap.add_argument("--tol", type=float, default=1e-9)
    args = ap.parse_args()
    with open(args.waypoints) as f:
        waypoints = json.load(f)
    names, fk, label = TOOLS[args.tool](args.urdf)
    max_p = max_r = 0.0
    for k, w in enumerate(waypoints):
        if set(w["joints"]) != names:
            print(
                f"waypoint {k}: joints differ: {label} only {sorted(names - set(w['joints']))}, "
                f"waypoint only {sorted(set(w['joints']) - names)}"
            )
            return 2
        poses = fk(w["joints"], [d["link"] for d in w["disks"]])
        for d in w["disks"]:
            pos, rot = poses[d["link"]]
            max_p = max(max_p, float(np.linalg.norm(pos - np.array(d["position"]))))
            max_r = max(max_r, rotation_angle(rot, np.array(d["rotation"])))
    ok = max_p <= args.tol and max_r <= args.tol
    print(
        f"{label} replays {len(waypoints)} waypoints ({len(names)} joints): position {max_p:.2e} m, "
        f"rotation {max_r:.2e} rad ({'ok' if ok else 'FAIL'}, tol {args.tol:g})"
    )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
