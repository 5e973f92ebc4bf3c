"""A BRDF Explorer file of Burley's principled BRDF, read by the engine's GLSL interpreter, is the engine's Disney."""

from __future__ import annotations

import numpy as np
import pytest

import lighting
from lighting.models import create_model

DISNEY = """analytic

# Burley's principled BRDF, in the layout of BRDF Explorer's files
::begin parameters
color baseColor .82 .67 .16
float metallic 0 1 0
float subsurface 0 1 0
float specular 0 1 .5
float roughness 0 1 .5
float specularTint 0 1 0
float anisotropic 0 1 0
float sheen 0 1 0
float sheenTint 0 1 .5
float clearcoat 0 1 0
float clearcoatGloss 0 1 1
::end parameters

::begin shader
const float PI = 3.14159265358979323846;

float sqr(float x) { return x*x; }

float SchlickFresnel(float u)
{
    float m = clamp(1-u, 0, 1);
    float m2 = m*m;
    return m2*m2*m; // pow(m,5)
}

float GTR1(float NdotH, float a)
{
    if (a >= 1) return 1/PI;
    float a2 = a*a;
    float t = 1 + (a2-1)*NdotH*NdotH;
    return (a2-1) / (PI*log(a2)*t);
}

float GTR2_aniso(float NdotH, float HdotX, float HdotY, float ax, float ay)
{
    return 1 / (PI * ax*ay * sqr( sqr(HdotX/ax) + sqr(HdotY/ay) + NdotH*NdotH ));
}

float smithG_GGX(float NdotV, float alphaG)
{
    float a = alphaG*alphaG;
    float b = NdotV*NdotV;
    return 1 / (NdotV + sqrt(a + b - a*b));
}

float smithG_GGX_aniso(float NdotV, float VdotX, float VdotY, float ax, float ay)
{
    return 1 / (NdotV + sqrt( sqr(VdotX*ax) + sqr(VdotY*ay) + sqr(NdotV) ));
}

vec3 mon2lin(vec3 x)
{
    return vec3(pow(x[0], 2.2), pow(x[1], 2.2), pow(x[2], 2.2));
}

vec3 BRDF( vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y )
{
    float NdotL = dot(N,L);
    float NdotV = dot(N,V);
    if (NdotL < 0 || NdotV < 0) return vec3(0);

    vec3 H = normalize(L+V);
    float NdotH = dot(N,H);
    float LdotH = dot(L,H);

    vec3 Cdlin = mon2lin(baseColor);
    float Cdlum = .3*Cdlin[0] + .6*Cdlin[1]  + .1*Cdlin[2]; // luminance approx.

    vec3 Ctint = Cdlum > 0 ? Cdlin/Cdlum : vec3(1); // normalize lum. to isolate hue+sat
    vec3 Cspec0 = mix(specular*.08*mix(vec3(1), Ctint, specularTint), Cdlin, metallic);
    vec3 Csheen = mix(vec3(1), Ctint, sheenTint);

    float FL = SchlickFresnel(NdotL), FV = SchlickFresnel(NdotV);
    float Fd90 = 0.5 + 2 * LdotH*LdotH * roughness;
    float Fd = mix(1.0, Fd90, FL) * mix(1.0, Fd90, FV);

    float Fss90 = LdotH*LdotH*roughness;
    float Fss = mix(1.0, Fss90, FL) * mix(1.0, Fss90, FV);
    float ss = 1.25 * (Fss * (1 / (NdotL + NdotV) - .5) + .5);

    float aspect = sqrt(1-anisotropic*.9);
    float ax = max(.001, sqr(roughness)/aspect);
    float ay = max(.001, sqr(roughness)*aspect);
    float Ds = GTR2_aniso(NdotH, dot(H, X), dot(H, Y), ax, ay);
    float FH = SchlickFresnel(LdotH);
    vec3 Fs = mix(Cspec0, vec3(1), FH);
    float Gs;
    Gs  = smithG_GGX_aniso(NdotL, dot(L, X), dot(L, Y), ax, ay);
    Gs *= smithG_GGX_aniso(NdotV, dot(V, X), dot(V, Y), ax, ay);

    vec3 Fsheen = FH * sheen * Csheen;

    float Dr = GTR1(NdotH, mix(.1,.001,clearcoatGloss));
    float Fr = mix(.04, 1.0, FH);
    float Gr = smithG_GGX(NdotL, .25) * smithG_GGX(NdotV, .25);

    return ((1/PI) * mix(Fd, ss, subsurface)*Cdlin + Fsheen)
        * (1-metallic)
        + Gs*Fs*Ds + .25*clearcoat*Gr*Fr*Dr;
}
::end shader
"""

#: The file's parameter names → the engine's.
NAMES = {"metallic": "metallic", "subsurface": "subsurface", "specular": "specular", "roughness": "roughness",
         "specularTint": "specular_tint", "anisotropic": "anisotropic", "sheen": "sheen", "sheenTint": "sheen_tint",
         "clearcoat": "clearcoat", "clearcoatGloss": "clearcoat_gloss"}  # fmt: skip


def _hemisphere(rng, count):
    d = rng.normal(size=(count, 3))
    d[:, 2] = np.abs(d[:, 2]) + 0.05
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


@pytest.mark.parametrize(
    "settings",
    [{}, {"metallic": 0.7, "roughness": 0.2, "anisotropic": 0.6},
     {"subsurface": 0.8, "sheen": 0.5, "clearcoat": 1.0, "clearcoatGloss": 0.3, "specularTint": 0.4, "sheenTint": 0.9}],
)  # fmt: skip
def test_the_file_is_the_engine_s_disney(tmp_path, settings):
    path = tmp_path / "disney.brdf"
    path.write_text(DISNEY)
    from_file = lighting.load_brdf(path, **settings)
    # The file's colour slider goes through mon2lin (x^2.2); the engine's base_color is linear.
    engine = create_model("disney", base_color=tuple(np.array((0.82, 0.67, 0.16)) ** 2.2),
                          **{NAMES[k]: v for k, v in settings.items()})  # fmt: skip
    rng = np.random.default_rng(0)
    l, v = _hemisphere(rng, 400), _hemisphere(rng, 400)  # noqa: E741
    n = np.broadcast_to([0.0, 0.0, 1.0], l.shape)
    t = np.broadcast_to([1.0, 0.0, 0.0], l.shape)
    np.testing.assert_allclose(from_file.eval(n, l, v, tangent=t), engine.eval(n, l, v, tangent=t), rtol=1e-6)


def test_a_component_index_must_be_a_constant_0_to_3(tmp_path):
    bad = DISNEY.replace("pow(x[0], 2.2)", "pow(x[4], 2.2)")
    path = tmp_path / "bad.brdf"
    path.write_text(bad)
    line = bad[: bad.index("x[4]")].count("\n") + 1
    with pytest.raises(ValueError, match=rf"bad.brdf:{line}:\d+: expected a constant index 0, 1, 2 or 3"):
        lighting.load_brdf(path)


def test_components_by_index_are_written_too():
    from lighting.files.brdf_format import from_text

    src = (
        "analytic\n::begin parameters\nfloat k 0 1 0.5\n::end parameters\n::begin shader\n"
        "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) {\n"
        "    vec3 c = vec3(0.0);\n    c[0] = k; c[2] += 2.0 * c[0];\n    return c;\n}\n::end shader\n"
    )
    got = from_text(src, "idx.brdf", k=0.25).eval([0, 0, 1], [0, 0, 1], [0, 0, 1])
    np.testing.assert_array_equal(got, [0.25, 0.0, 0.5])
