"""Energy compensation (Kulla–Conty 2017): the white furnace before and after, for rough microfacet models.
"""

from __future__ import annotations
