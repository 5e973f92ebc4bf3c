import sys
from pathlib import Path

import pytest

# Let tests import the sibling helper modules `quadrature` and `probes`.
sys.path.insert(0, str(Path(__file__).parent))

#: Test files marked ``slow`` as a whole: the seeded probes, the figure set, the Mesa comparison and the
#: off-screen explorer window.  ``python -m pytest -m "not slow"`` is the fast loop (under a minute here);
#: CI and the README's command run everything.
SLOW_FILES = frozenset(
    {
        "test_app.py",
        "test_figures.py",
        "test_gl_mesa.py",
        "test_probe_cli.py",
        "test_probe_explorer.py",
        "test_probe_integrate.py",
        "test_probe_models.py",
        "test_probe_scenes.py",
        "test_probe_shading.py",
        # The models beyond the slides: 80-digit references, albedo quadratures and χ² at grazing views
        # (tests/models/test_contract.py covers each of them in the fast loop).
        "test_oren_nayar.py",
        "test_ward.py",
        "test_ashikhmin_shirley.py",
        "test_disney.py",
        "test_microfacet_smith.py",
        # NDF normalization and projected area by quadrature for every NDF (about 30 s); the stability
        # sweep's 80-digit references of the new models (about 10 s).
        "test_ndf_laws.py",
        "test_model_references.py",
        # Anisotropic quadrature against 250 000-node references, every microfacet form (about 60 s).
        "test_quadrature_aniso_full.py",
        # Every sampler's χ² at 0°, 60°, 85° and 89° (about 4 min); test_sampler_grazing.py is the fast subset.
        "test_sampler_grazing_full.py",
        # The stability sweep's quick run covers 205 model variants against 80-digit references (about 25 s).
        "test_stability.py",
        # Fits three models to a tabulated MERL table (about 4 s).
        "test_figure_fitting.py",
        # The MERL table sampler's χ², variance and mass checks (about 15 s).
        "test_merl_sampler.py",
    }
)


def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.path.name in SLOW_FILES:
            item.add_marker(pytest.mark.slow)


@pytest.fixture(autouse=True, scope="session")
def _accuracy_cache_in_a_temporary_folder(tmp_path_factory):
    """The saved accuracy studies (explorer.reports.cache) go to a folder of this session, never the home folder."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("LIGHTING_EXPLORER_CACHE", str(tmp_path_factory.mktemp("lighting-explorer-cache")))
        yield


@pytest.fixture(autouse=True)
def _model_registry_restored():
    """Each test leaves the model registry as it found it.

    Tests register models (plug-ins, ``--brdf`` files, ``define_brdf``); one left behind would appear in
    every model list afterwards, e.g. in the registry-generated figure galleries of later tests.
    """
    from lighting.models import protocol

    before = dict(protocol._REGISTRY)
    yield
    if protocol._REGISTRY != before:
        protocol._REGISTRY.clear()
        protocol._REGISTRY.update(before)
