"""Chi-square goodness of fit of sample() against pdf(), driven from Python.

The sphere is cut into cells of equal solid angle (uniform in sinθ = w.x and in φ), the
pdf is integrated over each cell by a 4 × 4 Gauss–Legendre rule, cells expected to hold
fewer than 5 samples are pooled, and Pearson's statistic is compared with the chi-square
quantile at a family-wise significance of 1 % (Bonferroni over the cases). scipy is not
needed: the quantile is Wilson–Hilferty's approximation with the normal quantile found by
bisection on math.erfc. Negative controls (the pdf of another offset, a pdf scaled by 1.03)
must be rejected.
"""

import math
import zlib

import numpy as np
import pytest

import hairscatter as hs

N_THETA, N_PHI, ORDER = 40, 80, 4
FAMILY_ALPHA = 0.01


def normal_quantile(p):
    """x with Φ(x) = p, by bisection on Φ(x) = erfc(-x/√2)/2 (accurate to ~1e-12)."""
    lo, hi = -40.0, 40.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if 0.5 * math.erfc(-mid / math.sqrt(2)) < p:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def chi2_quantile(p, k):
    """Wilson–Hilferty: (χ²_k / k)^(1/3) is nearly normal with mean 1 - 2/(9k), variance 2/(9k)."""
    v = 2.0 / (9.0 * k)
    return k * (1.0 - v + normal_quantile(p) * math.sqrt(v)) ** 3


def test_the_quantile_matches_tabulated_values():
    assert normal_quantile(0.975) == pytest.approx(1.959963985, abs=1e-8)
    # χ²_{0.99}(100) = 135.807, χ²_{0.999}(1000) = 1143.917 (tables).
    assert chi2_quantile(0.99, 100) == pytest.approx(135.807, rel=1e-3)
    assert chi2_quantile(0.999, 1000) == pytest.approx(1143.917, rel=1e-4)


def cell_probabilities(pdf_of):
    """∫ pdf over each cell (N_THETA × N_PHI), by the tensor Gauss–Legendre rule."""
    x, w = np.polynomial.legendre.leggauss(ORDER)
    dx, dphi = 2.0 / N_THETA, 2 * math.pi / N_PHI
    s = -1 + dx * (np.arange(N_THETA)[:, None] + (x[None, :] + 1) / 2)  # sinθ nodes (N_THETA, ORDER)
    p = -math.pi + dphi * (np.arange(N_PHI)[:, None] + (x[None, :] + 1) / 2)
    S = s[:, None, :, None] * np.ones((1, N_PHI, 1, ORDER))
    P = p[None, :, None, :] * np.ones((N_THETA, 1, ORDER, 1))
    c = np.sqrt(np.maximum(0.0, 1 - S * S))
    wi = np.stack([S, c * np.cos(P), c * np.sin(P)], axis=-1).reshape(-1, 3)
    weights = (w[:, None] * w[None, :]).ravel() * (dx / 2) * (dphi / 2)
    values = np.asarray(pdf_of(wi), dtype=float).reshape(N_THETA, N_PHI, ORDER * ORDER)
    return (values * weights).sum(axis=-1)


def cells_of(wi):
    wi = np.asarray(wi, dtype=float)
    wi = wi / np.linalg.norm(wi, axis=1, keepdims=True)
    i = np.clip(((wi[:, 0] + 1) / 2 * N_THETA).astype(int), 0, N_THETA - 1)
    j = np.clip(((np.arctan2(wi[:, 2], wi[:, 1]) + math.pi) / (2 * math.pi) * N_PHI).astype(int), 0, N_PHI - 1)
    return np.bincount(i * N_PHI + j, minlength=N_THETA * N_PHI).reshape(N_THETA, N_PHI)


def chi2_statistic(observed, expected):
    """Pearson's statistic with cells of expected count < 5 pooled; returns (χ², degrees of freedom).

    As tests/support/chi2.hpp does: a pool still expecting fewer than 5 joins the kept cell
    with the smallest expectation (one legitimate tail sample in a pool expecting 0.005
    would otherwise read as a failure), and samples where the pdf integrates to 0 fail."""
    o, e = observed.ravel().astype(float), expected.ravel()
    small = e < 5
    o_kept, e_kept = o[~small].copy(), e[~small].copy()
    pool_o, pool_e = o[small].sum(), e[small].sum()
    if pool_o > 0 and pool_e <= 0:
        return math.inf, max(1, len(e_kept) - 1)
    if pool_e > 0:
        if pool_e >= 5 or len(e_kept) == 0:
            o_kept, e_kept = np.append(o_kept, pool_o), np.append(e_kept, pool_e)
        else:
            k = int(np.argmin(e_kept))
            o_kept[k] += pool_o
            e_kept[k] += pool_e
    return float(((o_kept - e_kept) ** 2 / e_kept).sum()), len(e_kept) - 1


def run_chi2(sample_wi, pdf_of, n):
    """(χ², threshold, total probability) of n samples against pdf_of."""
    wi = sample_wi()
    ok = np.all(np.isfinite(wi), axis=1) & np.any(wi != 0, axis=1)
    assert ok.mean() > 0.999, "too many failed samples"
    prob = cell_probabilities(pdf_of)
    stat, dof = chi2_statistic(cells_of(wi[ok]), prob * ok.sum())
    return stat, chi2_quantile(1 - FAMILY_ALPHA / len(CASES), dof), prob.sum()


def chiang(dt):
    return hs.Chiang(sigma_a=(0.25, 0.4, 0.9), beta_m=0.25, beta_n=0.3, dtype=dt)


WO = hs.direction(0.5, 0.3)
# name → (model, h, wo, samples)
CASES = {
    "chiang float32": (lambda: chiang(np.float32), 0.3, WO, 400_000),
    "chiang float64 grazing": (lambda: chiang(np.float64), -0.8, hs.direction(1.35, 2.0), 400_000),
    "chiang R+TRT float64": (lambda: hs.Chiang(lobes="R+TRT", beta_m=0.4), 0.1, WO, 300_000),
    "deon far field float32": (lambda: hs.DeonFarField(sigma_a=(0.1, 0.2, 0.3), dtype=np.float32), None, WO, 300_000),
    "tabulated float64": (lambda: hs.Tabulated(preset="coarse", beta_n=0.5), None, WO, 300_000),
    "marschner float64": (lambda: hs.Marschner(sigma_a=(0.2, 0.3, 0.6)), None, WO, 300_000),
    "huang float32": (
        lambda: hs.Huang(aspect_ratio=0.7, offset_nodes=16, tt_points=16, dtype=np.float32),
        None,
        WO,
        40_000,
    ),
}


@pytest.mark.parametrize("name", list(CASES))
def test_samples_follow_the_pdf(name):
    make, h, wo, n = CASES[name]
    model = make()
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    stat, threshold, total = run_chi2(
        lambda: model.sample(wo, rng.random((n, 4)), h).wi, lambda wi: model.pdf(wo, wi, h), n
    )
    assert total == pytest.approx(1.0, abs=2e-3), "the pdf does not integrate to 1"
    print(f"{name}: chi2 {stat:.1f}, threshold {threshold:.1f}")
    assert stat < threshold, f"{name}: chi2 {stat:.1f} above the threshold {threshold:.1f}"


def test_the_dual_bcsdf_samples_follow_its_pdf():
    m = hs.DeonFarField(sigma_a=(0.1, 0.15, 0.3))
    d = hs.DualScatteringBcsdf(m, m.dual_tables(theta_samples=32, psi_samples=17))
    rng = np.random.default_rng(5)
    n = 300_000
    stat, threshold, total = run_chi2(
        lambda: d.sample(WO, rng.random((n, 4)), spread=0.2).wi, lambda wi: d.pdf(WO, wi, spread=0.2), n
    )
    assert total == pytest.approx(1.0, abs=2e-3)
    assert stat < threshold


@pytest.mark.parametrize("control", ["another offset", "a 5 % rougher pdf"])
def test_a_wrong_pdf_is_rejected(control):
    model = chiang(np.float64)
    rng = np.random.default_rng(11)
    n = 400_000
    if control == "another offset":
        pdf_of = lambda wi: model.pdf(WO, wi, 0.4)  # noqa: E731 (samples drawn at h = 0.3)
    else:
        # The same albedo and lobes, only the longitudinal width off: a shape error that the
        # total probability cannot show.
        rougher = hs.Chiang(sigma_a=(0.25, 0.4, 0.9), beta_m=0.25 * 1.05, beta_n=0.3)
        pdf_of = lambda wi: rougher.pdf(WO, wi, 0.3)  # noqa: E731
    stat, threshold, _ = run_chi2(lambda: model.sample(WO, rng.random((n, 4)), 0.3).wi, pdf_of, n)
    print(f"{control}: chi2 {stat:.1f}, threshold {threshold:.1f}")
    assert stat > threshold, f"{control}: chi2 {stat:.1f} not above {threshold:.1f}"
