"""Accuracy and stability studies (loaded on demand; ``import lighting`` does not load them)."""

from __future__ import annotations

__all__ = []
