"""BRDF Explorer ``.brdf`` files: the built-in models written as files, each language feature, each error, a fuzz."""

import time

import numpy as np
import pytest

from lighting.brdf import BlinnPhong, CookTorrance, Lambert, Phong
from lighting.files import load_brdf
from lighting.files.brdf_format import MAX_FILE_BYTES, from_text
from lighting.files.glsl import interpret

SIG = "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)"
PI = "const float PI = 3.14159265358979323846;\n"


def brdf_file(body, params="", pre=""):
    """A file's text: an optional parameter block, then the shader with ``pre`` and ``BRDF``'s body."""
    block = f"::begin parameters\n{params}::end parameters\n" if params else ""
    return f"# test file\nanalytic\n{block}::begin shader\n{PI}{pre}\n{SIG}\n{{\n{body}\n}}\n::end shader\n"


def write(tmp_path, text, name="m.brdf"):
    p = tmp_path / name
    p.write_text(text)
    return p


def pairs(n=400, seed=0):
    rng = np.random.default_rng(seed)
    l, v = rng.normal(size=(2, n, 3))
    return np.array([0.0, 0.0, 1.0]), l / np.linalg.norm(l, axis=-1, keepdims=True), v


def const_value(body, pre="", **kw):
    """What the shader returns for straight-up directions (channel values as a list)."""
    b = from_text(brdf_file(body, pre=pre), "t.brdf", **kw)
    return b.eval((0, 0, 1.0), (0, 0, 1.0), (0, 0, 1.0)).tolist()


# --------------------------------------------------------------------------- the built-in models as files
LAMBERT = ("color kd 0.8 0.5 0.2\n", "return kd / PI;")
PHONG = (
    "color ks 0.5 0.4 0.3\nfloat n 0 1000 20\n",
    "vec3 R = reflect(-L, N);\nreturn ks * pow(max(dot(R, V), 0.0), n) / (PI * dot(N, L));",
)
BLINN = (
    "color ks 0.5 0.4 0.3\nfloat n 0 1000 30\nbool normalized 0\n",
    """vec3 H = normalize(L + V);
    float lobe = pow(max(dot(N, H), 0.0), n);
    if (normalized) return ks * (n + 2.0) / (2.0 * PI) * lobe;
    return ks * lobe / (PI * dot(N, L));""",
)
CT_PARAMS = "color ks 1 1 1\nfloat alpha 0.01 1 0.3\ncolor f0 0.04 0.5 0.9\nbool use_ggx 0\n"
CT_PRE = """
float beckmann(float c, float a) { float c2 = c * c; return exp((c2 - 1.0) / (c2 * a * a)) / (PI * a * a * c2 * c2); }
float ggx(float c, float a) { float a2 = a * a; float d = c * c * (a2 - 1.0) + 1.0; return a2 / (PI * d * d); }
"""
CT_BODY = """vec3 H = normalize(L + V);
    float nh = dot(N, H), nv = dot(N, V), nl = dot(N, L), vh = dot(V, H);
    float D = use_ggx ? ggx(nh, alpha) : beckmann(nh, alpha);
    float G = min(1.0, min(2.0 * nh * nv / vh, 2.0 * nh * nl / vh));
    vec3 F = f0 + (vec3(1.0) - f0) * pow(1.0 - vh, 5.0);
    return ks * D * G * F / (4.0 * nv * nl);"""


@pytest.mark.parametrize(
    "text, kwargs, model",
    [
        (brdf_file(LAMBERT[1], LAMBERT[0]), {}, Lambert((0.8, 0.5, 0.2))),
        (brdf_file(PHONG[1], PHONG[0]), {}, Phong((0.5, 0.4, 0.3), 20)),
        (brdf_file(PHONG[1], PHONG[0]), {"n": 200.0, "ks": 0.7}, Phong(0.7, 200)),
        (brdf_file(BLINN[1], BLINN[0]), {}, BlinnPhong((0.5, 0.4, 0.3), 30)),
        (brdf_file(BLINN[1], BLINN[0]), {"normalized": True}, BlinnPhong((0.5, 0.4, 0.3), 30, normalized=True)),
        (brdf_file(CT_BODY, CT_PARAMS, CT_PRE), {}, CookTorrance(1.0, 0.3, (0.04, 0.5, 0.9))),
        (
            brdf_file(CT_BODY, CT_PARAMS, CT_PRE),
            {"use_ggx": True, "alpha": 0.2},
            CookTorrance(1.0, 0.2, (0.04, 0.5, 0.9), ndf="ggx"),
        ),
    ],
    ids=["lambert", "phong", "phong-kw", "blinn", "blinn-normalized", "ct-beckmann", "ct-ggx"],
)
def test_file_equals_builtin_model(tmp_path, text, kwargs, model):
    b = load_brdf(write(tmp_path, text), **kwargs)
    n, l, v = pairs()
    got, want = b.eval(n, l, v), model.eval(n, l, v)
    assert (want > 0).any() and (got[(want == 0)] == 0).all()
    np.testing.assert_allclose(got, want, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(b.eval_cos(n, l, v), model.eval_cos(n, l, v), rtol=1e-6, atol=1e-12)


def test_float32_kept_and_parameter_table(tmp_path):
    b = load_brdf(write(tmp_path, brdf_file(BLINN[1], BLINN[0])))
    n, l, v = pairs(50)
    out = b.eval(n.astype(np.float32), l.astype(np.float32), v.astype(np.float32))
    assert out.dtype == np.float32 and out.shape == (50, 3)
    np.testing.assert_allclose(out, BlinnPhong((0.5, 0.4, 0.3), 30).eval(n, l, v), rtol=2e-4, atol=1e-6)
    kinds = [(p.name, p.kind, p.default) for p in b.parameters]
    assert kinds == [("ks", "color", (0.5, 0.4, 0.3)), ("n", "float", 30.0), ("normalized", "bool", False)]
    assert (b.parameters[1].low, b.parameters[1].high) == (0.0, 1000.0)


def test_zero_below_horizon_and_tangent_frame():
    # X and Y are the engine's tangent frame: in the local frame t = x̂, b = ŷ.
    b = from_text(brdf_file("return vec3(dot(L, X) + 2.0, dot(L, Y) + 2.0, dot(X, Y) + 1.0);"))
    out = b.eval((0, 0, 1.0), [(0.6, 0.0, 0.8), (0.0, 0.6, 0.8), (0.0, 0.0, -1.0)], (0, 0, 1.0))
    np.testing.assert_allclose(out, [[2.6, 2.0, 1.0], [2.0, 2.6, 1.0], [0.0, 0.0, 0.0]], atol=1e-12)


# --------------------------------------------------------------------------- language features
@pytest.mark.parametrize(
    "pre, body, want",
    [
        ("", "vec3 c = vec3(1.0); c.zx = vec2(2.0, 3.0); c.g += 4.0; return c;", [3.0, 5.0, 2.0]),
        ("", "vec4 c = vec4(1.0, 2.0, 3.0, 4.0); return c.abg + c.wzy.xxx;", [8.0, 7.0, 6.0]),
        (
            "void f(in float a, out float b, inout vec3 c) { b = a * 2.0; c.y = a; a = 100.0; }",
            "float a = 1.5, b; vec3 c = vec3(0.0); f(a, b, c); return vec3(a, b, c.y);",
            [1.5, 3.0, 1.5],
        ),  # fmt: skip
        (
            "float g(float x) { return 1.0; } float g(vec3 x) { return 2.0; } float g(int x) { return 3.0; }",
            "return vec3(g(0.5), g(N), g(7));",
            [1.0, 2.0, 3.0],
        ),  # fmt: skip
        ("float dot(vec3 a, vec3 b) { return 42.0; }", "return vec3(dot(L, V), length(L), 0.0);", [42.0, 1.0, 0.0]),
        ("", "float x = 2.0; return vec3(x > 1.0 ? 5.0 : 6.0, x < 1.0 ? 5.0 : 6.0, true ? 1 : 0);", [5.0, 6.0, 1.0]),
        (
            "",
            "if (dot(N, L) > 2.0) { return vec3(9.0); } else if (false) return vec3(8.0);\n"
            "vec3 r = vec3(1.0); if (N.z > 0.5) return r * 3.0; return vec3(7.0);",
            [3.0, 3.0, 3.0],
        ),  # fmt: skip
        (
            "",
            "float s = 0.0; for (int i = 0; i < 10; i++) { s += float(i); } int k = 7 / 2;\n"
            "return vec3(s, k, 5 % 1 == 0 ? 1.0 : 0.0);",
            None,
        ),  # fmt: skip
        ("const vec3 C = vec3(1.0, 2.0, 3.0); const float K = 2.0 * PI;", "return C * K / PI;", [2.0, 4.0, 6.0]),
        (
            "",
            "float a = 1.0; float b = a++ + ++a; bool t = !(a == 3.0) || a != 3.0 ^^ true;\n"
            "return vec3(a, b, t ? 1.0 : 0.0);",
            [3.0, 4.0, 1.0],
        ),  # fmt: skip
        (
            "",
            "return vec3(clamp(2.0, 0.0, 1.0), mix(0.0, 4.0, 0.25), smoothstep(0.0, 1.0, 0.5)) +"
            " vec3(mod(-1.0, 3.0), atan(1.0, 1.0) * 4.0 / PI, step(0.5, 0.2));",
            [3.0, 2.0, 0.5],
        ),  # fmt: skip
        (
            "",
            "return vec3(sqrt(-1.0), log(0.0), pow(-2.0, 0.5)) + vec3(acos(2.0), 1.0 / 0.0, inversesqrt(0.0));",
            [0.0, 0.0, 0.0],
        ),  # fmt: skip
    ],
    ids=[
        "swizzle-write",
        "swizzle-read",
        "out-inout",
        "overload",
        "shadow-builtin",
        "ternary",
        "if-return",
        "for",
        "const-global",
        "incdec-logic",
        "builtins",
        "undefined-is-zero",
    ],  # fmt: skip
)
def test_language_feature(pre, body, want):
    if want is None:  # '%' is not in the subset (GLSL 1.x has no float remainder): it is an error
        with pytest.raises(ValueError, match=r"t\.brdf:\d+:\d+: expected mod"):
            const_value(body, pre)
        body = body.replace("5 % 1 == 0", "true")
        want = [45.0, 3.0, 1.0]
    assert const_value(body, pre) == pytest.approx(want, abs=1e-12)


def test_return_in_one_branch_is_per_lane():
    b = from_text(brdf_file("if (L.x > 0.0) { return vec3(1.0); }\nvec3 r = vec3(2.0); r.x = 5.0; return r;"))
    out = b.eval((0, 0, 1.0), [(0.6, 0, 0.8), (-0.6, 0, 0.8)], (0, 0, 1.0))
    assert out.tolist() == [[1.0, 1.0, 1.0], [5.0, 2.0, 2.0]]


def test_short_circuit_side_effects_per_lane():
    body = "float k = 0.0; bool t = L.x > 0.0 && (k += 1.0) > 0.0; bool u = L.x > 0.0 || (k += 10.0) > 0.0;\n"
    body += "return vec3(k, t ? 1.0 : 0.0, u ? 1.0 : 0.0);"
    out = from_text(brdf_file(body)).eval((0, 0, 1.0), [(0.6, 0, 0.8), (-0.6, 0, 0.8)], (0, 0, 1.0))
    assert out.tolist() == [[1.0, 1.0, 1.0], [10.0, 0.0, 1.0]]


def test_data_dependent_loop_per_lane():
    body = "float s = 0.0; for (int i = 0; float(i) < 10.0 * L.x; ++i) s += 1.0; return vec3(s);"
    out = from_text(brdf_file(body)).eval((0, 0, 1.0), [(0.6, 0, 0.8), (0.0, 0.6, 0.8)], (0, 0, 1.0))
    assert out[:, 0].tolist() == [6.0, 0.0]


# --------------------------------------------------------------------------- errors: one ValueError, file:line:col
ERRORS = [
    (
        brdf_file("return vec3(f());", pre="void f() { }"),
        r"m\.brdf:8:13: expected a value, got a call of the void function 'f'",
    ),
    (brdf_file("return;"), r"m\.brdf:8:1: expected a vec3 value after return, got ';'"),
    (brdf_file("return L;", params="color k -1 0 0\n"), r"m\.brdf:4:7: expected r, g, b >= 0 for k, got -1 0 0"),
    (brdf_file("return vec3(" + "+".join(["1.0"] * 300) + ");"), r"m\.brdf:8:\d+: expected at most 200 levels"),
    (
        "::begin shader\nvec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return L; }\n",
        r"m\.brdf:1:1: expected '::end shader'",
    ),
    ("::begin parameters\nfloat k 0 1 0.5\n", r"m\.brdf:1:1: expected '::end parameters'"),
    (brdf_file("return Q;"), r"m\.brdf:8:8: expected a declared variable, got unknown identifier 'Q'"),
    (brdf_file("return vec3(frob(1.0));"), r"m\.brdf:8:13: .*unknown identifier 'frob'"),
    (brdf_file("return vec3(pow(1.0));"), r"m\.brdf:8:13: expected 2 arguments to pow, got 1"),
    (
        brdf_file("float x = L; return vec3(x);"),
        r"m\.brdf:8:7: type mismatch in the declaration of 'x': expected float, got vec3",
    ),
    (brdf_file("return L + vec2(1.0);"), r"m\.brdf:8:10: type mismatch: expected alike vectors"),
    (brdf_file("return L;;\n  } }"), r"m\.brdf:9:5: expected a type .*, got '}'"),
    (brdf_file("return L +;"), r"m\.brdf:8:11: expected an expression, got ';'"),
    (brdf_file("vec3 a = L\nreturn a;"), r"m\.brdf:9:1: expected ';' or ',', got 'return'"),
    (brdf_file("return L.xq;"), r"m\.brdf:8:10: expected a swizzle"),
    (
        "analytic\n::begin shader\nvec3 brdf(vec3 L) { return L; }\n::end shader\n",
        r"m\.brdf:3:1: expected a function vec3 BRDF",
    ),
    (
        "::begin shader\nfloat BRDF(vec3 L) { return 1.0; }\n::end shader\n",
        r"m\.brdf:2:1: expected vec3 BRDF\(vec3 L, .*got float BRDF\(in vec3\)",
    ),
    (
        brdf_file("float s = 0.0; for (int i = 0; i >= 0; i++) s += 1.0; return vec3(s);"),
        r"m\.brdf:8:16: expected a loop that ends within 1024",
    ),
    (
        brdf_file("return vec3(f(1.0));", pre="float f(float x) { return f(x); }"),
        r"m\.brdf:\d+:\d+: expected calls nested at most 64",
    ),
    (brdf_file("return L;", params="float k 0 1 2\n"), r"m\.brdf:4:13: expected MIN <= DEFAULT <= MAX for k"),
    (brdf_file("return L;", params="vector k 0 1 2\n"), r"m\.brdf:4:1: expected a parameter line"),
    (brdf_file("return L;", params="float k 0 1 nan\n"), r"m\.brdf:4:13: expected a finite number"),
    ("hello\n", r"m\.brdf:1:1: expected 'analytic'"),
    (brdf_file("return L; /* never closed"), r"m\.brdf:8:11: expected '\*/'"),
    (brdf_file("#define X 1\nreturn L;"), r"m\.brdf:8:1: expected a GLSL token, got '#'"),
    (brdf_file("if (1.0) return L; return V;"), r"m\.brdf:8:5: type mismatch: expected a bool condition, got float"),
    (brdf_file("PI = 3.0; return L;"), r"m\.brdf:8:1: expected a local variable, got 'PI'"),
    (brdf_file("float x = 1.0; float x = 2.0; return L;"), r"m\.brdf:8:22: expected a new name"),
    (brdf_file("while (true) {} return L;"), r"m\.brdf:8:1: expected a statement of the subset"),
    (brdf_file("return " + "(" * 500 + "L" + ")" * 500 + ";"), r"m\.brdf:8:\d+: expected at most 200 levels"),
]


@pytest.mark.parametrize("text, message", ERRORS)
def test_error_names_file_line_column(tmp_path, text, message):
    with pytest.raises(ValueError, match=message) as info:
        load_brdf(write(tmp_path, text))
    assert str(info.value).count("m.brdf") == 1 and info.value.__cause__ is None


def test_parameter_errors(tmp_path):
    p = write(tmp_path, brdf_file(PHONG[1], PHONG[0]))
    with pytest.raises(ValueError, match=r"unknown parameter 'shininess'; the file's parameters are ks, n"):
        load_brdf(p, shininess=3.0)
    with pytest.raises(ValueError, match=r"'n' must be a number in \[0, 1000\]; got 2000"):
        load_brdf(p, n=2000)
    with pytest.raises(ValueError, match=r"'ks' must be a finite scalar or RGB triple"):
        load_brdf(p, ks=(1, 2))


def test_file_errors(tmp_path):
    big = tmp_path / "big.brdf"
    big.write_bytes(b"#" * (MAX_FILE_BYTES + 1))
    with pytest.raises(ValueError, match=r"big\.brdf: expected at most 1048576 bytes"):
        load_brdf(big)
    bad = tmp_path / "bad.brdf"
    bad.write_bytes(b"analytic\n\xff\n")
    with pytest.raises(ValueError, match=r"bad\.brdf: byte 9: expected UTF-8 text, got byte 0xff"):
        load_brdf(bad)
    with pytest.raises(ValueError, match=r"cannot read"):
        load_brdf(tmp_path / "missing.brdf")


def test_work_is_bounded(monkeypatch):
    monkeypatch.setattr(interpret, "MAX_STEPS", 5000)
    body = "float s = 0.0; for (int i = 0; i < 1000; i++) for (int j = 0; j < 1000; j++) s += 1.0; return vec3(s);"
    t0 = time.perf_counter()
    with pytest.raises(ValueError, match=r"t\.brdf:8:\d+: expected at most 5000 statements"):
        from_text(brdf_file(body), "t.brdf")
    assert time.perf_counter() - t0 < 5


# --------------------------------------------------------------------------- fuzz: ValueError or a model, quickly
def test_fuzz_mutated_files_only_value_error():
    rng = np.random.default_rng(17)
    base = brdf_file(CT_BODY, CT_PARAMS, CT_PRE)
    alphabet = list("(){};,.+-*/=<>!?:&|^#xyzrgb0123456789 \n") + ["vec3", "float", "return", "if", "for", "else"]
    n, l, v = pairs(8)
    start = base.index("::begin shader")  # mutate the shader three times in four, else anywhere
    for k in range(300):
        text = list(base)
        for _ in range(rng.integers(1, 4)):
            i = int(rng.integers(0 if k % 4 == 0 else start, len(text)))
            op = rng.integers(0, 3)
            if op == 0:
                del text[i]
            elif op == 1:
                text.insert(i, alphabet[int(rng.integers(0, len(alphabet)))])
            else:
                text[i] = alphabet[int(rng.integers(0, len(alphabet)))]
        src = "".join(text)
        t0 = time.perf_counter()
        try:
            b = from_text(src, "fz.brdf")
            out = b.eval(n, l, v)
            assert out.shape == (8, 3) and np.isfinite(out).all() and (out >= 0).all()
        except ValueError as exc:
            assert str(exc).startswith("fz.brdf")
        assert time.perf_counter() - t0 < 2


def test_fuzz_random_token_streams_only_value_error():
    rng = np.random.default_rng(5)
    words = ("vec3 vec2 float int bool const in out inout void return if else for ( ) { } ; , . = += ++ -- + - "
             "* / < <= == && || ! ? : x y L N V BRDF dot pow normalize 1.0 2 0.5 true .xy .zzz").split()  # fmt: skip
    for _ in range(300):
        toks = [words[int(i)] for i in rng.integers(0, len(words), int(rng.integers(1, 40)))]
        src = f"::begin shader\n{SIG} {{ {' '.join(toks)} }}\n::end shader\n"
        t0 = time.perf_counter()
        try:
            from_text(src, "tok.brdf").eval((0, 0, 1.0), (0, 0.6, 0.8), (0, 0, 1.0))
        except ValueError as exc:
            assert str(exc).startswith("tok.brdf")
        assert time.perf_counter() - t0 < 2
