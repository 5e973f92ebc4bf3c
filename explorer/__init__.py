"""explorer — the front end of lighting-explorer.

``cli`` (the ``lighting-explorer`` command: one argparse tree), ``commands/`` (one module per
sub-command: ``add_parser``, ``run``, ``main``), ``app/`` (the explorer window), ``figures/`` (the
lecture-note figures: the registry, then one module per lecture topic), ``reports/`` (the accuracy
and stability reports), ``bench`` (the engine against VTK), ``output`` (image files written
atomically, signals), ``progress`` (a progress bar).

Heavy libraries (Matplotlib, PyVista/VTK, trimesh) are imported only by the
features that use them.
"""
