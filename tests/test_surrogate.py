"""The force surrogate on a synthetic study whose force law is known in closed form."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from corneasim.errors import InputError
from corneasim.surrogate import build_surrogate, load, synthetic
from corneasim.surrogate._fit import fit_gaussian_process

EVALUATOR = Path(__file__).resolve().parents[1] / "src" / "corneasim" / "surrogate" / "_evaluate.py"
NEW_INPUTS = [(1.5, 0.17), (2.7, 0.21), (4.2, 0.235), (3.3, 0.19)]
"""Inputs inside the training ranges, not training cases (mm/s, mm)."""


@pytest.fixture(scope="module")
def model(tmp_path_factory):
    study = synthetic.write_study(tmp_path_factory.mktemp("study"), count=14, samples=300)
    return build_surrogate(study, hold_out=0.15)


def test_recovers_the_law_within_its_band(model):
    depth = np.linspace(0.0, synthetic.DEPTH, 401)
    inside, errors = [], []
    for rate, diameter in NEW_INPUTS:
        truth = synthetic.needle_force(depth, rate, diameter)
        mean, lower, upper = model.force(depth, rate=rate, diameter=diameter)
        inside.append((truth >= lower) & (truth <= upper))
        errors.append(np.sqrt(np.mean((mean - truth) ** 2)) / truth.max())
        expected = synthetic.punctures(rate, diameter)
        for event, (centre, low, high) in model.punctures(rate=rate, diameter=diameter).items():
            assert abs(centre - expected[event]) < 0.003
            assert low <= expected[event] <= high
    assert np.mean(inside) >= 0.90  # the band is calibrated to hold 95% of left-out samples
    assert max(errors) < 0.05


def test_metadata_describes_inputs_and_scores(model):
    meta = model.metadata
    assert [i["name"] for i in meta["inputs"]] == [synthetic.RATE, synthetic.DIAMETER]
    assert [i["unit"] for i in meta["inputs"]] == ["mm/s", "mm"]
    rates = [i for i in meta["inputs"] if i["alias"] == "rate"][0]
    assert synthetic.RANGES[synthetic.RATE][0] <= rates["low"] < rates["high"] <= synthetic.RANGES[synthetic.RATE][1]
    assert len(meta["training_cases"]) + len(meta["held_out_cases"]) == 14
    assert meta["events"] == ["epithelium", "stroma", "cornea"]
    assert meta["held_out"]["channels"]["force_N"]["coverage"] >= 0.9


def test_gaussian_process_arrays_match_scikit_learn():
    from sklearn.gaussian_process import GaussianProcessRegressor
    from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

    rng = np.random.default_rng(3)
    U = rng.random((12, 2))
    y = np.sin(3 * U[:, 0]) + U[:, 1] ** 2 + 0.01 * rng.standard_normal(12)
    inverse, weights, covariance, prior, mean, noise, _ = fit_gaussian_process(U, y)
    # the same kernel, fixed, in scikit-learn: its posterior mean and standard deviation
    scale = y.std()
    amplitude = (prior - noise) / scale**2
    kernel = (ConstantKernel(amplitude, "fixed") * RBF(1 / inverse, "fixed")
              + WhiteKernel(noise / scale**2, "fixed"))
    gp = GaussianProcessRegressor(kernel, optimizer=None, normalize_y=True).fit(U, y)
    u = rng.random((5, 2))
    expected, std = gp.predict(u, return_std=True)
    k = np.exp(-0.5 * np.sum(((u[:, None, :] - U[None]) * inverse) ** 2, axis=2))   # (5, N)
    np.testing.assert_allclose(mean + k @ weights, expected, rtol=1e-7, atol=1e-9)
    variance = prior - np.einsum("in,np,ip->i", k, covariance, k)
    np.testing.assert_allclose(np.sqrt(variance), std, rtol=1e-5)


def test_save_and_load_give_identical_predictions(model, tmp_path):
    path = tmp_path / "model.npz"
    model.save(path)
    again = load(path)
    depth = np.linspace(0.0, 1.0, 57)
    for got, expected in zip(again.force(depth, rate=2.2, diameter=0.2), model.force(depth, rate=2.2, diameter=0.2)):
        assert np.array_equal(got, expected)
    assert again.punctures(rate=2.2, diameter=0.2) == model.punctures(rate=2.2, diameter=0.2)
    assert again.metadata == json.loads(json.dumps(model.metadata))


def test_evaluator_runs_without_corneasim(model, tmp_path):
    path = tmp_path / "model.npz"
    model.save(path)
    script = (f"import sys, importlib.util\nsys.modules['corneasim'] = None\n"
              f"spec = importlib.util.spec_from_file_location('evaluate', {str(EVALUATOR)!r})\n"
              "module = importlib.util.module_from_spec(spec); spec.loader.exec_module(module)\n"
              f"mean, lower, upper = module.load({str(path)!r}).force(0.45, rate=3.0, diameter=0.2)\n"
              "print(repr(float(mean)), repr(float(upper)))\n"
              "assert 'corneasim.solver' not in sys.modules and 'sklearn' not in sys.modules\n")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True).stdout.split()
    mean, _, upper = model.force(0.45, rate=3.0, diameter=0.2)
    assert [float(v) for v in out] == [float(mean), float(upper)]


def test_out_of_range_inputs_are_refused_in_one_line(model):
    with pytest.raises(InputError, match=r"instrument\.motion\.insertion\.rate = 7 mm/s is outside the training range"):
        model.force(0.3, rate=7.0, diameter=0.2)
    with pytest.raises(InputError, match="missing"):
        model.force(0.3, rate=3.0)
    with pytest.raises(InputError, match="unknown input 'speed'"):
        model.force(0.3, speed=3.0, diameter=0.2)
    with pytest.raises(InputError, match="depth_mm outside the trained range"):
        model.force(1.5, rate=3.0, diameter=0.2)
    mean, lower, upper = model.force(0.3, extrapolate=True, rate=7.0, diameter=0.2)
    assert np.isfinite(mean) and lower <= mean <= upper


def test_full_dotted_keys_and_aliases_agree(model):
    by_alias = model.force(0.5, rate=2.0, diameter=0.2)
    by_key = model.force(0.5, **{synthetic.RATE: 2.0, synthetic.DIAMETER: 0.2})
    assert by_alias == by_key


def test_one_depth_and_many_depths_agree(model):
    events = [v[0] for v in model.punctures(rate=2.5, diameter=0.22).values()]
    depths = np.concatenate(([0.0, 1.0], events, np.linspace(0.0, 1.0, 37)))
    many = np.array(model.force(depths, rate=2.5, diameter=0.22))
    one = np.array([model.force(d, rate=2.5, diameter=0.22) for d in depths]).T
    np.testing.assert_allclose(one, many, rtol=1e-12, atol=1e-14)
