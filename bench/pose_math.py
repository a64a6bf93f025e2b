"""Poses as 4x4 matrices for the benchmark scripts: from a translation and a quaternion (x y z w), a turn
about an axis, a chain of revolute joints, and the distance between two poses in mm / mrad."""
import math

import numpy as np


def matrix(translation, quaternion):
    x, y, z, w = np.asarray(quaternion, dtype=float) / np.linalg.norm(quaternion)
    m = np.eye(4)
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m[:3, 3] = translation
    return m


def turn(axis, angle):
    """A rotation by `angle` radians about `axis` (Rodrigues)."""
    axis = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    m = np.eye(4)
    m[:3, :3] = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    return m


def chain_pose(joints, angles):
    """base <- the last joint's child through revolute `joints` (rig.yaml's, in order) at `angles`."""
    pose = np.eye(4)
    for joint, angle in zip(joints, angles):
        origin = joint["origin"]
        pose = pose @ matrix(origin[:3], origin[3:]) @ turn(joint["axis"], angle)
    return pose


def error(found, truth):
    """(mm, mrad) between two 4x4 poses."""
    d = np.linalg.inv(truth) @ found
    angle = math.acos(max(-1.0, min(1.0, (np.trace(d[:3, :3]) - 1) / 2)))
    return 1000 * np.linalg.norm(found[:3, 3] - truth[:3, 3]), 1000 * angle
