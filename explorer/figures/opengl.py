"""OpenGL's light positions (w = 0: a direction, w = 1: a point) and the spot light's parameters.
"""

from __future__ import annotations
