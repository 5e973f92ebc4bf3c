"""The model gallery: every registered model on the same lit sphere, in the same polar slice, with its albedo curve.
"""

from __future__ import annotations
