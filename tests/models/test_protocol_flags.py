"""What a model tells the rest of the engine: its flags, its microfacet description, its separable forms."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lighting.models import BRDF, BRDFFlags, MicrofacetLobe, create_model
from lighting.models.ashikhmin_shirley import AshikhminShirley
from lighting.models.brdf import BlinnPhong, CookTorrance, Lambert, Phong
from lighting.models.disney import Disney
from lighting.models.geometry import Geometry
from lighting.models.mirror import Mirror
from lighting.models.oren_nayar import OrenNayar
from lighting.models.ward import Ward
from lighting.shading.separable import is_separable, stacks, terms

F = BRDFFlags


@pytest.mark.parametrize("model, flags", [
    (Lambert(), F.DIFFUSE | F.LAMBERTIAN),
    (OrenNayar(), F.DIFFUSE),
    (Phong(), F.SPECULAR),
    (BlinnPhong(), F.SPECULAR),
    (CookTorrance(), F.SPECULAR),
    (CookTorrance(alpha_x=0.1, alpha_y=0.3, ndf="ggx"), F.SPECULAR | F.ANISOTROPIC),
    (Ward(1.0, 0.2), F.SPECULAR),
    (Ward(1.0, 0.2, 0.05), F.SPECULAR | F.ANISOTROPIC),
    (AshikhminShirley(), F.SPECULAR | F.OWN_DIFFUSE | F.ANISOTROPIC),
    (AshikhminShirley(nu=50, nv=50), F.SPECULAR | F.OWN_DIFFUSE),
    (Disney(), F.SPECULAR | F.OWN_DIFFUSE),
    (Disney(anisotropic=0.5), F.SPECULAR | F.OWN_DIFFUSE | F.ANISOTROPIC),
    (Mirror(), F.SPECULAR | F.DELTA),
])  # fmt: skip
def test_each_model_says_what_it_is(model, flags):
    assert model.flags == flags
    assert model.term == ("diffuse" if F.DIFFUSE in flags else "specular")
    assert (model.lambertian, model.own_diffuse, model.is_delta) == (F.LAMBERTIAN in flags, F.OWN_DIFFUSE in flags,
                                                                    F.DELTA in flags)  # fmt: skip


def test_the_old_names_are_read_only_views_of_the_flags():
    assert Lambert.term == "diffuse" and Lambert.lambertian and not Lambert.is_delta
    assert Mirror.is_delta and Mirror.term == "specular" and not Phong.own_diffuse
    m = Lambert()
    for name in ("term", "lambertian", "own_diffuse", "is_delta"):
        with pytest.raises(AttributeError, match=f"{name} is read from flags"):
            setattr(m, name, True)
    assert m.flags == F.DIFFUSE | F.LAMBERTIAN


def test_a_class_written_with_the_old_attributes_gets_its_flags():
    class Old(BRDF):
        term = "diffuse"
        is_delta = True
        own_diffuse = False

        def _f(self, g):
            return np.zeros(np.shape(g.n))

    class Older(Old):
        lambertian = True

    assert Old.flags == F.DIFFUSE | F.DELTA and Old().term == "diffuse" and Old.is_delta
    assert Older.flags == F.DIFFUSE | F.DELTA | F.LAMBERTIAN and Older().lambertian
    assert "term" not in Old.__dict__ and "lambertian" not in Older.__dict__


def test_a_microfacet_model_describes_its_lobe():
    ct = CookTorrance(0.7, 0.25, 0.5, ndf="ggx", geometry="smith", fresnel="none")
    lobe = ct.microfacet()
    assert isinstance(lobe, MicrofacetLobe) and lobe.isotropic
    assert (lobe.ndf, lobe.alpha_x, lobe.alpha_y, lobe.geometry, lobe.fresnel, lobe.denominator,
            lobe.energy_compensation) == ("ggx", 0.25, 0.25, "smith", "none", "4", False)  # fmt: skip
    assert lobe.specular.tolist() == [0.7, 0.7, 0.7]
    an = CookTorrance(ks=(0.9, 0.5, 0.1), alpha_x=0.1, alpha_y=0.4, ndf="beckmann", denominator="pi").microfacet()
    assert (an.alpha_x, an.alpha_y, an.isotropic, an.denominator) == (0.1, 0.4, False, "pi")
    assert an.specular.tolist() == [0.9, 0.5, 0.1]
    # Both widths given and equal: the lobe is round with that width, whatever the roughness says.
    assert CookTorrance(roughness=0.5, alpha_x=0.2, alpha_y=0.2).microfacet().alpha_x == 0.2
    assert CookTorrance(energy_compensation=True, geometry="smith", ndf="ggx").microfacet().energy_compensation
    for other in (Lambert(), Phong(), BlinnPhong(), Ward(), Disney(), Mirror(), OrenNayar(), AshikhminShirley()):
        assert other.microfacet() is None


@pytest.mark.parametrize("model, separable, stacked", [
    (Lambert(), True, True),
    (Phong(), True, True),
    (BlinnPhong(), True, True),
    (Mirror(), True, True),
    (CookTorrance(), True, True),
    (CookTorrance(alpha_x=0.1, alpha_y=0.3, ndf="ggx"), True, False),
    (Ward(1.0, 0.2), True, True),
    (Ward(1.0, 0.2, 0.05), True, False),
    (OrenNayar(), True, False),
    (AshikhminShirley(), True, False),
    (Disney(), False, False),
    (Lambert() + Phong(), True, True),
    (Lambert() + OrenNayar(), True, False),
])  # fmt: skip
def test_the_separable_extension_is_each_models_answer(model, separable, stacked):
    assert is_separable(model) is separable and stacks(model) is stacked
    g = Geometry(np.array([0.0, 0.0, 1.0]), np.array([[0.0, 0.6, 0.8], [0.8, 0.0, 0.6]]), np.array([0.3, 0.0, 0.95]))
    for form, public in (("cos", model.eval_cos_geometry), ("classic", model.classic_geometry)):
        combined = sum(s[..., None] * c for s, c in terms(model, g, form))
        np.testing.assert_allclose(combined, public(g), rtol=1e-12, atol=1e-300)


def test_a_sum_of_separable_and_plain_parts_adds_their_values():
    class Flat(BRDF):
        def _f(self, g):
            return np.where(g.above[..., None], np.full(3, 0.25 / math.pi), 0.0)

    total = create_model("lambert", kd=0.5) + Flat()
    assert not total.stackable and total.term == "specular"
    n, l, v = np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.6, 0.8]), np.array([0.0, 0.0, 1.0])  # noqa: E741
    np.testing.assert_allclose(total.classic(n, l, v), [0.75 * 0.8] * 3, rtol=1e-15)
    np.testing.assert_allclose(total.eval_cos(n, l, v), [0.75 * 0.8 / math.pi] * 3, rtol=1e-15)
    assert len(total.separable_classic(Geometry(n, l, v))) == 1 + 3  # Lambert's one term, the plain part's channels


def test_is_black_follows_the_colour_and_a_sum_is_black_only_when_every_part_is():
    black = [Lambert(0.0), Phong(0.0, 10), BlinnPhong((0, 0, 0), 10), CookTorrance(0.0, 0.3, 0.04),
             OrenNayar(0.0), Ward(ks=0.0), Mirror(ks=0.0)]  # fmt: skip
    lit = [Lambert((0, 0, 0.1)), Phong(0.2, 10), CookTorrance((0.0, 1e-300, 0.0), 0.3, 0.04), Ward(ks=0.5)]
    assert [m.is_black for m in black] == [True] * len(black)
    assert [m.is_black for m in lit] == [False] * len(lit)
    # A black model reflects nothing: eval is exactly 0 at a lit pair of directions.
    n, l, v = np.array([0, 0, 1.0]), np.array([0.3, 0, 0.95]), np.array([-0.3, 0, 0.95])
    for m in black[:4]:
        assert not np.any(m.eval(n, l, v))
    assert (Lambert(0.0) + Phong(0.0, 5)).is_black and not (Lambert(0.0) + Phong(0.1, 5)).is_black
    # Models that do not say (Disney, measured data) are never taken for black.
    assert Disney().is_black is False
