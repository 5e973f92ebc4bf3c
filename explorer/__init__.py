"""explorer — the front end of lighting-explorer (CLI, figures, desktop app).

Heavy libraries (Matplotlib, PyVista/VTK, trimesh) are imported only by the
features that use them.
"""
