"""Geometry the tests share."""

import numpy as np


def quaternions_onto(d):
    """Unit quaternions (w, x, y, z) rotating the x axis onto each row of d."""
    x = np.array([1.0, 0.0, 0.0])
    axis = np.cross(x, d)
    s = np.linalg.norm(axis, axis=1)
    angle = np.arctan2(s, d @ x)
    axis /= np.where(s > 0, s, 1.0)[:, None]
    return np.column_stack([np.cos(angle / 2), axis * np.sin(angle / 2)[:, None]])
