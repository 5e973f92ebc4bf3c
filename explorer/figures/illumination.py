"""The slides' concepts before any model: local vs global illumination, one point lit from several directions,
the BRDF as L_i → L_o, diffuse / glossy / specular, the micro-roughness of chalk, glossy reflectance around the
mirror direction, retro-reflection as the third part of a decomposed BRDF.
"""

from __future__ import annotations
