"""Shared by the URDF checkers tests/scripts/urdf_fk.py (yourdfpy) and tests/scripts/urdf_mujoco.py (MuJoCo):
their command line, the SRDF joint values and the rotation error."""
import argparse
import json
import math
import xml.etree.ElementTree as ET

import numpy as np


def arguments(doc):
    """ROBOT.urdf EXPECTED.json [--srdf ROBOT.srdf --state NAME] [--tol 1e-9]."""
    ap = argparse.ArgumentParser(description=doc)
    ap.add_argument("urdf")
    ap.add_argument("expected")
    ap.add_argument("--srdf")
    ap.add_argument("--state")
    ap.add_argument("--tol", type=float, default=1e-9)
    return ap.parse_args()


def joint_values(args):
    """The SRDF group_state `args.state` as {joint: value}; {} without an SRDF (fixed mode)."""
    if not args.srdf:
        return {}
    root = ET.parse(args.srdf).getroot()
    for gs in root.findall("group_state"):
        if gs.get("name") == args.state:
            return {j.get("name"): float(j.get("value")) for j in gs.findall("joint")}
    raise SystemExit(f"no group_state named {args.state!r} in {args.srdf}")


def expected_disks(args):
    """The list of {"link", "position" [m], "rotation" (row-major 3x3)} to compare against."""
    with open(args.expected) as f:
        return json.load(f)


def rotation_angle(a, b):
    """Angle between rotations a and b: |A - B|_F = 2 sqrt(2) sin(theta / 2), accurate for
    small angles."""
    s = np.linalg.norm(a - b) / (2.0 * math.sqrt(2.0))
    return 2.0 * math.asin(min(1.0, s))
