"""Gaussian-sum model and fit against the papers' published fits (closed forms)."""

import numpy as np
import pytest

from corneasim.analysis import GaussianFit, fit_gaussian_sum, gaussian_sum
from corneasim.errors import InputError

# needle paper eq. 16 (x = depth in mm, F in N), sorted by centre
EQ16 = (np.array([0.22, 0.46, 0.40]), np.array([0.36, 0.61, 0.86]), np.array([0.17, 0.15, 0.20]))
# trephination paper eq. 14 (x = time in s, g in N), sorted by centre
EQ14 = (np.array([0.06, 0.10]), np.array([33.86, 62.36]), np.array([18.63, 22.04]))


def test_gaussian_sum_closed_form():
    x = np.array([0.36, 0.5])
    expected = 0.22 * np.exp(-(((x - 0.36) / 0.17) ** 2)) + 0.46 * np.exp(-(((x - 0.61) / 0.15) ** 2))
    np.testing.assert_allclose(gaussian_sum(x, [0.22, 0.46], [0.36, 0.61], [0.17, 0.15]), expected, rtol=1e-15)
    assert gaussian_sum(np.zeros((2, 3)), *EQ16).shape == (2, 3)


def test_recovers_eq14_from_samples_on_its_domain():
    x = np.linspace(0.0, 70.0, 141)
    fit = fit_gaussian_sum(x, gaussian_sum(x, *EQ14), 2)
    for fitted, published in zip((fit.a, fit.b, fit.c), EQ14):
        np.testing.assert_allclose(fitted, published, rtol=1e-6)
    assert fit.rmse < 1e-10


def test_recovers_eq16_when_all_terms_are_sampled():
    # eq. 16's third centre (0.86 mm) lies outside its range [0, 0.7] mm; sampled up to
    # 1.2 mm (beyond b + 1.5 c of every term) the coefficients are identifiable.
    x = np.linspace(0.0, 1.2, 121)
    fit = fit_gaussian_sum(x, gaussian_sum(x, *EQ16), 3)
    for fitted, published in zip((fit.a, fit.b, fit.c), EQ16):
        np.testing.assert_allclose(fitted, published, rtol=1e-6)


def test_eq16_on_its_own_range_is_reproduced_but_not_identifiable():
    # on [0, 0.7] mm alone another coefficient set reproduces eq. 16 to ~1e-5 N (docs/data.md),
    # so only the curve is checked here; shuffled samples must not matter.
    x = np.random.default_rng(0).permutation(np.linspace(0.0, 0.7, 71))
    y = gaussian_sum(x, *EQ16)
    fit = fit_gaussian_sum(x, y, 3)
    assert fit.rmse < 2e-5
    dense = np.linspace(0.0, 0.7, 701)
    assert np.max(np.abs(fit(dense) - gaussian_sum(dense, *EQ16))) < 1e-4
    np.testing.assert_allclose(fit.b[:2], EQ16[1][:2], atol=0.01)


def test_noisy_fit_is_close_and_widths_positive():
    rng = np.random.default_rng(1)
    x = np.linspace(0.0, 70.0, 400)
    y = gaussian_sum(x, *EQ14) + rng.normal(0.0, 0.002, x.size)
    fit = fit_gaussian_sum(x, y, 2)
    assert isinstance(fit, GaussianFit) and fit.n_terms == 2
    assert np.all(fit.c > 0) and np.all(np.diff(fit.b) >= 0)
    assert 0.0015 < fit.rmse < 0.0025  # the noise level
    np.testing.assert_allclose(fit(x), gaussian_sum(x, *EQ14), atol=0.003)


def test_initial_guess_is_used():
    x = np.linspace(0.0, 70.0, 50)
    fit = fit_gaussian_sum(x, gaussian_sum(x, *EQ14), 2, initial=EQ14, n_starts=2)
    np.testing.assert_allclose(fit.b, EQ14[1], rtol=1e-8)


@pytest.mark.parametrize(
    "x, y, n_terms, fragment",
    [
        ([0, 1, 2], [0, 1], 1, "3 samples but y has 2"),
        ([0, 1], [0, 1], 1, "expected at least 3"),
        ([0, 1, np.nan], [0, 1, 2], 1, "finite"),
        ([1, 1, 1], [0, 1, 2], 1, "no spread"),
        ([0, 1, 2], [0, 1, 2], 0, "n_terms"),
    ],
)
def test_bad_input(x, y, n_terms, fragment):
    with pytest.raises(InputError, match=fragment):
        fit_gaussian_sum(x, y, n_terms)


def test_a_long_noisy_history_gives_the_coefficients_and_the_noise_level():
    # a force history with thousands of samples and noise: the coefficients are eq. 16's and
    # the RMSE is the noise level (the fit uses Kaufman's variable-projection Jacobian)
    x = np.linspace(0.0, 1.2, 3001)
    noise = 1e-4 * np.random.default_rng(1).standard_normal(x.size)
    fit = fit_gaussian_sum(x, gaussian_sum(x, *EQ16) + noise, 3)
    for fitted, published in zip((fit.a, fit.b, fit.c), EQ16):
        np.testing.assert_allclose(fitted, published, rtol=2e-3)
    expected_rmse = np.sqrt(np.mean((fit(x) - gaussian_sum(x, *EQ16) - noise) ** 2))
    assert fit.rmse == pytest.approx(expected_rmse, rel=1e-12)
    assert 0.9e-4 < fit.rmse < 1.1e-4


def test_kaufman_jacobian_is_the_exact_jacobian_at_a_zero_residual():
    # the term Kaufman's approximation drops is proportional to the residual: where the sum
    # fits exactly, the Jacobian must equal central finite differences of the residual
    from corneasim.analysis._gaussian import _projected_jacobian, _projected_residual

    x = np.linspace(0.0, 1.2, 121)
    y = gaussian_sum(x, *EQ16)
    p = np.concatenate([EQ16[1], EQ16[2]])
    bounds = (-10.0, 10.0)
    analytic = _projected_jacobian(p, x, y, 3, bounds)
    step = 1e-6
    numeric = np.column_stack([
        (_projected_residual(p + step * e, x, y, 3, bounds) - _projected_residual(p - step * e, x, y, 3, bounds))
        / (2 * step) for e in np.eye(6)])
    np.testing.assert_allclose(analytic, numeric, atol=1e-7 * np.abs(numeric).max())


def test_min_width_keeps_terms_wider_than_a_table_spacing():
    """A smooth rise with one sharp drop: free widths spend a term on the drop (narrower than a
    0.05 mm table spacing); with min_width = 0.05 every term is at least that wide."""
    x = np.linspace(0.0, 0.7, 3501)
    y = 0.6 * (x / 0.7) ** 2
    y[(x > 0.401) & (x < 0.405)] -= 0.1  # a 4 um force drop, as at a deletion
    free = fit_gaussian_sum(x, y, 3, nonnegative=True)
    wide = fit_gaussian_sum(x, y, 3, nonnegative=True, min_width=0.05)
    assert free.c.min() < 0.05
    assert wide.c.min() >= 0.05 - 1e-12
    # the wide fit follows the smooth trend: within 0.01 N of it away from the drop
    away = np.abs(x - 0.403) > 0.05
    assert np.max(np.abs(wide(x)[away] - 0.6 * (x[away] / 0.7) ** 2)) < 0.01


def test_min_width_beyond_the_data_range_is_capped():
    """Samples over 0.002 mm with a 0.05 mm floor (a run stopped early; the floor is above the
    widest allowed term, 10 x the range): the widths are capped at the range and the fit still
    follows the samples."""
    x = np.linspace(0.0, 0.002, 50)
    y = 0.1 + 2.0 * x
    fit = fit_gaussian_sum(x, y, 3, nonnegative=True, min_width=0.05)
    assert fit.c.min() >= 0.002 - 1e-12
    assert fit.rmse < 1e-4
