"""Importance sampling of the family-A models: ``brdf_rs.sample`` against ``brdf_rs.pdf``.

χ² goodness of fit (harness in ``chi2.py``): N = 1e6 draws per case, histogrammed on
40 θ bands of equal pilot mass (plus tail bands) × 40 φ bins in a frame about the lobe's
axis (the mirror direction for the lobe samplers, the normal for cosine / uniform),
expected counts by adaptive Gauss-Legendre integration of ``pdf`` clipped at the
horizon, and draws lost below the surface as one more cell; Pearson's χ², an exact
binomial test of the valid mass and a test of draws in empty cells are combined by
Bonferroni into one p-value per case. The family of K = ``len(CHI2_CASES)`` tests (58 as
written) is held at a family-wise level of 1% by Šidák's correction: each test at
``α₁ = 1 − 0.99^(1/K)`` (≈ 1.7e-4 for K = 58). The seeds are fixed (crc32 of the case id).

Which cases, and why this subset (the full product of 10 models × 3 incidences × 5
exponents × {single lobe, mixture} would be ~300 tests of ~0.6 s each; the file must run
in about a minute on 2 cores):

- What a draw's distribution depends on is the *warp* and the mixture weights. With
  ``kd = 0`` every Phong-family model (phong, modified_phong, normalized_phong) draws
  from the same single Phong lobe about the mirror direction, and every Blinn-family
  model and torrance_sparrow from the same single Blinn half-vector lobe. So the
  single-lobe grid, every mu_i ∈ {0.05, 0.5, 0.95} × p ∈ {1, 10, 100, 1e3, 1e4}, is run
  for one representative of each warp: normalized_phong and torrance_sparrow
  (30 cases).
- Mixtures (``kd`` and ``ks`` > 0) depend on each model's own lobe weights (the
  non-normalized models weigh ``kd`` by π, the Fresnel models differ, ...), so every
  model with an exponent gets two mixture cases, the (mu_i, p) pairs rotated so that
  each incidence and each exponent occurs several times across models (16 cases).
- lambert and oren_nayar (cosine sampling) once each; ``sampler="cosine"`` and
  ``sampler="uniform"`` on lobe models, one of them at grazing incidence (5 cases).
- A tilted normal (not +z) for a Phong mixture, a Blinn lobe at grazing incidence and
  the uniform sampler (3 cases).

Other checks, with their tolerances:

- ∫ pdf dω over the sphere (adaptive quadrature in the lobe frame, per-piece tolerance
  1e-11 absolute + 1e-10 relative, geometric θ bands from 1e-4 rad: fine for p = 1e4)
  equals the fraction of valid draws: exactly 1 with no invalid draw for cosine,
  uniform and Phong lobes at mu_i = 1; otherwise within 5 binomial standard errors,
  ``|∫pdf − valid fraction| ≤ 5·sqrt(P(1 − P)/N)`` with N = 1e6. Where the integral has
  a closed form it must match it to 1e-9: a Phong lobe with p = 1 keeps (1 + mu_i)/2
  (the tilted-plane sky view factor); a Blinn half-vector lobe at mu_i = 1 keeps
  ``P(θh < 45°) = 1 − 2^(−(p+2)/2)`` (it *does* lose mass at normal incidence).
- ``weight == eval·cos θo / pdf`` to 1e-12 relative, ``weight == 0`` exactly for
  invalid draws (those are exactly the draws with ``wo·n ≤ 0``), and the returned pdf
  equals ``brdf_rs.pdf`` of the returned ``wo`` to 1e-12 relative.
- The mean of ``weight`` (2^18 draws) matches ``brdf_rs.albedo`` (2^16 Sobol samples)
  within 5 combined standard errors per channel (plus 1e-9 relative, for the models
  whose albedo is exact and whose weight has zero variance).
- Determinism (same ``u``, same bits, whatever the batch) and argument errors.
"""

from __future__ import annotations

import dataclasses
import math
import zlib

import brdf_rs
import chi2
import numpy as np
import pytest
from conftest import FAMILY_A, FAMILY_B

PHONG = ("phong", "modified_phong", "normalized_phong")
BLINN = (
    "blinn_phong",
    "modified_blinn_phong",
    "normalized_blinn_phong",
    "blinn_phong_fresnel",
    "torrance_sparrow",
)
DIFFUSE = ("lambert", "oren_nayar")
MICROFACET = ("ggx", "beckmann", "ward", "ashikhmin_shirley")
MULTIPLE_SCATTERING = ("ggx_ms", "beckmann_ms")
#: ggx's and beckmann's lobes with other Fresnel terms (drawn from the same visible normals).
FRESNEL_VARIANTS = (
    "ggx_conductor",
    "beckmann_conductor",
    "ggx_f82",
    "beckmann_f82",
    "ggx_gen_schlick",
    "beckmann_gen_schlick",
)
SHEEN = ("charlie_sheen", "charlie_sheen_neubelt", "ashikhmin_cloth", "zeltner_sheen")
#: Defined on the whole sphere (they transmit): their sampling tests are in
#: tests/test_dielectric.py, which histograms the sphere rather than the hemisphere.
DIELECTRIC = ("ggx_dielectric", "beckmann_dielectric", "ggx_dielectric_ms")
MUS = (0.05, 0.5, 0.95)
EXPONENTS = (1.0, 10.0, 100.0, 1e3, 1e4)
TILTED = (0.35, -0.25, 0.9)


def test_the_model_lists_cover_family_a():
    lists = PHONG + BLINN + DIFFUSE + MICROFACET + MULTIPLE_SCATTERING + SHEEN + FRESNEL_VARIANTS
    lists += DIELECTRIC
    assert sorted(lists) == sorted(FAMILY_A)


@dataclasses.dataclass(frozen=True)
class Case:
    """One sampling configuration: a model, an incidence, parameters, sampler, normal."""

    model: str
    mu: float
    params: tuple[tuple[str, float | tuple[float, ...]], ...]
    sampler: str = "auto"
    normal: tuple[float, float, float] = (0.0, 0.0, 1.0)

    @classmethod
    def of(cls, model, mu, sampler="auto", normal=(0.0, 0.0, 1.0), **params):
        items = tuple(
            sorted((k, tuple(v) if isinstance(v, list) else v) for k, v in params.items())
        )
        return cls(model, mu, items, sampler, normal)

    @property
    def kwargs(self) -> dict:
        return dict(self.params)

    @property
    def id(self) -> str:
        p = ",".join(
            f"{k}={v:g}" if not isinstance(v, tuple) else f"{k}={list(v)}" for k, v in self.params
        )
        extra = "" if self.sampler == "auto" else f"-{self.sampler}"
        tilt = "" if self.normal == (0.0, 0.0, 1.0) else "-tilted"
        return f"{self.model}-mu={self.mu:g}-{p}{extra}{tilt}"

    @property
    def seed(self) -> int:
        return zlib.crc32(self.id.encode())

    def geometry(self):
        """``wi`` at cos θi = mu about the (unit) normal, the normal, and the lobe axis."""
        n = np.asarray(self.normal, dtype=np.float64)
        n = n / np.linalg.norm(n)
        t = chi2.Frame.around(n).x
        wi = self.mu * n + math.sqrt(1.0 - self.mu * self.mu) * t
        mirror = 2.0 * self.mu * n - wi
        lobe = self.sampler == "auto" and self.model not in DIFFUSE + MULTIPLE_SCATTERING + SHEEN
        return wi, n, (mirror if lobe else n)

    def draw(self, u):
        wi, n, _ = self.geometry()
        return brdf_rs.sample(self.model, wi, u, n, sampler=self.sampler, **self.kwargs)

    def sampler_fn(self, u):
        wo, _, pdf = self.draw(u)
        return wo, pdf > 0.0

    def pdf_fn(self, wo):
        wi, n, _ = self.geometry()
        return brdf_rs.pdf(self.model, wi, wo, n, sampler=self.sampler, **self.kwargs)


def _params(model: str, p: float, mixture: bool) -> dict:
    """kd, ks (and eta, sigma) for a model: a single lobe (kd = 0) or a mixture.

    For the microfacet models ``p`` is the roughness: α for ggx and beckmann, (αx, αy) =
    (p, 4p) for ward and (nu, nv) = (1/p, 100/p) for ashikhmin_shirley (anisotropic).
    """
    if model in SHEEN:  # alpha in [1e-3, 1]; an exponent-like p > 1 maps to 1/sqrt(p)
        alpha = p if p <= 1.0 else 1.0 / math.sqrt(p)
        return {"alpha": alpha, "kd": [0.3, 0.2, 0.1] if mixture else 0.0, "ks": [1.0, 0.8, 0.6]}
    if model in MULTIPLE_SCATTERING:  # alpha within the table's range [1e-3, 1]
        return {"alpha": min(max(p, 1e-3), 1.0), "ks": [1.0, 0.8, 0.6]}
    if model in ("ggx_conductor", "beckmann_conductor"):
        kd = [0.3, 0.2, 0.1] if mixture else 0.0
        return {"alpha": p, "kd": kd, "eta": [0.2, 1.0, 1.5], "k": [3.0, 2.0, 0.0]}
    if model in ("ggx_f82", "beckmann_f82"):
        kd = [0.3, 0.2, 0.1] if mixture else 0.0
        return {"alpha": p, "kd": kd, "f0": [0.95, 0.6, 0.1], "f82": [0.9, 0.5, 0.0]}
    if model in ("ggx_gen_schlick", "beckmann_gen_schlick"):
        kd = [0.3, 0.2, 0.1] if mixture else 0.0
        return {
            "alpha": p,
            "kd": kd,
            "f0": [0.9, 0.5, 0.04],
            "f90": [1.0, 0.3, 1.0],
            "exponent": 3.0,
        }
    if model in ("ggx", "beckmann"):
        return {"alpha": p, "kd": [0.3, 0.2, 0.1] if mixture else 0.0, "ks": [1.0, 0.8, 0.6]}
    if model == "ward":
        kd = [0.3, 0.2, 0.1] if mixture else 0.0
        return {"alpha_x": p, "alpha_y": 4 * p, "kd": kd, "ks": [1.0, 0.8, 0.6]}
    if model == "ashikhmin_shirley":
        rd = [0.3, 0.2, 0.1] if mixture else 0.0
        return {"nu": 1 / p, "nv": 100 / p, "Rd": rd, "Rs": [0.9, 0.5, 0.2]}
    if model in DIFFUSE:
        return {"kd": [0.8, 0.5, 0.3]} | ({"sigma": 0.5} if model == "oren_nayar" else {})
    out: dict = {"p": p, "kd": [0.3, 0.2, 0.1] if mixture else 0.0}
    out["ks"] = [0.9, 0.6, 0.5] if model == "blinn_phong_fresnel" else [1.0, 0.8, 0.6]
    if model == "torrance_sparrow":
        out["eta"] = 1.5
    return out


def _chi2_cases() -> list[Case]:
    cases = []
    # Single lobes: the full grid for one model per warp.
    for model in ("normalized_phong", "torrance_sparrow"):
        for mu in MUS:
            for p in EXPONENTS:
                cases.append(Case.of(model, mu, **_params(model, p, mixture=False)))
    # Mixtures: two (mu, p) points per model, rotated over models.
    mixture_points = {
        "phong": [(0.05, 100.0), (0.95, 1e4)],
        "modified_phong": [(0.5, 1.0), (0.05, 1e3)],
        "normalized_phong": [(0.95, 10.0), (0.5, 1e4)],
        "blinn_phong": [(0.05, 10.0), (0.5, 1e3)],
        "modified_blinn_phong": [(0.95, 1.0), (0.05, 1e4)],
        "normalized_blinn_phong": [(0.5, 100.0), (0.95, 1e3)],
        "blinn_phong_fresnel": [(0.05, 1.0), (0.95, 100.0)],
        "torrance_sparrow": [(0.5, 10.0), (0.05, 1e3)],
    }
    for model, points in mixture_points.items():
        for mu, p in points:
            cases.append(Case.of(model, mu, **_params(model, p, mixture=True)))
    # Microfacet models: grazing to normal incidence, smooth to sharp, single and mixed.
    microfacet_points = {
        "ggx": [(0.05, 0.02, False), (0.5, 0.3, True), (0.95, 1.0, False)],
        # Visible normals (Heitz & d'Eon 2014): grazing to normal incidence, 0.005 to 1.5.
        "beckmann": [
            (0.05, 0.3, False),
            (0.5, 0.02, False),
            (0.95, 0.7, True),
            (0.01, 0.5, False),
            (0.2, 0.005, False),
            (1.0, 0.3, False),
            (0.999, 1.5, False),
        ],
        "ward": [(0.05, 0.05, False), (0.5, 0.2, True), (0.95, 0.02, False)],
        "ashikhmin_shirley": [(0.05, 0.1, False), (0.5, 0.01, True), (0.95, 1.0, False)],
        # Their lobes' samplers, with one mixture term per distinct colour channel.
        "ggx_conductor": [(0.05, 0.3, False), (0.7, 0.1, True)],
        "beckmann_conductor": [(0.5, 0.5, True)],
        "ggx_f82": [(0.3, 0.2, True)],
        "beckmann_f82": [(0.9, 0.05, False)],
        "ggx_gen_schlick": [(0.95, 0.4, True)],
        "beckmann_gen_schlick": [(0.2, 0.2, False)],
    }
    for model, points in microfacet_points.items():
        for mu, roughness, mixture in points:
            cases.append(Case.of(model, mu, **_params(model, roughness, mixture)))
    # Sheen (drawn uniformly) and cloth (a cosine/uniform mixture whose shares move with
    # mu and alpha): grazing to normal incidence, sharp to wide.
    sheen_points = {
        "charlie_sheen": [(0.05, 0.3, False), (0.5, 1.0, True), (0.95, 0.01, False)],
        "charlie_sheen_neubelt": [(0.5, 0.05, False)],
        "ashikhmin_cloth": [(0.95, 0.5, True), (0.3, 0.8, False), (0.05, 0.05, False)],
        "zeltner_sheen": [(0.05, 0.3, False), (0.7, 1.0, True)],
    }
    for model, points in sheen_points.items():
        for mu, roughness, mixture in points:
            cases.append(Case.of(model, mu, **_params(model, roughness, mixture)))
    # The multiple-scattering lobes (diffuse-like: drawn cosine-weighted).
    cases.append(Case.of("ggx_ms", 0.05, **_params("ggx_ms", 0.5, False)))
    cases.append(Case.of("beckmann_ms", 0.7, **_params("beckmann_ms", 1.0, False)))
    # Diffuse models; the single-warp samplers on lobe models.
    cases.append(Case.of("lambert", 0.05, **_params("lambert", 0, False)))
    cases.append(Case.of("oren_nayar", 0.5, **_params("oren_nayar", 0, False)))
    cases.append(
        Case.of("torrance_sparrow", 0.5, "cosine", **_params("torrance_sparrow", 100.0, True))
    )
    cases.append(Case.of("phong", 0.05, "cosine", **_params("phong", 1e3, False)))
    cases.append(
        Case.of("normalized_phong", 0.05, "uniform", **_params("normalized_phong", 1e3, True))
    )
    # A tilted normal.
    cases.append(
        Case.of("normalized_phong", 0.5, normal=TILTED, **_params("normalized_phong", 100.0, True))
    )
    cases.append(
        Case.of("torrance_sparrow", 0.05, normal=TILTED, **_params("torrance_sparrow", 1e3, False))
    )
    cases.append(
        Case.of("blinn_phong", 0.5, "uniform", normal=TILTED, **_params("blinn_phong", 10.0, True))
    )
    return cases


CHI2_CASES = _chi2_cases()
#: Number of χ² tests in this module, and the per-test level for a family-wise 1%.
K = len(CHI2_CASES)
ALPHA_1 = chi2.sidak_alpha(0.01, K)


def test_every_family_a_model_has_a_chi2_case():
    assert {c.model for c in CHI2_CASES} == set(FAMILY_A) - set(DIELECTRIC)
    assert len({c.id for c in CHI2_CASES}) == K


@pytest.mark.parametrize("case", CHI2_CASES, ids=lambda c: c.id)
def test_chi2_sample_matches_pdf(case):
    _, n, pole = case.geometry()
    result = chi2.chi2_test(
        case.sampler_fn,
        case.pdf_fn,
        pole=pole,
        normal=n,
        n_samples=1_000_000,
        seed=case.seed,
        alpha=ALPHA_1,
        label=case.id,
    )
    assert result.passed, result.summary()


# ------------------------------------------------------------------ ∫ pdf = valid mass


def _integral(case: Case) -> float:
    _, n, pole = case.geometry()
    value, error = chi2.integrate_sphere(case.pdf_fn, pole, normal=n)
    assert error < 1e-8, (case.id, error)
    return value


LOSSLESS = [
    Case.of("lambert", 0.3, kd=0.5),
    Case.of("oren_nayar", 0.05, kd=0.5, sigma=1.0),
    Case.of("torrance_sparrow", 0.05, "cosine", kd=0.2, ks=1.0, p=100.0, eta=1.5),
    Case.of("normalized_phong", 0.5, "uniform", kd=0.2, ks=1.0, p=100.0),
    Case.of("blinn_phong", 0.5, "uniform", TILTED, kd=0.2, ks=1.0, p=100.0),
    *(Case.of("normalized_phong", 1.0, kd=0.0, ks=1.0, p=p) for p in EXPONENTS),
    Case.of("phong", 1.0, kd=0.5, ks=1.0, p=30.0),
    Case.of("modified_phong", 1.0, "auto", TILTED, kd=0.0, ks=1.0, p=1e3),
]


@pytest.mark.parametrize("case", LOSSLESS, ids=lambda c: c.id)
def test_pdf_integrates_to_one_when_no_draw_is_lost(case):
    assert abs(_integral(case) - 1.0) < 1e-9
    u = np.random.default_rng(case.seed).random((200_000, 2))
    wo, _, pdf = case.draw(u)
    _, n, _ = case.geometry()
    assert (pdf > 0).all() and (wo @ n > 0).all()


@pytest.mark.parametrize("p", EXPONENTS)
def test_blinn_lobe_at_normal_incidence_keeps_the_half_vectors_within_45_degrees(p):
    case = Case.of("torrance_sparrow", 1.0, kd=0.0, ks=1.0, p=p, eta=1.5)
    assert abs(_integral(case) - (1.0 - 2.0 ** (-(p + 2.0) / 2.0))) < 1e-9


@pytest.mark.parametrize("mu", [0.05, 0.5, 0.95])
def test_phong_lobe_with_p_1_keeps_the_sky_view_factor(mu):
    case = Case.of("modified_phong", mu, kd=0.0, ks=1.0, p=1.0)
    assert abs(_integral(case) - 0.5 * (1.0 + mu)) < 1e-9


LOSSY = [
    Case.of("normalized_phong", 0.05, kd=0.0, ks=1.0, p=10.0),
    Case.of("normalized_phong", 0.5, kd=0.0, ks=1.0, p=1.0),
    Case.of("phong", 0.05, kd=0.3, ks=1.0, p=100.0),
    Case.of("torrance_sparrow", 0.05, kd=0.0, ks=1.0, p=1e4, eta=1.5),
    Case.of("normalized_blinn_phong", 0.5, kd=0.2, ks=1.0, p=1.0),
    Case.of("blinn_phong_fresnel", 0.95, kd=0.0, ks=0.5, p=10.0),
    Case.of("torrance_sparrow", 0.05, normal=TILTED, kd=0.0, ks=1.0, p=1e3, eta=1.5),
    # Beckmann's visible normals: every h faces wi, but wo = reflect(wi, h) can still
    # fall below the horizon.
    Case.of("beckmann", 0.05, kd=0.0, ks=1.0, alpha=0.5),
    Case.of("beckmann", 0.5, kd=0.0, ks=1.0, alpha=1.0),
    Case.of("beckmann", 0.95, kd=0.2, ks=1.0, alpha=0.3),
]


@pytest.mark.parametrize("case", LOSSY, ids=lambda c: c.id)
def test_pdf_integrates_to_the_fraction_of_valid_draws(case):
    integral = _integral(case)
    n = 1_000_000
    u = np.random.default_rng(case.seed).random((n, 2))
    _, _, pdf = case.draw(u)
    fraction = float(np.mean(pdf > 0))
    sigma = math.sqrt(integral * (1.0 - integral) / n)
    assert 0.0 < integral < 1.0
    assert abs(integral - fraction) <= 5.0 * sigma + 1e-9, (integral, fraction, sigma)


# ------------------------------------------------------------------- weight, albedo

WEIGHT_CASES = [
    Case.of(model, mu, normal=normal, **_params(model, p, mixture))
    for model in FAMILY_A
    if model not in DIELECTRIC
    for mu, p, mixture, normal in [
        (0.05, 10.0, True, (0.0, 0.0, 1.0)),
        (0.5, 1e3, False, (0.0, 0.0, 1.0)),
        (0.8, 100.0, True, TILTED),
        (0.95, 1e4, True, (0.0, 0.0, 1.0)),
    ]
] + [
    Case.of("torrance_sparrow", 0.3, "cosine", **_params("torrance_sparrow", 50.0, True)),
    Case.of(
        "normalized_blinn_phong", 0.3, "uniform", **_params("normalized_blinn_phong", 50.0, True)
    ),
]


@pytest.mark.parametrize("case", WEIGHT_CASES, ids=lambda c: c.id)
def test_weight_is_f_cos_over_pdf(case):
    wi, n, _ = case.geometry()
    u = np.random.default_rng(case.seed).random((4096, 2))
    wo, weight, pdf = case.draw(u)
    np.testing.assert_allclose(np.linalg.norm(wo, axis=-1), 1.0, rtol=0, atol=1e-15)
    valid = pdf > 0.0
    mu_o = wo @ n
    assert np.array_equal(valid, mu_o > 0.0)
    assert (weight[~valid] == 0.0).all()
    f = brdf_rs.eval(case.model, wi, wo[valid], n, **case.kwargs)
    want = f * mu_o[valid, None] / pdf[valid, None]
    # The test's mu_o (from the returned wo and the normalized n) and the sampler's differ
    # by a relative ε/mu_o: visible at grazing draws (a uniform sampler makes many).
    rtol = 1e-12 + 4.0 * np.finfo(float).eps / mu_o[valid, None]
    assert (np.abs(weight[valid] - want) <= rtol * np.abs(want)).all()
    again = brdf_rs.pdf(case.model, wi, wo, n, sampler=case.sampler, **case.kwargs)
    np.testing.assert_allclose(again, pdf, rtol=1e-12, atol=0)


ALBEDO_CASES = [
    Case.of("lambert", 0.3, **_params("lambert", 0, False)),
    Case.of("oren_nayar", 0.05, **_params("oren_nayar", 0, False)),
    Case.of("phong", 0.05, **_params("phong", 100.0, True)),
    Case.of("modified_phong", 0.5, **_params("modified_phong", 1.0, True)),
    Case.of("normalized_phong", 0.95, **_params("normalized_phong", 1e4, True)),
    Case.of("blinn_phong", 0.5, **_params("blinn_phong", 10.0, True)),
    Case.of("modified_blinn_phong", 0.05, **_params("modified_blinn_phong", 1e3, True)),
    Case.of("normalized_blinn_phong", 0.95, **_params("normalized_blinn_phong", 100.0, False)),
    Case.of("blinn_phong_fresnel", 0.05, **_params("blinn_phong_fresnel", 1.0, True)),
    Case.of("torrance_sparrow", 0.05, **_params("torrance_sparrow", 1e4, True)),
    Case.of("torrance_sparrow", 0.5, **_params("torrance_sparrow", 30.0, False)),
    Case.of("torrance_sparrow", 0.5, "cosine", **_params("torrance_sparrow", 10.0, True)),
    Case.of("phong", 0.5, "uniform", **_params("phong", 10.0, True)),
]


@pytest.mark.parametrize("case", ALBEDO_CASES, ids=lambda c: c.id)
def test_mean_weight_is_the_albedo(case):
    n = 1 << 18
    u = np.random.default_rng(case.seed).random((n, 2))
    _, weight, _ = case.draw(u)
    mean = weight.mean(axis=0)
    stderr = weight.std(axis=0, ddof=1) / math.sqrt(n)
    ref = brdf_rs.albedo(
        case.model, case.mu, samples=1 << 16, seed=7, sampler=case.sampler, **case.kwargs
    )
    bound = 5.0 * np.sqrt(stderr**2 + ref.stderr**2) + 1e-9 * np.abs(ref.value)
    assert (np.abs(mean - ref.value) <= bound).all(), (mean, stderr, ref)


# --------------------------------------------------------------- determinism, errors


def test_same_u_gives_the_same_bits():
    case = Case.of("torrance_sparrow", 0.4, **_params("torrance_sparrow", 200.0, True))
    u = np.random.default_rng(5).random((50_000, 2))
    first = case.draw(u)
    second = case.draw(u.copy())
    # Element by element: the result does not depend on the batch around it.
    part = case.draw(u[12_345:12_400])
    single = case.draw(u[777])
    for a, b, c, d in zip(first, second, part, single, strict=True):
        assert np.array_equal(a, b)
        assert np.array_equal(a[12_345:12_400], c)
        assert np.array_equal(a[777], d)


@pytest.mark.parametrize("model", FAMILY_B)
def test_family_b_models_cannot_be_sampled(model):
    with pytest.raises(ValueError, match="family-A"):
        brdf_rs.sample(model, [0, 0, 1], [0.5, 0.5])
    with pytest.raises(ValueError, match="family-A"):
        brdf_rs.pdf(model, [0, 0, 1], [0, 0, 1])


@pytest.mark.parametrize("shape", [(3,), (10, 3), (10, 1), (4, 10, 3)])
def test_u_must_have_two_components(shape):
    with pytest.raises(ValueError, match=r"u: expected an array of shape \(\.\.\., 2\)"):
        brdf_rs.sample("lambert", [0, 0, 1], np.full(shape, 0.5))


def test_sidak_level():
    assert ALPHA_1 == pytest.approx(1.0 - 0.99 ** (1.0 / K), rel=1e-12)
    assert 1.0 - (1.0 - ALPHA_1) ** K == pytest.approx(0.01, rel=1e-12)
