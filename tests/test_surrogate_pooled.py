"""A surrogate of several studies of the same scenario and inputs: a first design and the cases
added later, pooled; studies that do not match are refused in one line."""

import numpy as np
import pytest

from cli_helpers import corneasim_here

from corneasim.errors import InputError
from corneasim.surrogate import build_surrogate, synthetic


@pytest.fixture(scope="module")
def studies(tmp_path_factory):
    root = tmp_path_factory.mktemp("studies")
    return (synthetic.write_study(root / "first", count=8, samples=200, seed=0),
            synthetic.write_study(root / "added", count=6, samples=200, seed=5))


def test_pooled_studies_train_on_every_case_under_its_folder_name(studies):
    first, added = studies
    model = build_surrogate([first, added], hold_out=0.0)
    names = sorted(model.metadata["training_cases"])
    assert names == sorted([f"first/c{n:04d}" for n in range(8)] + [f"added/c{n:04d}" for n in range(6)])
    assert model.metadata["study"] == "first, added"
    one = build_surrogate(first, hold_out=0.0)
    assert sorted(one.metadata["training_cases"]) == [f"c{n:04d}" for n in range(8)]
    for rate, diameter in ((1.5, 0.17), (4.2, 0.235)):
        truth = synthetic.punctures(rate, diameter)["epithelium"]
        assert abs(model.punctures(rate=rate, diameter=diameter)["epithelium"][0] - truth) < 0.003


def test_a_study_of_other_overrides_is_refused(studies, tmp_path):
    first, _ = studies
    other = synthetic.write_study(tmp_path / "other", count=4, samples=50, seed=1)
    spec = other / "study.toml"
    spec.write_text(spec.read_text().replace('"mesh.preset" = "coarse"', '"mesh.preset" = "default"'))
    with pytest.raises(InputError, match=r"other: its study's overrides .* differ from .*first's"):
        build_surrogate([first, other])


def test_the_command_line_pools_the_folders_it_is_given(studies, tmp_path):
    first, added = studies
    result = corneasim_here("surrogate", "build", str(first), str(added), "--out", str(tmp_path / "m.npz"),
                            "--hold-out", "0.2")
    assert result.returncode == 0, result.stderr
    assert "trained on 11 cases of study 'first, added', 3 held out" in result.stdout
    assert np.load(tmp_path / "m.npz")["train_inputs"].shape == (11, 2)


def test_named_cases_are_held_out_instead_of_a_random_fraction(studies):
    first, added = studies
    model = build_surrogate([first, added], held_out_cases=["added/c0002", "first/c0005"])
    assert model.metadata["held_out_cases"] == ["first/c0005", "added/c0002"]  # in the pooled order
    assert len(model.metadata["training_cases"]) == 12 and model.metadata["held_out"]["cases"] == 2
    with pytest.raises(InputError, match="held_out_cases: no completed case 'c0005' in"):
        build_surrogate([first, added], held_out_cases=["c0005"])
